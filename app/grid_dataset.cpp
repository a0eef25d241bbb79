#include "app/grid_dataset.hpp"

#include <mutex>

#include "app/cli_args.hpp"
#include "renderer/volume/region_mesh.hpp"
#include "scene/input_error.hpp"

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

TetMesh grid_dataset_mesh(const volume::SampledGrid& grid, double density_scale) {
  TetMesh mesh = volume::make_region_mesh(grid, volume::blocks_above(grid, 1e-3 * volume::max_abs_value(grid)), density_scale);
  if (mesh.tets.empty()) throw InputError(grid.name, "no sample is above a thousandth of the largest: nothing to draw");
  return mesh;
}

}  // namespace prismoid::app
