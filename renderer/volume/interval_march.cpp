#include "renderer/volume/interval_march.hpp"

#include <cmath>
#include <optional>
#include <glm/matrix.hpp>
#include <string>

#include "renderer/vk/memory.hpp"
#include "scene/input_error.hpp"
#include "scene/setting_names.hpp"

namespace prismoid::volume {

void validate_march(const GpuTetMesh& mesh, const ResolveSettings& settings) {
  const MarchSettings& m = settings.march;
  if (!m.enabled) {
    if (settings.quantity == Quantity::Isosurface)
      throw InputError(setting("quantity", "isosurface"), "needs marching (a " + setting("mode") + " that marches) over an analytic field (field:NAME)");
    return;
  }
  validate(m.field);
  if (!(m.step > 0.0) || !std::isfinite(m.step)) throw InputError(setting("march-step"), "must be a positive number of world units");
  if (mesh.longest_edge / m.step > double(PRISMOID_MARCH_MAX_STEPS))
    throw InputError(setting("march-step"), "needs more than " + std::to_string(PRISMOID_MARCH_MAX_STEPS) +
                                         " steps in the longest cell (" + std::to_string(mesh.longest_edge) + "); use at least " +
                                         std::to_string(mesh.longest_edge / PRISMOID_MARCH_MAX_STEPS));
  if (!std::isfinite(m.isovalue)) throw InputError(setting("isovalue"), "must be a finite number");
  if (!(m.density_scale >= 0.0) || !std::isfinite(m.density_scale)) throw InputError(setting("density-scale"), "must not be negative");
  if (!mesh.has_scalars)
    throw InputError("the march", "the mesh must carry a scalar array (the field: datasets do)");
}

void fill_march_uniforms(gpu::FrameUniforms& frame, const ResolveSettings& settings, const Camera& camera,
                         const glm::dvec3& mesh_origin, double extinction_cap) {
  const MarchSettings& m = settings.march;
  frame.camera_to_mesh = glm::mat4(glm::inverse(view_matrix(camera, mesh_origin)));
  // The shader samples at mesh-local points (small: the mesh's size and the eye's distance
  // to it); a field moved into the mesh frame in double needs no world offset, one that
  // cannot be moved is placed in float by field_origin (precise only near the world origin).
  // A density scale beyond float is stored as its largest value: the shader holds each
  // sample's density_scale * field to the cap first (inf * 0 would be NaN).
  frame.march = glm::vec4(float(m.step), float(m.isovalue), float(std::min(m.density_scale, 3.4028234663852886e38)),
                          float(extinction_cap));
  const uint32_t what = settings.quantity == Quantity::Color        ? PRISMOID_MARCH_COLOR
                        : settings.quantity == Quantity::Isosurface ? PRISMOID_MARCH_ISOSURFACE
                                                                    : PRISMOID_MARCH_OPTICAL_DEPTH;
  // The field's point at mesh-local 0, and the field's length of one mesh-local unit.
  const glm::dvec3 base = m.field_offset + m.field_scale * mesh_origin;
  const double scale = m.field_scale;
  if (m.field.kind == FieldKind::Grid) {
    // The grid's samples are uploaded as they are; only its placement moves into the mesh frame.
    const SampledGrid& g = *m.field.grid;
    frame.field_origin = glm::vec4(0.0f, 0.0f, 0.0f, 1.0f);
    frame.field = glm::uvec4(PRISMOID_FIELD_GRID, 3u, what, 0u);
    frame.field_params[0] = glm::vec4(glm::vec3((g.origin - base) / scale), float(g.background));
    frame.field_params[1] = glm::vec4(glm::vec3(scale / g.spacing), 0.0f);
    frame.field_params[2] = glm::vec4(glm::vec3(g.dims), 0.0f);
    return;
  }
  const std::optional<AnalyticField> local = placed(m.field, base, scale);
  const AnalyticField& uploaded = local ? *local : m.field;
  frame.field_origin = local ? glm::vec4(0.0f, 0.0f, 0.0f, 1.0f) : glm::vec4(glm::vec3(base), float(scale));
  frame.field = glm::uvec4(uint32_t(uploaded.kind), uint32_t(uploaded.params.size()), what, 0u);
  for (size_t i = 0; i < uploaded.params.size() && i < PRISMOID_FIELD_MAX_PARAMS; ++i) frame.field_params[i] = glm::vec4(uploaded.params[i]);
}

VkRenderingAttachmentInfo begin_isosurface_depth(VkCommandBuffer cmd, const VolumeTargets& targets) {
  vk::image_barrier(cmd, targets.depth.get(), VK_IMAGE_LAYOUT_UNDEFINED, VK_IMAGE_LAYOUT_DEPTH_ATTACHMENT_OPTIMAL,
                    VK_PIPELINE_STAGE_2_EARLY_FRAGMENT_TESTS_BIT | VK_PIPELINE_STAGE_2_LATE_FRAGMENT_TESTS_BIT,
                    VK_ACCESS_2_DEPTH_STENCIL_ATTACHMENT_WRITE_BIT,
                    VK_PIPELINE_STAGE_2_EARLY_FRAGMENT_TESTS_BIT | VK_PIPELINE_STAGE_2_LATE_FRAGMENT_TESTS_BIT,
                    VK_ACCESS_2_DEPTH_STENCIL_ATTACHMENT_READ_BIT | VK_ACCESS_2_DEPTH_STENCIL_ATTACHMENT_WRITE_BIT,
                    VK_IMAGE_ASPECT_DEPTH_BIT);
  VkRenderingAttachmentInfo depth{VK_STRUCTURE_TYPE_RENDERING_ATTACHMENT_INFO};
  depth.imageView = targets.depth.view();
  depth.imageLayout = VK_IMAGE_LAYOUT_DEPTH_ATTACHMENT_OPTIMAL;
  depth.loadOp = VK_ATTACHMENT_LOAD_OP_CLEAR;
  depth.storeOp = VK_ATTACHMENT_STORE_OP_DONT_CARE;
  depth.clearValue.depthStencil = {0.0f, 0};
  return depth;
}

}  // namespace prismoid::volume
