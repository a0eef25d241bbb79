#include "app/common/grid_dataset.hpp"

#include <algorithm>
#include <mutex>

#include "app/common/cli_args.hpp"
#include "renderer/volume/region_mesh.hpp"
#include "scene/input_error.hpp"
#include "scene/tet_mesh.hpp"

namespace prismoid::app {

bool is_grid_spec(const std::string& spec) { return spec.rfind("grid:", 0) == 0; }

std::shared_ptr<const volume::SampledGrid> grid_from_spec(const std::string& spec) {
  static std::mutex mutex;  // the viewer's loader thread calls this too
  const std::lock_guard lock(mutex);
  static std::string last_spec;
  static std::shared_ptr<const volume::SampledGrid> last;
  if (last && spec == last_spec) return last;
  const std::string rest = spec.substr(5);
  const auto colon = rest.find(':');
  volume::AnalyticField field;
  try {
    field = volume::field_from_name(rest.substr(0, colon));
  } catch (const InputError& e) {  // named as the user wrote it, not as field:NAME
    throw InputError(spec, std::string(e.what()).substr(e.source().size() + 2));
  }
  uint32_t n = 32;
  if (colon != std::string::npos) {
    n = parse_uint("grid", rest.substr(colon + 1));
    if (n < 2 || n > 512) throw InputError(spec, "N samples per axis must be between 2 and 512");
  }
  auto grid = std::make_shared<volume::SampledGrid>(volume::sample_onto_grid(field, glm::uvec3(n), glm::dvec3(-1.0), glm::dvec3(1.0)));
  grid->name = spec;
  last_spec = spec;
  last = std::move(grid);
  return last;
}

namespace {

// The last .vdb grid and its regions, so the field and the mesh of one command share them.
struct VdbGridCache {
  std::string key;
  std::shared_ptr<const volume::SampledGrid> grid;
  std::vector<volume::IndexBox> regions;
};
VdbGridCache& vdb_cache() {
  static VdbGridCache cache;
  return cache;
}

}  // namespace

std::shared_ptr<const volume::SampledGrid> grid_from_vdb(const std::string& path, const io::VdbReadOptions& options) {
  VdbGridCache& cache = vdb_cache();
  const std::string key = path + "\n" + options.grid + "\n" + std::to_string(options.subsample);
  if (cache.grid && cache.key == key) return cache.grid;
  io::VdbDense dense = io::read_vdb_dense(path, options);
  auto grid = std::make_shared<volume::SampledGrid>();
  grid->dims = dense.dims;
  grid->origin = dense.origin;
  grid->spacing = dense.spacing;
  grid->values = std::move(dense.values);
  grid->background = dense.background;
  grid->name = path;
  std::vector<volume::IndexBox> regions;
  if (dense.grid_class == io::VdbClass::LevelSet) {
    const double width = std::abs(double(dense.background));
    if (!(width > 0.0)) throw InputError(path, "level set with a zero background (narrow-band width): cannot tell inside from outside");
    for (float& v : grid->values) v = float(std::clamp(-double(v) / width, 0.0, 1.0));
    grid->background = 0.0;
    regions = volume::whole_grid(*grid);
  } else {
    for (const io::VdbBox& b : dense.active_boxes) regions.push_back({b.min, b.size});
  }
  volume::validate(*grid);
  cache = {key, std::move(grid), std::move(regions)};
  return cache.grid;
}

TetMesh grid_dataset_mesh(const volume::SampledGrid& grid, double density_scale) {
  const VdbGridCache& cache = vdb_cache();
  const bool from_vdb = cache.grid.get() == &grid;
  TetMesh mesh = volume::make_region_mesh(
      grid, from_vdb ? cache.regions : volume::blocks_above(grid, 1e-3 * volume::max_abs_value(grid)), density_scale);
  if (mesh.tets.empty()) throw InputError(grid.name, "no sample is above a thousandth of the largest: nothing to draw");
  return mesh;
}

}  // namespace prismoid::app
