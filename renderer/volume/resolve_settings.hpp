#pragma once
// What a volume frame shows and how its segments are integrated: the settings both the GPU
// passes and the frame planner read (no Vulkan here).
#include <array>
#include <memory>
#include <vector>
#include <cstdint>
#include <glm/vec3.hpp>

#include "renderer/volume/analytic_field.hpp"
#include "renderer/volume/transfer_function.hpp"

namespace prismoid::volume {

// What a frame shows: optical depth and transmittance integrate sigma (order independent);
// colour is emission-absorption through a transfer function (order dependent); an isosurface
// (marching only) is the nearest point where the field reaches the isovalue (depth tested).
enum class Quantity { OpticalDepth, Transmittance, Color, Isosurface };
inline bool order_dependent(Quantity q) { return q == Quantity::Color; }

// Marching inside intervals (Tricard 2024, section 3.2): each fragment samples an analytic
// field or a sampled grid (world coordinates) along its interval in equal steps of at most `step` (world
// length) instead of integrating the mesh's own linear field.
struct MarchSettings {
  bool enabled = false;
  AnalyticField field;
  double step = 0.0;           // > 0 when enabled
  double density_scale = 1.0;  // optical depth: sigma = density_scale * max(field, 0)
  double isovalue = 0.5;       // Quantity::Isosurface
  // Where the field lies in the frame's coordinates: the frame's point q is the field's point
  // field_offset + field_scale * q (the renderer draws in units of the data's size,
  // frame/frame_units.hpp; the field keeps its own).
  glm::dvec3 field_offset{0.0};
  double field_scale = 1.0;
};

struct ResolveSettings {
  Quantity quantity = Quantity::Transmittance;
  glm::vec3 background{1.0f, 1.0f, 1.0f};
  glm::vec3 medium{0.05f, 0.08f, 0.2f};
  // Colour only: the transfer function, and how segments are integrated: 0 exactly in the
  // fragment shader, N > 1 by lookup in an N^3 pre-integrated table (faster, approximate).
  TransferFunction transfer = preset("cool-to-warm");
  uint32_t preintegration_size = 0;
  MarchSettings march;
  // Cells per mesh workgroup, one per invocation: 1 is the paper's one cell per workgroup.
  uint32_t tetlet_size = 16;
  // Tetlets: group cells so a workgroup loads their shared points once (needs tetlet_size > 1
  // and GpuTetlets of that size; cells are then drawn tetlet by tetlet, in no depth order).
  bool shared_vertices = false;
  // Where each pixel's ray ends: the depth along the viewing axis of opaque geometry in front
  // of or inside the volume (a slice, a surface drawn before it), one per pixel of the frame,
  // row 0 at the top; +inf where nothing is. Null: no limit. Both backends and the CPU
  // references end each interval there (optical depth, transmittance, colour).
  std::shared_ptr<const std::vector<float>> depth_limit;
};

// The workgroup sizes there are shader variants of.
inline constexpr std::array<uint32_t, 4> kTetletSizes = {1, 4, 8, 16};

// The name of the interval pass these settings record (its timestamp pair and its entry in
// the frame plan): interval-shading, interval-shading (emission) or interval-march (...).
const char* interval_pass_name(const ResolveSettings& settings);

}  // namespace prismoid::volume
