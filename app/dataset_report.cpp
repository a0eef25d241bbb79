#include "app/dataset_report.hpp"

#include <sstream>

namespace prismoid::app {

namespace {

std::string bytes_text(size_t bytes) {
  std::ostringstream s;
  s.precision(3);
  if (bytes < 1024) s << bytes << " B";
  else if (bytes < size_t(1) << 20) s << double(bytes) / 1024.0 << " KiB";
  else if (bytes < size_t(1) << 30) s << double(bytes) / double(size_t(1) << 20) << " MiB";
  else s << double(bytes) / double(size_t(1) << 30) << " GiB";
  return s.str();
}

}  // namespace

std::string format_dataset_info(const std::string& path, const io::DatasetInfo& info) {
  std::ostringstream s;
  s.precision(9);
  size_t cells = 0;
  std::string by_type;
  for (const auto& [name, count] : info.cells_by_type) {
    cells += count;
    by_type += std::string(by_type.empty() ? "" : ", ") + std::to_string(count) + " " + name;
  }
  s << path << "\n";
  s << "  cells: " << cells << " (" << by_type << ")\n";
  s << "  points: " << info.points;
  if (info.conversion.pieces > 1)
    s << " (" << info.conversion.pieces << " pieces merged, " << info.conversion.merged_points << " shared points stored once)";
  s << "\n";
  s << "  bounds: [" << info.bounds.min.x << ", " << info.bounds.max.x << "] x [" << info.bounds.min.y << ", " << info.bounds.max.y
    << "] x [" << info.bounds.min.z << ", " << info.bounds.max.z << "]\n";
  for (const bool per_point : {true, false}) {
    s << (per_point ? "  point arrays:" : "  cell arrays:");
    bool any = false;
    for (const auto& a : info.arrays) {
      if (a.per_point != per_point) continue;
      any = true;
      s << "\n    " << a.name << ": [" << a.min << ", " << a.max << "]";
      if (a.components > 1) s << " (magnitude of " << a.components << " components)";
    }
    s << (any ? "\n" : " none\n");
  }
  const io::MeshConversion& c = info.conversion;
  s << "  as tetrahedra: " << c.tets_out << " tetrahedra, " << info.mesh_points << " points, volume " << info.volume << "\n";
  const std::string note = io::conversion_note(c);
  s << "  conversion: " << (note.empty() ? "none needed (all cells are sound tetrahedra)" : note) << "\n";
  s << "  zero-volume tetrahedra: " << c.zero_volume << " (kept; they contribute nothing)\n";
  s << "  inverted tetrahedra: " << c.inverted << " (negative orientation; rendering does not depend on it)\n";
  s << "  GPU memory (mesh buffers): " << bytes_text(io::estimated_gpu_bytes(c.tets_out, info.mesh_points)) << " ("
    << io::kGpuBytesPerTet << " B per tetrahedron + " << io::kGpuBytesPerPoint
    << " B per point; a point array adds 4 B per point per role)\n";
  return s.str();
}

}  // namespace prismoid::app
