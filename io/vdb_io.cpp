#include "io/vdb_io.hpp"

#include <algorithm>
#include <atomic>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <limits>
#include <map>
#include <mutex>
#include <sstream>
#include <unordered_map>

#include <glm/common.hpp>
#include <openvdb/openvdb.h>
#include <openvdb/io/File.h>
#include <openvdb/io/Stream.h>
#include <openvdb/tools/LevelSetUtil.h>
#include <openvdb/tools/MeshToVolume.h>
#include <openvdb/tools/VolumeToMesh.h>

#include "io/file_write.hpp"
#include "io/isolated_read.hpp"
#include "io/kuhn_split.hpp"
#include "io/path_util.hpp"
#include "io/voxel_tets.hpp"
#include "io/surface_io.hpp"
#include "scene/input_error.hpp"

namespace prismoid::io {

namespace {

using openvdb::Coord;
using openvdb::FloatGrid;

void initialize_openvdb() {
  static std::once_flag once;
  std::call_once(once, [] { openvdb::initialize(); });
}

// Every grid of the file, fully read, in the file's order. OpenVDB trusts the lengths it reads:
// past the end of a truncated file its reads fail silently and it goes on with garbage sizes (an
// 800 MB string, for one). A stream that throws on the first failed read stops it there.
// Delayed loading stays off: it would read voxels on first touch, after we checked the file.
openvdb::GridPtrVec read_grids(const std::string& path) {
  detail::require_regular_file(path);
  if (!is_vdb_path(path)) throw InputError(path, "is not a .vdb file");
  initialize_openvdb();
  try {
    std::ifstream in(path, std::ios::binary);
    if (!in) throw InputError(path, "cannot open the file for reading");
    in.exceptions(std::ios::failbit | std::ios::badbit);
    openvdb::io::Stream stream(in, /*delayLoad=*/false);
    openvdb::GridPtrVecPtr grids = stream.getGrids();
    if (!grids || grids->empty()) throw InputError(path, "is not a readable VDB file (truncated?): it holds no grids");
    return *grids;
  } catch (const InputError&) {
    throw;
  } catch (const std::bad_alloc&) {
    throw InputError(path, "is not a readable VDB file (corrupt: a size in it is impossibly large)");
  } catch (const std::ios_base::failure&) {
    throw InputError(path, "is not a readable VDB file (truncated or corrupt: it ends where OpenVDB expects more)");
  } catch (const std::exception& e) {  // openvdb::Exception and the standard library's, from corrupt or truncated files
    throw InputError(path, std::string("is not a readable VDB file (truncated or corrupt?): ") + e.what());
  }
}

// A number as people write it: 3 significant digits, exponent where needed (1e-09, 0.00205).
std::string short_number(double v) {
  std::ostringstream s;
  s.precision(3);
  s << v;
  return s.str();
}

std::string grid_label(const openvdb::GridBase& grid) {
  return (grid.getName().empty() ? std::string("(unnamed)") : "'" + grid.getName() + "'") + " (" + grid.valueType() + ")";
}

std::string grid_list(const openvdb::GridPtrVec& grids) {
  std::string text;
  for (const auto& g : grids) text += (text.empty() ? "" : ", ") + grid_label(*g);
  return text;
}

VdbClass class_of(const openvdb::GridBase& grid) {
  switch (grid.getGridClass()) {
    case openvdb::GRID_LEVEL_SET: return VdbClass::LevelSet;
    case openvdb::GRID_FOG_VOLUME: return VdbClass::FogVolume;
    default: return VdbClass::Unknown;
  }
}

FloatGrid::Ptr choose_float_grid(const std::string& path, const openvdb::GridPtrVec& grids, const std::string& name) {
  for (const auto& g : grids) {
    if (!name.empty() && g->getName() != name) continue;
    if (auto f = openvdb::gridPtrCast<FloatGrid>(g)) return f;
    if (!name.empty()) throw InputError(path, "grid " + grid_label(*g) + " is not a float grid; only float grids open as volumes (grids: " + grid_list(grids) + ")");
  }
  if (name.empty()) throw InputError(path, "has no float grid to open as a volume (grids: " + grid_list(grids) + ")");
  throw InputError(path, "has no grid '" + name + "' (grids: " + grid_list(grids) + ")");
}

void check_grid(const std::string& path, const FloatGrid& grid) {
  if (!grid.transform().isLinear())
    throw InputError(path, "grid " + grid_label(grid) + " has a non-linear (" + grid.transform().mapType() +
                               ") transform; only affine voxel grids are supported");
  if (grid.activeVoxelCount() == 0) throw InputError(path, "grid " + grid_label(grid) + " is empty (no active voxels)");
  if (!std::isfinite(grid.background())) throw InputError(path, "grid " + grid_label(grid) + " has a non-finite background value");
  for (auto it = grid.cbeginValueAll(); it; ++it)
    if (!std::isfinite(*it)) {
      const Coord c = it.getCoord();
      throw InputError(path, "grid " + grid_label(grid) + " holds a non-finite value at voxel (" + std::to_string(c.x()) + ", " +
                                 std::to_string(c.y()) + ", " + std::to_string(c.z()) + ")");
    }
}

int64_t floor_div(int64_t a, int64_t k) { return a >= 0 ? a / k : -((-a + k - 1) / k); }
int64_t ceil_div(int64_t a, int64_t k) { return -floor_div(-a, k); }
Coord scaled(const Coord& c, int k) { return Coord(c.x() * k, c.y() * k, c.z() * k); }
Coord corner_of(const Coord& cell, uint32_t corner) { return cell.offsetBy(int(corner & 1), int((corner >> 1) & 1), int(corner >> 2)); }

// Calls visit(coord) for every active voxel, active tiles voxel by voxel.
template <typename Visit>
void for_each_active_voxel(const FloatGrid& grid, Visit&& visit) {
  for (auto it = grid.cbeginValueOn(); it; ++it) {
    if (it.isVoxelValue()) visit(it.getCoord());
    else {
      const openvdb::CoordBBox box = it.getBoundingBox();
      for (auto c = box.begin(); c; ++c) visit(*c);
    }
  }
}

// The coarse dual cells (keyed by their lowest corner, in units of `subsample` voxels) that hold
// an active voxel: a voxel on a coarse lattice plane lies in the cells on both sides of it.
openvdb::MaskGrid::Ptr dual_cells(const FloatGrid& shape, uint32_t subsample, const Progress& progress, const std::string& source) {
  auto cells = openvdb::MaskGrid::create(false);
  auto acc = cells->getAccessor();
  const int64_t k = subsample;
  const double total = double(shape.activeVoxelCount());
  uint64_t seen = 0;
  for_each_active_voxel(shape, [&](const Coord& v) {
    if ((++seen & 0xFFFF) == 0) report(progress, 0.3 * double(seen) / total, "finding the voxel cells", source);
    int lo[3], hi[3];
    for (int a = 0; a < 3; ++a) {
      hi[a] = int(floor_div(v[a], k));
      lo[a] = (int64_t(v[a]) % k == 0) ? hi[a] - 1 : hi[a];
    }
    for (int z = lo[2]; z <= hi[2]; ++z)
      for (int y = lo[1]; y <= hi[1]; ++y)
        for (int x = lo[0]; x <= hi[0]; ++x) acc.setValueOn(Coord(x, y, z));
  });
  return cells;
}

std::string subsample_advice(uint64_t tets, uint64_t max_cells, uint32_t subsample) {
  // The count falls about as the cube of the subsample: an estimate, which the reader rechecks.
  const double factor = std::cbrt(double(tets) / double(max_cells));
  const auto k = uint64_t(std::ceil(double(subsample) * factor * 1.05));
  return "try --subsample " + std::to_string(std::max<uint64_t>(k, subsample + 1)) + " (keeps 1 voxel in K per axis)";
}


}  // namespace

bool is_vdb_path(const std::string& path) { return detail::lower_extension(path) == ".vdb"; }

const char* vdb_class_name(VdbClass c) {
  switch (c) {
    case VdbClass::FogVolume: return "fog volume";
    case VdbClass::LevelSet: return "level set";
    default: return "unknown";
  }
}

namespace {

VdbInfo inspect_vdb_here(const std::string& path) {
  const openvdb::GridPtrVec grids = read_grids(path);
  VdbInfo info;
  info.path = path;
  std::error_code ec;
  info.file_bytes = std::filesystem::file_size(path, ec);
  for (const auto& g : grids) {
    VdbGridInfo gi;
    gi.name = g->getName();
    gi.value_type = g->valueType();
    gi.grid_class = class_of(*g);
    const openvdb::Vec3d vs = g->voxelSize();
    gi.voxel_size = {vs[0], vs[1], vs[2]};
    gi.linear_transform = g->transform().isLinear();
    gi.active_voxels = g->activeVoxelCount();
    gi.leaf_nodes = g->baseTree().leafCount();
    gi.memory_bytes = g->memUsage();
    if (gi.active_voxels > 0) {
      const openvdb::CoordBBox box = g->evalActiveVoxelBoundingBox();
      gi.index_min = {box.min().x(), box.min().y(), box.min().z()};
      gi.index_max = {box.max().x(), box.max().y(), box.max().z()};
      bool first = true;
      for (int corner = 0; corner < 8; ++corner) {
        const Coord c((corner & 1) ? box.max().x() : box.min().x(), (corner & 2) ? box.max().y() : box.min().y(),
                      (corner & 4) ? box.max().z() : box.min().z());
        const openvdb::Vec3d w = g->indexToWorld(c);
        const glm::dvec3 p(w[0], w[1], w[2]);
        gi.world.min = first ? p : glm::min(gi.world.min, p);
        gi.world.max = first ? p : glm::max(gi.world.max, p);
        first = false;
      }
    }
    if (auto f = openvdb::gridPtrCast<FloatGrid>(g); f && gi.active_voxels > 0) {
      gi.has_range = true;
      gi.value_min = std::numeric_limits<double>::infinity();
      gi.value_max = -gi.value_min;
      for (auto it = f->cbeginValueOn(); it; ++it) {
        gi.value_min = std::min(gi.value_min, double(*it));
        gi.value_max = std::max(gi.value_max, double(*it));
      }
      if (gi.linear_transform) {
        FloatGrid::Ptr shape = f;
        if (gi.grid_class == VdbClass::LevelSet) {
          shape = f->deepCopy();
          openvdb::tools::sdfToFogVolume(*shape);
        }
        const auto cells = dual_cells(*shape, 1, {}, path);
        gi.dual_cells = cells->activeVoxelCount();
        openvdb::MaskGrid corners(false);
        auto acc = corners.getAccessor();
        for (auto it = cells->cbeginValueOn(); it; ++it)
          for (uint32_t c = 0; c < 8; ++c) acc.setValueOn(corner_of(it.getCoord(), c));
        gi.mesh_points = corners.activeVoxelCount();
      }
    }
    info.grids.push_back(gi);
  }
  return info;
}

}  // namespace

namespace {

TetMesh read_vdb_voxels_here(const std::string& path, const VdbReadOptions& options) {
  if (options.subsample == 0) throw InputError(path, "subsample must be at least 1");
  const openvdb::GridPtrVec grids = read_grids(path);
  const FloatGrid::Ptr grid = choose_float_grid(path, grids, options.grid);
  check_grid(path, *grid);
  const VdbClass grid_class = class_of(*grid);
  const std::string label = "grid " + grid_label(*grid);

  // A level set's extinction is its fog volume; that volume's active voxels (the inside, tiles
  // included) decide the cells, so the solid interior is filled and not only the narrow band.
  FloatGrid::Ptr shape = grid;
  if (grid_class == VdbClass::LevelSet) {
    shape = grid->deepCopy();
    openvdb::tools::sdfToFogVolume(*shape);
    if (shape->activeVoxelCount() == 0) throw InputError(path, label + " is a level set with no inside (no negative distance)");
  }

  const uint32_t k = options.subsample;
  // Each coarse cell's closed box holds at most (k + 1)^3 voxels: a lower bound on the cell count
  // refuses absurd grids before any cell is built.
  const uint64_t least_tets = 6 * (shape->activeVoxelCount() / (uint64_t(k + 1) * (k + 1) * (k + 1)));
  if (least_tets > options.max_cells)
    throw InputError(path, label + " has " + std::to_string(shape->activeVoxelCount()) + " active voxels, which make over " +
                               std::to_string(least_tets) + " tetrahedra, more than the limit of " + std::to_string(options.max_cells) +
                               "; " + subsample_advice(least_tets, options.max_cells, k));
  const auto cells = dual_cells(*shape, k, options.progress, path);
  const uint64_t tet_count = 6 * cells->activeVoxelCount();
  if (tet_count > options.max_cells)
    throw InputError(path, label + " makes " + std::to_string(tet_count) + " tetrahedra" +
                               (k > 1 ? " (keeping 1 voxel in " + std::to_string(k) + " per axis)" : std::string()) +
                               ", more than the limit of " + std::to_string(options.max_cells) + "; " +
                               subsample_advice(tet_count, options.max_cells, k));

  // Points: the corners of the kept cells, numbered in the tree's (deterministic) order.
  auto point_ids = openvdb::Int64Grid::create(-1);
  {
    auto acc = point_ids->getAccessor();
    for (auto it = cells->cbeginValueOn(); it; ++it)
      for (uint32_t c = 0; c < 8; ++c) acc.setValueOn(corner_of(it.getCoord(), c), 0);
  }
  const uint64_t point_count = point_ids->activeVoxelCount();
  if (point_count > std::numeric_limits<uint32_t>::max())
    throw InputError(path, label + " makes more points than 32-bit indices address; " + subsample_advice(tet_count, tet_count / 8, k));

  TetMesh mesh;
  mesh.name = path;
  mesh.points.reserve(point_count);
  mesh.point_scalars.reserve(point_count);
  std::vector<double> density;
  density.reserve(point_count);
  {
    const openvdb::math::Transform& xform = grid->transform();
    auto values = grid->getConstAccessor();
    auto shape_values = shape->getConstAccessor();
    int64_t next = 0;
    for (auto it = point_ids->beginValueOn(); it; ++it) {
      if ((next & 0xFFFF) == 0) report(options.progress, 0.3 + 0.2 * double(next) / double(point_count), "placing voxel points", path);
      const Coord fine = scaled(it.getCoord(), int(k));
      const openvdb::Vec3d w = xform.indexToWorld(fine);
      mesh.points.emplace_back(w[0], w[1], w[2]);
      mesh.point_scalars.push_back(double(values.getValue(fine)));
      density.push_back(double(shape_values.getValue(fine)));
      it.setValue(next++);
    }
  }

  mesh.tets.reserve(tet_count);
  {
    auto ids = point_ids->getConstAccessor();
    bool flip = false, orientation_known = false;
    uint64_t done = 0;
    const double total = double(cells->activeVoxelCount());
    for (auto it = cells->cbeginValueOn(); it; ++it) {
      if ((++done & 0xFFFF) == 0) report(options.progress, 0.5 + 0.5 * double(done) / total, "splitting voxel cells into tetrahedra", path);
      uint32_t corner[8];
      for (uint32_t c = 0; c < 8; ++c) corner[c] = uint32_t(ids.getValue(corner_of(it.getCoord(), c)));
      if (!orientation_known) {  // the transform is affine: one cell tells its handedness for all
        const auto& t = kKuhnTets[0];
        flip = signed_volume(mesh.points[corner[t[0]]], mesh.points[corner[t[1]]], mesh.points[corner[t[2]]], mesh.points[corner[t[3]]]) < 0.0;
        orientation_known = true;
      }
      for (const auto& t : kKuhnTets)
        mesh.tets.push_back(flip ? std::array<uint32_t, 4>{corner[t[0]], corner[t[1]], corner[t[3]], corner[t[2]]}
                                 : std::array<uint32_t, 4>{corner[t[0]], corner[t[1]], corner[t[2]], corner[t[3]]});
    }
  }
  report(options.progress, 1.0, "splitting voxel cells into tetrahedra", path);

  if (options.role == ArrayRole::Extinction) {
    if (const double lowest = *std::min_element(density.begin(), density.end()); lowest < 0.0)
      throw InputError(path, label + " holds negative values (down to " + std::to_string(lowest) +
                                 "), which cannot be densities; mark it a level set, or map it with --quantity color --tf");
    detail::set_point_extinction(mesh, density, options.density_scale);
  } else {
    mesh.cell_extinction.assign(mesh.tets.size(), options.density_scale);
  }
  validate(mesh);
  return mesh;
}

}  // namespace

namespace {

VdbDense read_vdb_dense_here(const std::string& path, const VdbReadOptions& options, uint64_t max_voxels) {
  if (options.subsample == 0) throw InputError(path, "subsample must be at least 1");
  const openvdb::GridPtrVec grids = read_grids(path);
  const FloatGrid::Ptr grid = choose_float_grid(path, grids, options.grid);
  check_grid(path, *grid);
  const std::string label = "grid " + grid_label(*grid);
  const openvdb::Mat4d m = grid->transform().baseMap()->getAffineMap()->getMat4();
  for (int r = 0; r < 3; ++r)
    for (int c = 0; c < 3; ++c)
      if (r != c && m(r, c) != 0.0) throw InputError(path, label + " is rotated or sheared; dense sampling needs an axis-aligned grid");

  const int64_t k = options.subsample;
  const openvdb::CoordBBox box = grid->evalActiveVoxelBoundingBox();
  Coord lo, hi;  // coarse voxels covering the active box, rounded outward
  uint64_t count = 1;
  VdbDense dense;
  for (int a = 0; a < 3; ++a) {
    lo[a] = int(floor_div(box.min()[a], k));
    hi[a] = int(ceil_div(box.max()[a], k));
    dense.dims[a] = uint32_t(hi[a] - lo[a] + 1);
    count *= dense.dims[a];
  }
  if (count > max_voxels)
    throw InputError(path, label + " spans " + std::to_string(dense.dims.x) + " x " + std::to_string(dense.dims.y) + " x " +
                               std::to_string(dense.dims.z) + " voxels, more than the dense limit of " + std::to_string(max_voxels) +
                               "; try --subsample " + std::to_string(uint64_t(std::ceil(double(k) * std::cbrt(double(count) / double(max_voxels))))));

  const openvdb::math::Transform& xform = grid->transform();
  const openvdb::Vec3d origin = xform.indexToWorld(scaled(lo, int(k)));
  dense.origin = {origin[0], origin[1], origin[2]};
  for (int a = 0; a < 3; ++a) {
    Coord step(0, 0, 0);
    step[a] = int(k);
    dense.spacing[a] = xform.indexToWorld(scaled(lo, int(k)) + step)[a] - origin[a];
  }
  dense.grid_class = class_of(*grid);
  dense.background = grid->background();
  dense.values.resize(count);
  auto acc = grid->getConstAccessor();
  size_t i = 0;
  for (uint32_t z = 0; z < dense.dims.z; ++z) {
    report(options.progress, double(z) / double(dense.dims.z), "sampling the grid densely", path);
    for (uint32_t y = 0; y < dense.dims.y; ++y)
      for (uint32_t x = 0; x < dense.dims.x; ++x)
        dense.values[i++] = acc.getValue(Coord(int((lo.x() + int64_t(x)) * k), int((lo.y() + int64_t(y)) * k), int((lo.z() + int64_t(z)) * k)));
  }
  auto add_box = [&](const openvdb::CoordBBox& b) {
    VdbBox out;
    for (int a = 0; a < 3; ++a) {
      const int64_t first = floor_div(b.min()[a], k), last = ceil_div(b.max()[a], k);
      out.min[a] = int(first - lo[a]);
      out.size[a] = int(last - first + 1);
    }
    dense.active_boxes.push_back(out);
  };
  for (auto leaf = grid->tree().cbeginLeaf(); leaf; ++leaf)
    if (leaf->onVoxelCount() > 0) add_box(leaf->getNodeBoundingBox());
  for (auto it = grid->cbeginValueOn(); it; ++it)
    if (!it.isVoxelValue()) add_box(it.getBoundingBox());
  report(options.progress, 1.0, "sampling the grid densely", path);
  return dense;
}

}  // namespace

// OpenVDB's reading runs in a child process (io/isolated_read.hpp): it trusts the sizes it
// reads, so a corrupt file can make it allocate without end.
template <typename S, Carries<VdbGridInfo> M>
void fields(S& s, M& g) {
  s(g.name);
  s(g.value_type);
  s(g.grid_class);
  s(g.voxel_size);
  s(g.linear_transform);
  s(g.active_voxels);
  s(g.index_min);
  s(g.index_max);
  s(g.world);
  s(g.has_range);
  s(g.value_min);
  s(g.value_max);
  s(g.leaf_nodes);
  s(g.memory_bytes);
  s(g.dual_cells);
  s(g.mesh_points);
}
template <typename S, Carries<VdbInfo> M>
void fields(S& s, M& info) {
  s(info.path);
  s(info.file_bytes);
  s(info.grids);
}
template <typename S, Carries<VdbDense> M>
void fields(S& s, M& d) {
  s(d.dims);
  s(d.origin);
  s(d.spacing);
  s(d.values);
  s(d.active_boxes);
  s(d.grid_class);
  s(d.background);
}

namespace {

// What the reader child needs: the path and the options (their progress is the child's own).
struct VdbRequest {
  std::string path;
  VdbReadOptions options;
  uint64_t max_voxels = 0;  // read_vdb_dense's
};
template <typename S, Carries<VdbRequest> M>
void fields(S& s, M& r) {
  s(r.path);
  s(r.options.grid);
  s(r.options.role);
  s(r.options.density_scale);
  s(r.options.subsample);
  s(r.options.max_cells);
  s(r.max_voxels);
}

const ChildWork<std::string, VdbInfo> kInspectVdb("inspect-vdb", [](const std::string& path, const Progress&) { return inspect_vdb_here(path); });
const ChildWork<VdbRequest, TetMesh> kReadVdbVoxels("read-vdb-voxels", [](const VdbRequest& request, const Progress& progress) {
  VdbReadOptions reading = request.options;
  reading.progress = progress;
  return read_vdb_voxels_here(request.path, reading);
});
const ChildWork<VdbRequest, VdbDense> kReadVdbDense("read-vdb-dense", [](const VdbRequest& request, const Progress& progress) {
  VdbReadOptions reading = request.options;
  reading.progress = progress;
  return read_vdb_dense_here(request.path, reading, request.max_voxels);
});

}  // namespace

VdbInfo inspect_vdb(const std::string& path) {
  detail::require_regular_file(path);
  return kInspectVdb(read_job(path), {}, path);
}

TetMesh read_vdb_voxels(const std::string& path, const VdbReadOptions& options) {
  detail::require_regular_file(path);
  return kReadVdbVoxels(read_job(path), options.progress, {path, options, 0});
}

VdbDense read_vdb_dense(const std::string& path, const VdbReadOptions& options, uint64_t max_voxels) {
  detail::require_regular_file(path);
  return kReadVdbDense(read_job(path), options.progress, {path, options, max_voxels});
}

namespace {

// OpenVDB's interrupter, polled from its worker threads, onto our single-threaded Progress.
class ProgressInterrupter : public openvdb::util::NullInterrupter {
 public:
  ProgressInterrupter(const Progress& progress, std::string stage) : progress_(progress), stage_(std::move(stage)) {}
  bool wasInterrupted(int percent = -1) override {
    if (!progress_) return false;
    const std::lock_guard<std::mutex> lock(mutex_);
    if (!cancelled_ && !progress_(percent >= 0 ? percent / 100.0 : -1.0, stage_)) cancelled_ = true;
    return cancelled_;
  }
  bool cancelled() const { return cancelled_; }

 private:
  const Progress& progress_;
  std::string stage_;
  std::mutex mutex_;
  std::atomic<bool> cancelled_{false};
};

}  // namespace

namespace {

// A closed surface as a narrow-band level set of voxel size `voxel_size` (<= 0: the bounding
// box's diagonal / 128), refusing open surfaces and sizes over max_voxels.
FloatGrid::Ptr surface_level_set(const SurfaceMesh& surface, double voxel_size, uint64_t max_voxels, const Progress& progress) {
  if (surface.triangles.empty()) throw InputError(surface.name, "the surface has no triangles");
  if (const SurfaceCheck check = check_surface(surface); !check.closed())
    throw InputError(surface.name, "the surface is not closed (" + std::to_string(check.boundary_edges) + " boundary edges, " +
                                       std::to_string(check.nonmanifold_edges) + " non-manifold edges), so it has no inside; --fill-holes closes holes");
  Bounds b{surface.points.front(), surface.points.front()};
  for (const auto& p : surface.points) {
    b.min = glm::min(b.min, p);
    b.max = glm::max(b.max, p);
  }
  const double diagonal = 2.0 * b.radius();
  if (!(diagonal > 0.0) || !std::isfinite(diagonal)) throw InputError(surface.name, "the surface has no extent (or non-finite points)");
  const double h = voxel_size > 0.0 ? voxel_size : diagonal / 128.0;
  // Below two voxels across the box's thinnest side, the grid may hold no voxel centre inside
  // the shape at all: an empty fog volume, or a level set with no inside.
  const double thinnest = std::min({b.max.x - b.min.x, b.max.y - b.min.y, b.max.z - b.min.z});
  if (h > 0.5 * thinnest)
    throw InputError(surface.name, "a voxel size of " + short_number(h) + " is over half the bounding box's thinnest side (" +
                                       short_number(thinnest) + "), too coarse for the grid to hold the inside; use at most " +
                                       short_number(0.5 * thinnest));
  constexpr float kHalfWidth = 3.0f;  // voxels each side of the surface: OpenVDB's default band
  double voxels = 1.0, padded_volume = 1.0;
  for (int a = 0; a < 3; ++a) {
    const double n = std::ceil((b.max[a] - b.min[a]) / h) + 2.0 * double(kHalfWidth) + 1.0;
    voxels *= n;
    padded_volume *= n * h;  // finite where the count is not: the size to suggest comes from it
  }
  if (!(voxels <= double(max_voxels))) {
    const double suggested = std::cbrt(padded_volume / double(max_voxels)) * 1.05;
    throw InputError(surface.name, "a voxel size of " + short_number(h) + " makes about " + short_number(voxels) +
                                       " voxels in the bounding box, more than " + std::to_string(max_voxels) +
                                       (std::isfinite(suggested) ? "; try a voxel size of " + short_number(suggested) : std::string()));
  }

  initialize_openvdb();
  std::vector<openvdb::Vec3s> points;
  points.reserve(surface.points.size());
  for (const auto& p : surface.points) points.emplace_back(float(p.x), float(p.y), float(p.z));
  std::vector<openvdb::Vec3I> triangles;
  triangles.reserve(surface.triangles.size());
  for (const auto& t : surface.triangles) triangles.emplace_back(t[0], t[1], t[2]);
  const openvdb::math::Transform::Ptr xform = openvdb::math::Transform::createLinearTransform(h);
  ProgressInterrupter interrupter(progress, "converting the surface to a level set");
  // Through its base class: libopenvdb already holds meshToLevelSet for NullInterrupter (explicit
  // instantiation), so this file need not compile the whole conversion again (most of its build
  // time, issue 40). wasInterrupted is virtual, so the progress still reaches our override.
  openvdb::util::NullInterrupter& base = interrupter;
  FloatGrid::Ptr grid = openvdb::tools::meshToLevelSet<FloatGrid>(base, *xform, points, triangles, kHalfWidth);
  if (interrupter.cancelled()) throw Cancelled(surface.name);
  // The band reaches 3 voxels inward, so a shape with any voxel centre inside has an active
  // negative value; without one the fog would be empty and the level set all outside.
  bool inside = false;
  for (auto value = grid->cbeginValueOn(); value && !inside; ++value) inside = *value < 0.0f;
  if (!inside)
    throw InputError(surface.name, "no voxel centre lies inside the surface at voxel size " + short_number(h) +
                                       " (the shape is thinner than a voxel?); try a smaller voxel size");
  return grid;
}

}  // namespace

VdbWriteReport write_vdb_from_surface(const std::string& path, const SurfaceMesh& surface, const VdbWriteOptions& options) {
  if (!is_vdb_path(path)) throw InputError(path, "is not a .vdb file name");
  FloatGrid::Ptr grid = surface_level_set(surface, options.voxel_size, options.max_voxels, options.progress);
  const double h = grid->voxelSize()[0];
  if (options.fog) {
    report(options.progress, -1.0, "level set to fog volume", surface.name);
    openvdb::tools::sdfToFogVolume(*grid);
    grid->setGridClass(openvdb::GRID_FOG_VOLUME);
    grid->setName("density");
  } else {
    grid->setGridClass(openvdb::GRID_LEVEL_SET);
    grid->setName("surface");
  }
  VdbWriteReport result{h, grid->activeVoxelCount()};

  try {
    openvdb::io::File file(path);
    file.write({grid});
    file.close();
  } catch (const std::exception& e) {
    std::error_code ec;
    std::filesystem::remove(path, ec);
    throw InputError(path, std::string("cannot write the .vdb file: ") + e.what());
  }
  // OpenVDB's file writing does not notice a full disk: the file ends at whatever fitted. (Its
  // stream writing would, but writes no offsets, which other programs' readers need.) So the
  // file is synced, read back and its voxels counted.
  sync_file(path);
  bool whole = false;
  try {
    const openvdb::GridPtrVec back = read_grids(path);
    whole = back.size() == 1 && back.front()->activeVoxelCount() == result.active_voxels;
  } catch (const InputError&) {
  }
  if (!whole) {
    std::error_code ec;
    std::filesystem::remove(path, ec);
    throw InputError(path, "cannot be written: what reached the disk is incomplete (is the disk full?)");
  }
  return result;
}

SurfaceMesh remesh_through_level_set(const SurfaceMesh& surface, double voxel_size, const Progress& progress) {
  FloatGrid::Ptr grid = surface_level_set(surface, voxel_size, kMaxDenseVoxels, progress);
  report(progress, -1.0, "extracting the level set's zero crossing", surface.name);
  std::vector<openvdb::Vec3s> points;
  std::vector<openvdb::Vec3I> triangles;
  std::vector<openvdb::Vec4I> quads;
  openvdb::tools::volumeToMesh(*grid, points, triangles, quads, 0.0, 0.0);  // isovalue 0, no adaptivity
  SurfaceMesh out;
  out.name = surface.name;
  out.points.reserve(points.size());
  for (const auto& p : points) out.points.emplace_back(p.x(), p.y(), p.z());
  out.triangles.reserve(triangles.size() + 2 * quads.size());
  // OpenVDB winds its polygons the opposite way to the outward-facing convention: reversed here.
  for (const auto& t : triangles) out.triangles.push_back({t[0], t[2], t[1]});
  for (const auto& q : quads) {
    out.triangles.push_back({q[0], q[2], q[1]});
    out.triangles.push_back({q[0], q[3], q[2]});
  }
  if (out.triangles.empty()) throw InputError(surface.name, "the level set has no zero crossing at this voxel size");
  return out;
}

SurfaceMesh boundary_surface(const TetMesh& mesh) {
  // Each face keyed by its sorted corners; a face met twice is interior and cancels.
  struct Face {
    std::array<uint32_t, 3> corners;  // facing out of the cell that holds it
    int uses = 0;
  };
  std::map<std::array<uint32_t, 3>, Face> faces;
  for (const auto& t : mesh.tets) {
    const bool positive = signed_volume(mesh.points[t[0]], mesh.points[t[1]], mesh.points[t[2]], mesh.points[t[3]]) >= 0.0;
    // Outward faces of a positively oriented tetrahedron (a, b, c, d).
    const std::array<std::array<uint32_t, 3>, 4> outward = {{{t[0], t[2], t[1]}, {t[0], t[1], t[3]}, {t[0], t[3], t[2]}, {t[1], t[2], t[3]}}};
    for (auto f : outward) {
      if (!positive) std::swap(f[1], f[2]);
      auto key = f;
      std::sort(key.begin(), key.end());
      Face& face = faces[key];
      face.corners = f;
      ++face.uses;
    }
  }
  SurfaceMesh surface;
  surface.name = mesh.name;
  std::unordered_map<uint32_t, uint32_t> renumber;
  for (const auto& [key, face] : faces) {
    if (face.uses != 1) continue;
    std::array<uint32_t, 3> tri{};
    for (int i = 0; i < 3; ++i) {
      const auto [it, inserted] = renumber.try_emplace(face.corners[size_t(i)], uint32_t(surface.points.size()));
      if (inserted) surface.points.push_back(mesh.points[face.corners[size_t(i)]]);
      tri[size_t(i)] = it->second;
    }
    surface.triangles.push_back(tri);
  }
  return surface;
}

}  // namespace prismoid::io
