#pragma once
// Marching inside intervals (Tricard 2024, section 3.2): what IntervalShadingPass does only
// when it marches an analytic field. Internal to renderer/volume.
#include <vulkan/vulkan.h>

#include "renderer/volume/volume_inputs.hpp"
#include "shaders/shared/volume.h"

namespace prismoid::volume {

// Throws InputError naming the option for march settings the pass cannot render: a
// non-positive step, one that needs more than PRISMOID_MARCH_MAX_STEPS in the longest cell,
// an isosurface without marching, a mesh without the scalar arrays the mesh shader reads.
void validate_march(const GpuTetMesh& mesh, const ResolveSettings& settings);

// The uniforms march.frag and isosurface.frag read beyond the interval pass's own; each
// sample's extinction is held to `extinction_cap` (volume::extinction_cap).
void fill_march_uniforms(gpu::FrameUniforms& frame, const ResolveSettings& settings, const Camera& camera,
                         const glm::dvec3& mesh_origin, double extinction_cap);

// Moves the depth target to attachment layout and describes it, cleared to 0 (no hit).
VkRenderingAttachmentInfo begin_isosurface_depth(VkCommandBuffer cmd, const VolumeTargets& targets);

}  // namespace prismoid::volume
