#pragma once
// The CPU double-precision reference of a mixed frame (mixed_frame.hpp): what the GPU frame is
// measured against (`render --mode reference`, `--reference-error`) and tested against. The
// surfaces by the direct-light reference of the forward mode (renderer/reference/direct_light.hpp,
// with or without shadows as the GPU shaded them), each pixel's first hit giving the depth along
// the viewing axis where the volume's ray ends; the volume by the tetrahedral integrators up to
// that depth (frame::render_reference with ResolveSettings::depth_limit); the composite by the
// same rule as the GPU frame's (composite_over_surfaces).
#include <vector>

#include <vulkan/vulkan.h>

#include "renderer/mixed/mixed_frame.hpp"
#include "renderer/reference/direct_light.hpp"

namespace prismoid::mixed {

// Per pixel the depth along the viewing axis of the reference's first hit (t times the ray
// direction's component along the axis), +inf where the ray meets nothing.
std::vector<float> first_hit_depth(const reference::DirectLightImage& image, const Camera& camera);

// The whole mixed frame on the CPU: surfaces (linear RGBA, alpha = hit), their depth, the volume's
// frame ending there, the composite, and the CPU time of each part as `passes`. InputError as
// MixedRenderer::render for settings that follow no depth limit or bring their own.
MixedFrame render_mixed_reference(const TetMesh& volume, const SurfaceScene& surfaces, const Camera& camera,
                                  const volume::ResolveSettings& resolve, VkExtent2D size, bool shadows);

}  // namespace prismoid::mixed
