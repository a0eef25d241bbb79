#pragma once
// What float32 can represent for a volume frame, decided from the inputs before anything is
// drawn: the limits every volume backend shares (the GPU computes in float32, and every image
// Prismoid writes stores float32). A frame whose answer float cannot hold is refused
// (InputError naming the option or dataset, with the limit and why); one that float renders
// only approximately is rendered with a warning saying by how much.
#include <cstdint>
#include <string>
#include <vector>

#include <glm/vec3.hpp>

#include "renderer/volume/resolve_settings.hpp"
#include "scene/bounds.hpp"
#include "scene/camera.hpp"
#include "scene/tet_mesh_fwd.hpp"

namespace prismoid::volume {

// float32's largest finite value, and the margin kept below it for sums along a ray (up to
// PRISMOID_MARCH_MAX_STEPS = 2^12 march samples per interval and the blending of the
// intervals; 2^16 leaves room for both).
inline constexpr double kFloatMax = 3.4028234663852886e38;
inline constexpr double kSumMargin = 1.0 / 65536.0;

// What a mesh brings to the limits, measured once in double.
struct MeshFloatFacts {
  std::string name;
  Bounds bounds;
  glm::dvec3 origin{0.0};          // the bounds centre the GPU's float positions are relative to
  double diagonal = 0.0;           // of the bounds: no ray's path through the mesh is longer
  double max_extinction = 0.0;     // the largest cell or point extinction
  double position_rounding = 0.0;  // largest |float(p - origin) - (p - origin)| of a coordinate
  bool has_scalars = false;
  double scalar_abs_max = 0.0;     // largest |scalar| (the transfer function's input)
  // The world length of one unit of these facts (frame/frame_units.hpp: the GPU's mesh is
  // measured in units of the data's size); lengths in messages are given in world units.
  double unit = 1.0;
};
MeshFloatFacts float_facts(const TetMesh& mesh);

// The largest extinction the GPU stores for a mesh of this diagonal: kSumMargin * kFloatMax /
// diagonal, so an optical depth summed along any ray stays finite. Larger values are stored as
// this. Only transmittance and colour ever see the difference (optical depth itself is refused
// past it), and only on segments shorter than 104 / cap (e^-104 is 0 in float), which is
// 2e-32 of the diagonal: far below the float rounding of any interval's length.
double extinction_cap(double diagonal);

// How the GPU maps a scalar s to the transfer function's x: x = s * scale + offset, both
// computed in double from the range and rounded once, so a range far wider than the data or far
// from zero still maps into [0, 1] without overflow ((s - lo) / width with lo = -1e300 does not).
struct ScalarMapping {
  double scale = 1.0;
  double offset = 0.0;
};
ScalarMapping scalar_mapping(const TransferFunction& tf);

struct FloatCheck {
  std::vector<std::string> warnings;  // what the frame renders only approximately, and by how much
};

// Throws InputError when the frame's answer cannot be represented: optical depths beyond float
// (with the margin above), scalars or their mapping into the transfer function beyond float, a
// camera whose projection or depths leave float's range. Warns when the points' camera-space
// positions as the GPU computes them (float positions relative to the bounds centre, the float
// view matrix, the float transform) stray across the view by more than the rasterizer's own
// snapping (2^-8 pixel) at the nearest depth of the data: first bounded from the facts, and
// where the bound says they might, measured point by point on `points` (the mesh's, in double)
// when given. `gpu` false: the CPU reference, whose arithmetic is double but whose image is
// float32 (only the image's limits).
FloatCheck check_float_limits(const MeshFloatFacts& mesh, const Camera& camera, uint32_t width, uint32_t height,
                              const ResolveSettings& settings, bool gpu = true,
                              const std::vector<glm::dvec3>* points = nullptr);

}  // namespace prismoid::volume
