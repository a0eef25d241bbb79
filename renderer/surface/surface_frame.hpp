#pragma once
// The per-frame block every surface backend shades with (gpu::SurfaceFrame, shaders/shared/
// surface.h): camera matrices relative to the scene's origin, the viewport, the lights' counts
// and the sky. Computed in double, rounded once.
#include <glm/vec2.hpp>
#include <vulkan/vulkan.h>

#include "renderer/surface/gpu_surface_scene.hpp"
#include "scene/camera.hpp"
#include "shaders/shared/surface.h"

namespace prismoid::surface {

// `subpixel`: where each pixel is sampled, in pixels from its centre (folded into the projection
// and stored for passes that build pixel rays themselves); subpixel.z carries the scene's scale
// (GpuSurfaceScene::scale) for the shadow rays' offset.
gpu::SurfaceFrame surface_frame(const GpuSurfaceScene& scene, const Camera& camera, VkExtent2D extent, const glm::dvec2& subpixel);

}  // namespace prismoid::surface
