#include "renderer/frame/frame_units.hpp"

#include <cmath>
#include <glm/geometric.hpp>

#include "scene/tet_mesh.hpp"

namespace prismoid::frame {

FrameUnits frame_units(const Bounds& bounds) {
  FrameUnits u;
  u.origin = bounds.center();
  if (!std::isfinite(u.origin.x) || !std::isfinite(u.origin.y) || !std::isfinite(u.origin.z)) u.origin = glm::dvec3(0.0);
  const double radius = 0.5 * glm::length(bounds.max - bounds.min);
  // Finite and positive in double (a point cloud of one point has none; a radius beyond double
  // is refused by the float limits long before this matters).
  if (radius > 0.0 && std::isfinite(radius)) {
    int exponent = 0;
    std::frexp(radius, &exponent);  // radius = m * 2^exponent with m in [0.5, 1)
    u.unit = std::ldexp(1.0, exponent);
  }
  return u;
}

TetMesh in_units(const TetMesh& mesh, const FrameUnits& units) {
  TetMesh local = mesh;
  for (glm::dvec3& p : local.points) p = units.point(p);
  for (double& s : local.cell_extinction) s *= units.unit;
  for (double& s : local.point_extinction) s *= units.unit;
  return local;
}

Camera in_units(const Camera& camera, const FrameUnits& units) {
  Camera local = camera;
  local.eye = units.point(camera.eye);
  // The direction as it is in world units (the target's own rounding could turn it).
  local.target = local.eye + (camera.target - camera.eye) / units.unit;
  local.near_distance = units.length(camera.near_distance);
  return local;
}

std::shared_ptr<const std::vector<float>> limit_in_units(const std::vector<float>& world, const FrameUnits& units) {
  auto local = std::make_shared<std::vector<float>>(world.size());
  const double scale = 1.0 / units.unit;
  for (size_t i = 0; i < world.size(); ++i) (*local)[i] = float(double(world[i]) * scale);
  return local;
}

volume::ResolveSettings in_units(const volume::ResolveSettings& settings, const FrameUnits& units,
                                 std::shared_ptr<const std::vector<float>> scaled_limit) {
  volume::ResolveSettings local = settings;
  local.transfer.density_scale = settings.transfer.density_scale * units.unit;
  volume::MarchSettings& m = local.march;
  m.step = settings.march.step / units.unit;
  m.density_scale = settings.march.density_scale * units.unit;
  // The field stays in its own coordinates; the GPU's point q is the field's point
  // field_offset + field_scale * q.
  m.field_offset = settings.march.field_offset + settings.march.field_scale * units.origin;
  m.field_scale = settings.march.field_scale * units.unit;
  local.depth_limit = settings.depth_limit ? std::move(scaled_limit) : nullptr;
  return local;
}

}  // namespace prismoid::frame
