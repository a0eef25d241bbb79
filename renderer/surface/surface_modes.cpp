#include "renderer/surface/surface_modes.hpp"

#include "renderer/surface/fastatlas/fastatlas_backend.hpp"
#include "renderer/surface/forward/forward_backend.hpp"
#include "renderer/surface/htex/htex_backend.hpp"
#include "renderer/surface/msa/msa_backend.hpp"
#include "renderer/surface/texel/texel_backend.hpp"

namespace prismoid::surface {

const std::vector<SurfaceMode>& surface_mode_table() {
  using frame::SurfaceGi;
  static const std::vector<SurfaceMode> table = {
      {"forward", "per-pixel shading: direct light from point, directional and emissive-triangle lights and the sky", &forward_backend(),
       SurfaceGi::None},
      {"htex", "Htex object-space shading on per-edge texture quads, gathered per pixel", &htex_backend(), SurfaceGi::None},
      {"htex-gi", "htex with one-bounce ReSTIR GI over its texels, as the paper ships it (biased)", &htex_backend(), SurfaceGi::RestirBiased},
      {"htex-gi-unbiased", "htex with ReSTIR GI, bias-corrected (a shadow ray per reused sample)", &htex_backend(), SurfaceGi::RestirUnbiased},
      {"htex-pt", "htex with one fresh bounce per texel and frame, no reuse: path tracing in object space", &htex_backend(),
       SurfaceGi::PathTraced},
      {"texel", "texel shading over a static mip-mapped atlas of planar charts", &texel_backend(), SurfaceGi::None},
      {"msa", "the meshlet shading atlas: a block per seen meshlet, sized from its pixels", &msa_backend(), SurfaceGi::None},
      {"fastatlas", "FastAtlas: a new atlas of the visible charts every frame, packed at the largest scale that fits",
       &fastatlas_backend(), SurfaceGi::None},
      {"path-reference", "the CPU path tracer: every light path, double precision, the reference", nullptr, SurfaceGi::None},
  };
  return table;
}

const SurfaceMode* find_surface_mode(std::string_view name) {
  for (const SurfaceMode& m : surface_mode_table())
    if (m.name == name) return &m;
  return nullptr;
}

const SurfaceMode* find_surface_mode(const SurfaceBackendInfo& backend, frame::SurfaceGi gi) {
  for (const SurfaceMode& m : surface_mode_table())
    if (m.backend == &backend && m.gi == gi) return &m;
  return nullptr;
}

std::vector<std::string> surface_modes(const vk::Device& device) {
  std::vector<std::string> modes;
  for (const SurfaceMode& m : surface_mode_table())
    if (m.gpu() && m.backend->device_problem(device).empty()) modes.emplace_back(m.name);
  return modes;
}

}  // namespace prismoid::surface
