#pragma once
// CPU double-precision reference images, resolved into the same OffscreenFrame the GPU path
// returns (quantity, display colour, emission), so `render --mode reference` and the
// comparisons treat both alike.
#include <vulkan/vulkan.h>

#include "renderer/frame/frame_report.hpp"
#include "renderer/metrics/image_error.hpp"
#include "scene/camera.hpp"
#include "scene/tet_mesh_fwd.hpp"

namespace prismoid::frame {

// A frame of `size` for a CPU reference to fill: one quantity and one RGBA display value per pixel.
OffscreenFrame blank_frame(VkExtent2D size);

// The mesh's piecewise-linear (or per-cell) field, composited in exact per-pixel order.
OffscreenFrame render_reference(const TetMesh& mesh, const Camera& camera, const volume::ResolveSettings& resolve,
                                       VkExtent2D size);

// The analytic field in resolve.march (what interval-march approximates).
OffscreenFrame render_field_reference(const TetMesh& mesh, const Camera& camera, const volume::ResolveSettings& resolve,
                                             VkExtent2D size);

// The CPU reference of the frame a command line asks for: of the analytic field when there is
// one (`field`), else of the mesh.
OffscreenFrame reference_of(const TetMesh& mesh, const Camera& camera, const volume::ResolveSettings& resolve,
                                   VkExtent2D size, bool field);

// The signal range a PSNR is relative to: the reference's largest optical depth, else 1.
double error_peak(const OffscreenFrame& ref, volume::Quantity q);
// How far `test` is from `ref`: of the display RGB for colour, else of the quantity.
reference::ImageError frame_error(const OffscreenFrame& test, const OffscreenFrame& ref, volume::Quantity q);

}  // namespace prismoid::frame
