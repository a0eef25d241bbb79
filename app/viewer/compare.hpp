#pragma once
// The compare settings of the view, without a window: which comparison is on, split view's
// second mode (B) and its settings, and what the difference view's reference is computed for.
// Plain functions over ViewState, unit-tested with the rest of the viewer's logic.
#include <optional>
#include <string>
#include <vulkan/vulkan.h>

#include "app/viewer/view_state.hpp"
#include "scene/camera.hpp"

namespace prismoid::app {

const char* compare_mode_name(CompareMode mode);  // off, split, difference
std::optional<CompareMode> compare_mode_of_name(const std::string& name);

// Each returns an empty string when applied, else why not (the state is then unchanged).
// Entering Split with no B chosen yet picks the exact order when A is not in it, else mesh order.
std::string set_compare(ViewState& state, CompareMode mode);
std::string set_compare_mode(ViewState& state, const std::string& mode);  // B's mode
std::string set_compare_quantity(ViewState& state, volume::Quantity quantity);  // B's quantity
// The interval backend ("mesh" or "compute") of A, or of B (choosing B's backend alone makes B
// A's mode on that backend, so the split view compares the two backends). Tetlets are the mesh
// backend's: choosing compute turns --shared-vertices off, and says so.
std::string set_backend(ViewState& state, const std::string& backend);
std::string set_compare_backend(ViewState& state, const std::string& backend);

// B's settings for this frame: A's transfer function, field, colours and workgroup settings,
// with B's own ordering, march switch, quantity, pre-integration size and backend, so the two halves
// differ only in what B chose.
frame::FrameSettings compare_frame_settings(const ViewState& state);

// The difference view's reference size: the window's, scaled down (aspect kept) so its long
// side is at most max_side pixels; the CPU reference costs seconds per megapixel.
VkExtent2D reference_size(VkExtent2D window, uint32_t max_side);

// Everything the reference and the GPU frame it is compared with depend on, as text: a new
// reference is due when this changes.
std::string reference_key(const Camera& camera, const frame::FrameSettings& settings, VkExtent2D size, size_t dataset);

}  // namespace prismoid::app
