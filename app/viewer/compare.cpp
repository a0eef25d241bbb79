#include "app/viewer/compare.hpp"

#include <algorithm>
#include <cmath>
#include <sstream>
#include <string>

#include "renderer/frame/volume_modes.hpp"
#include "renderer/volume/volume_backends.hpp"

namespace prismoid::app {

const char* compare_mode_name(CompareMode mode) {
  switch (mode) {
    case CompareMode::Off: return "off";
    case CompareMode::Split: return "split";
    case CompareMode::Difference: return "difference";
  }
  return "?";
}

std::optional<CompareMode> compare_mode_of_name(const std::string& name) {
  for (CompareMode m : {CompareMode::Off, CompareMode::Split, CompareMode::Difference})
    if (name == compare_mode_name(m)) return m;
  return std::nullopt;
}

namespace {

// B as a ViewState of its own, so B's mode and quantity go through set_mode and set_quantity
// with exactly A's checks and fallbacks.
ViewState as_b(const ViewState& state) {
  ViewState b;
  b.datasets = state.datasets;
  b.active = state.active;
  b.mode = state.compare_mode.empty() ? state.mode : state.compare_mode;
  b.settings = state.compare_mode.empty() ? state.settings : state.compare_settings;
  return b;
}

void take_b(ViewState& state, ViewState&& b) {
  state.compare_mode = std::move(b.mode);
  state.compare_settings = std::move(b.settings);
}

}  // namespace

std::string set_compare(ViewState& state, CompareMode mode) {
  if (mode == CompareMode::Split && state.compare_mode.empty()) {
    // B starts as the exact order, the most accurate GPU mode, unless A is that already.
    const frame::VolumeMode* exact = frame::find_volume_mode(frame::Ordering::Exact, false);
    const frame::VolumeMode* b = state.mode == exact->name ? frame::find_volume_mode(frame::Ordering::MeshOrder, false) : exact;
    const std::string problem = set_compare_mode(state, std::string(b->name));
    if (!problem.empty()) return problem;
  }
  state.compare = mode;
  return {};
}

std::string set_compare_mode(ViewState& state, const std::string& mode) {
  ViewState b = as_b(state);
  const std::string problem = set_mode(b, mode);
  if (problem.empty()) take_b(state, std::move(b));
  return problem;
}

std::string set_compare_quantity(ViewState& state, volume::Quantity quantity) {
  ViewState b = as_b(state);
  const std::string problem = set_quantity(b, quantity);
  if (problem.empty()) take_b(state, std::move(b));
  return problem;
}

namespace {

// The backends the window switches between: the table's GPU ones.
std::string gpu_volume_backend_names() {
  std::string names;
  for (const volume::VolumeBackendInfo* b : volume::volume_backend_table())
    if (b->gpu()) names += (names.empty() ? "" : ", ") + std::string(b->name);
  return names;
}

std::string apply_backend(frame::FrameSettings& settings, const std::string& backend) {
  const volume::VolumeBackendInfo* info = volume::find_volume_backend(backend);
  if (!info || !info->gpu()) return "unknown backend '" + backend + "' (available: " + gpu_volume_backend_names() + ")";
  settings.backend = frame::IntervalBackend{info->name};
  settings.backend_reason.clear();  // chosen by name now, not by auto's calibration
  if (settings.resolve.shared_vertices && !info->passes.tetlets) {
    settings.resolve.shared_vertices = false;
    return std::string(info->name) + " backend: shared vertices (tetlets) are the mesh backend's, turned off";
  }
  return {};
}

}  // namespace

std::string set_backend(ViewState& state, const std::string& backend) {
  frame::FrameSettings s = state.settings;
  const std::string message = apply_backend(s, backend);
  if (message.rfind("unknown", 0) == 0) return message;
  state.settings = s;
  return message;
}

std::string set_compare_backend(ViewState& state, const std::string& backend) {
  ViewState b = as_b(state);
  const std::string message = apply_backend(b.settings, backend);
  if (message.rfind("unknown", 0) == 0) return message;
  take_b(state, std::move(b));
  return message;
}

frame::FrameSettings compare_frame_settings(const ViewState& state) {
  frame::FrameSettings s = state.settings;
  if (state.compare_mode.empty()) return s;
  const frame::FrameSettings& b = state.compare_settings;
  s.ordering = b.ordering;
  s.resolve.quantity = b.resolve.quantity;
  s.resolve.march.enabled = b.resolve.march.enabled;
  s.resolve.preintegration_size = b.resolve.preintegration_size;
  s.backend = b.backend;
  s.backend_reason = b.backend_reason;
  if (s.resolve.march.enabled && !(s.resolve.march.step > 0.0)) s.resolve.march.step = b.resolve.march.step;
  if (s.resolve.march.enabled && state.dataset().field) s.resolve.march.field = *state.dataset().field;
  // Tetlets fix the draw order: B keeps A's choice only where its own quantity and order allow,
  // and only on the mesh backend, whose workgroups they are.
  ViewState check;
  check.settings = s;
  if (!shared_vertices_problem(check).empty() || s.backend != frame::IntervalBackend::Mesh) s.resolve.shared_vertices = false;
  return s;
}

VkExtent2D reference_size(VkExtent2D window, uint32_t max_side) {
  const uint32_t longest = std::max(window.width, window.height);
  if (longest <= max_side || longest == 0) return window;
  const double k = double(max_side) / double(longest);
  return {std::max(1u, uint32_t(std::lround(window.width * k))), std::max(1u, uint32_t(std::lround(window.height * k)))};
}

std::string reference_key(const Camera& c, const frame::FrameSettings& s, VkExtent2D size, size_t dataset) {
  std::ostringstream k;
  k.precision(17);
  auto v3 = [&](const auto& v) { k << v.x << ',' << v.y << ',' << v.z << ' '; };
  k << dataset << ' ' << size.width << 'x' << size.height << ' ';
  v3(c.eye), v3(c.target), v3(c.up);
  k << c.fovy_degrees << ' ' << c.near_distance << " | " << int(s.ordering) << ' ';
  const volume::ResolveSettings& r = s.resolve;
  k << int(r.quantity) << ' ';
  v3(r.background), v3(r.medium);
  k << r.preintegration_size << ' ' << r.tetlet_size << ' ' << r.shared_vertices << " tf ";
  k << r.transfer.range_lo << ' ' << r.transfer.range_hi << ' ' << r.transfer.density_scale << ' ';
  for (const auto& p : r.transfer.color) k << p.x << ':', v3(p.rgb);
  for (const auto& p : r.transfer.opacity) k << p.x << ':' << p.opacity << ' ';
  const volume::MarchSettings& m = r.march;
  k << " march " << m.enabled << ' ' << m.step << ' ' << m.density_scale << ' ' << m.isovalue << ' ' << m.field.name << ' '
    << int(m.field.kind) << ' ' << m.field.grid.get();
  for (const auto& p : m.field.params) k << ' ' << p.x << ',' << p.y << ',' << p.z << ',' << p.w;
  return k.str();
}

}  // namespace prismoid::app
