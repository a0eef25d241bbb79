#pragma once
// The Htex backend behind the surface renderer's interface (surface_backend.hpp): marking,
// allocation, shading and gather of htex_pass, and for the GI modes ReSTIR GI hosted on its
// texels (renderer/surface/gi/htex_gi) between shading and gather.
#include "renderer/surface/gi/restir_gi.hpp"
#include "renderer/surface/surface_backend.hpp"

namespace prismoid::surface {

// Htex's finest level without --texels-per-unit: this many texels along the scene's bounding-box
// diagonal on its largest quads (texels_per_unit = this / diagonal), so the finest level is about
// two texels per pixel for the whole scene seen in a 1080p view; the level of detail picks
// coarser levels from there. The size follows the scene, not its units (a scene in millimetres
// gets the same atlas as one in metres).
inline constexpr double kHtexTexelsPerDiagonal = 2048.0;
// The GI modes' pool without --pool-pages: GI keeps 256 bytes per pool texel (samples,
// reservoirs, stamps), 16 times the pool's own 16, so 256 pages of 4096 texels hold 16 MiB of
// radiance and 256 MiB of GI.
inline constexpr uint32_t kGiPoolPages = 256;
double htex_texels_per_unit(const SurfaceScene& scene);

// The ReSTIR GI settings of each indirect-light mode (before --gi-neighbours and --gi-fallback).
RestirGiSettings restir_gi_settings(frame::SurfaceGi gi);

const SurfaceBackendInfo& htex_backend();

}  // namespace prismoid::surface
