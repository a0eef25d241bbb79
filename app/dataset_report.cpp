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
  if (!info.blocks.empty()) {
    s << "  blocks (render --blocks LIST picks them by index or name):\n";
    for (const std::string& b : info.blocks) s << "    " << b << "\n";
  }
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

std::string format_vdb_info(const io::VdbInfo& info) {
  std::ostringstream s;
  s.precision(9);
  s << info.path << " (OpenVDB, " << bytes_text(info.file_bytes) << ", " << info.grids.size() << " grid" << (info.grids.size() == 1 ? "" : "s") << ")\n";
  for (const io::VdbGridInfo& g : info.grids) {
    s << "  grid '" << g.name << "': " << g.value_type << ", " << io::vdb_class_name(g.grid_class) << "\n";
    s << "    voxel size: " << g.voxel_size.x << " x " << g.voxel_size.y << " x " << g.voxel_size.z
      << (g.linear_transform ? "" : " (non-linear transform: cannot be opened)") << "\n";
    s << "    active voxels: " << g.active_voxels << " in " << g.leaf_nodes << " leaf nodes (and tiles); in memory "
      << bytes_text(g.memory_bytes) << "\n";
    if (g.active_voxels == 0) continue;
    s << "    active index box: [" << g.index_min.x << ", " << g.index_max.x << "] x [" << g.index_min.y << ", " << g.index_max.y
      << "] x [" << g.index_min.z << ", " << g.index_max.z << "]\n";
    s << "    world bounds (voxel centres): [" << g.world.min.x << ", " << g.world.max.x << "] x [" << g.world.min.y << ", "
      << g.world.max.y << "] x [" << g.world.min.z << ", " << g.world.max.z << "]\n";
    if (g.has_range) s << "    values (active voxels): [" << g.value_min << ", " << g.value_max << "]\n";
    if (g.dual_cells > 0)
      s << "    as tetrahedra: " << g.tets() << " (6 per cell between 8 voxel centres, " << g.dual_cells << " cells), " << g.mesh_points
        << " points; GPU memory (mesh buffers): " << bytes_text(io::estimated_gpu_bytes(g.tets(), g.mesh_points)) << "\n";
  }
  return s.str();
}

}  // namespace prismoid::app
