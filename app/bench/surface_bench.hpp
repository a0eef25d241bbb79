#pragma once
// The bench's surface rows: every surface mode of surface::SurfaceRenderer on each surface scene,
// timed on the GPU and measured against the CPU double-precision reference of what the mode
// computes (surface_reference_kind), supersampled so that a mode's aliasing counts as error the
// way a person sees it.
#include <string>
#include <vector>

#include "app/bench/bench_cases.hpp"
#include "app/bench/bench_table.hpp"
#include "renderer/surface/msa/meshlets.hpp"

namespace prismoid::vk {
class Device;
}

namespace prismoid::bench {

struct SurfaceBenchOptions {
  std::vector<std::string> scenes{"cornell-box"};  // as `prismoid render` names them
  ImageSize size{96, 72};
  uint32_t frames = 3;
  double warm_up_seconds = 0.0;  // before each row's timed frames (timing::warm_up); at least one frame
  uint32_t supersample = 4;  // the direct-light reference's samples per pixel side
  uint32_t path_spp = 64;    // the GI modes' reference: path tracer samples per pixel
  uint32_t gi_frames = 16;   // GI rows measure the frame after this many frames of a still camera
  std::vector<std::string> modes;  // empty: every mode the device draws
  // Equal terms: with a budget, the texture-space modes get a second row shading about this many
  // samples per frame (htex, texel: a level-of-detail bias found from the unbiased row's count,
  // log2 of the ratio halved; msa: its block budget). 0: no such rows; kBudgetCoveredPixels: the
  // scene's covered pixels (one sample per visible pixel, the papers' equal terms).
  static constexpr uint32_t kBudgetCoveredPixels = 0xffffffffu;
  uint32_t shading_budget = 0;
  // Shading load: N point lights (on a sphere around the scene, each casting shadows) replace the
  // scene's own, as Hillesland & Yang scale their lights (they report 30). 0: the scene's lights.
  uint32_t extra_lights = 0;
  // A third row for htex, texel and msa whose frames reuse the shading of a still camera (the
  // planner's rule): what a frame costs when nothing has to be shaded again.
  bool still_rows = false;
  // Moving rows (> 0): forward, htex, texel and msa with the camera orbiting its target about its
  // up axis by this many degrees per frame, `frames` warm-up frames and then the measured ones,
  // the last at the scene's camera (the reference's). Shading is kept or redone by each mode's
  // own rule, as in the window.
  double motion_degrees = 0.0;
  // With motion: msa rows amortized over n frames each (SurfaceRenderer::set_msa_amortization).
  std::vector<uint32_t> msa_amortization;
  // The msa rows' charts, each kind a set of rows (--msa-charts projection,conformal).
  std::vector<msa::Parametrization> msa_charts{msa::Parametrization::Projection};
  // Equal terms (--shading-scales): each texture-space mode without GI also at these shading-rate
  // factors SF < 1 (texels per pixel side, the FastAtlas paper's pre-scale; SF^2 of the samples):
  // htex, texel and fastatlas by a level-of-detail bias of -log2 SF, msa by a block budget of SF^2
  // times its own row's shaded texels. Settings say "sf=0.5".
  std::vector<double> shading_scales;
  // FastAtlas's atlas sides (--fastatlas-atlases 2048,4096,8192): one set of fastatlas rows per
  // side (settings "atlas=N"); empty: the backend's default.
  std::vector<uint32_t> fastatlas_atlases;
  // With motion: fastatlas rows with temporal reuse refreshed every n frames (--fastatlas-refresh LIST).
  std::vector<uint32_t> fastatlas_refresh;
  // --max-triangle-pixels P: each scene's large triangles split until none spans more than P
  // pixels of the first view (refine_large_triangles; 0: as loaded). Settings say "refined=P".
  double max_triangle_pixels = 0.0;
  // Which shadow settings get rows (--surface-shadows on|off|both); both: where the device traces rays.
  bool shadows_off = true, shadows_on = true;
};

// Which CPU reference a mode is held to, in words (the report's notes say it).
std::string surface_reference_kind(const std::string& mode);

std::vector<BenchRow> bench_surfaces(const vk::Device& device, const SurfaceBenchOptions& options);

}  // namespace prismoid::bench
