#pragma once
// The units the GPU draws a volume in. float32 has the same relative precision at every
// magnitude but a bounded range: the interval stages multiply lengths up to four times (areas
// of projected faces, plane equations, depths squared), which overflows float for cells of
// 1e10 and underflows it for cells of 1e-12. The renderer therefore hands the GPU the scene
// relative to the data's centre and in units of a power of two near the data's radius: every
// length divided by it, every extinction (1 / length) multiplied by it. A power of two scales
// floats exactly, so a scene and its copy scaled by any power of two give the GPU identical
// numbers, and every other scale differs only by rounding; optical depths, colours and
// images are unchanged (they are dimensionless). The CPU references keep world units.
#include <memory>
#include <vector>

#include <glm/vec3.hpp>

#include "renderer/volume/resolve_settings.hpp"
#include "scene/bounds.hpp"
#include "scene/camera.hpp"
#include "scene/tet_mesh_fwd.hpp"

namespace prismoid::frame {

struct FrameUnits {
  glm::dvec3 origin{0.0};  // world position of the GPU's 0: the data's bounds centre
  double unit = 1.0;       // world length of the GPU's 1: a power of two (1 for empty or flat data)

  glm::dvec3 point(const glm::dvec3& world) const { return (world - origin) / unit; }
  double length(double world) const { return world / unit; }
};

// The units for data with these bounds: the power of two nearest above half their diagonal.
FrameUnits frame_units(const Bounds& bounds);

// The mesh in these units: points moved and scaled, extinction scaled, scalars as they are.
TetMesh in_units(const TetMesh& mesh, const FrameUnits& units);
// The camera in these units: the same view (direction, field of view) of the moved data.
Camera in_units(const Camera& camera, const FrameUnits& units);
// The settings in these units: the march step, the extinction per unit of field or opacity,
// the field's placement and the depth limit. `scaled_limit` is the depth limit already scaled
// (the caller keeps it across frames; the per-pixel scaling is done once per limit).
volume::ResolveSettings in_units(const volume::ResolveSettings& settings, const FrameUnits& units,
                                 std::shared_ptr<const std::vector<float>> scaled_limit);
// A depth limit (depths along the viewing axis, +inf where nothing is) in these units.
std::shared_ptr<const std::vector<float>> limit_in_units(const std::vector<float>& world, const FrameUnits& units);

}  // namespace prismoid::frame
