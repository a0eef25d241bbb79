#pragma once
// The emission-absorption test fixture: renders colour on the device and compares every pixel
// and channel with the CPU double-precision reference in exact per-pixel order, within
// per-pixel tolerances derived in color_comparison.cpp. Any non-finite channel fails the
// calling test.
#include <cstdint>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "renderer/frame/frame_renderer.hpp"
#include "renderer/reference/emission_absorption.hpp"
#include "renderer/volume/transfer_function.hpp"
#include "scene/camera.hpp"
#include "scene/tet_mesh_fwd.hpp"
#include "support/backends.hpp"
#include "support/gpu_fixture.hpp"

namespace prismoid::test {

struct ColorComparison {
  size_t failures = 0, covered = 0;  // failing channels; pixels the reference sees medium at
  double rmse = 0.0;  // over all pixels and channels, against the reference
  std::vector<std::string> passes;
  double max_error = 0.0, worst_over_tolerance = 0.0;
  std::string first_failure;
  std::string ordering;
  bool order_exact = false;
  frame::FrameReport report;
  // Per pixel: whether a colour channel (r, g, b) or alpha lies beyond its tolerance, and how
  // many segments the reference's ray crosses.
  std::vector<bool> colour_failed, alpha_failed;
  std::vector<uint32_t> segments;
};

// The CPU reference of a colour frame and each pixel's tolerance (the same for its four
// channels), as derived in color_comparison.cpp, for a device snapping to 2^-subpixel_bits pixel.
struct ColorReference {
  reference::ColorImage image;
  std::vector<double> tolerance;
};
ColorReference color_reference(uint32_t subpixel_bits, const TetMesh& mesh, const volume::TransferFunction& tf, const Camera& camera,
                               uint32_t w, uint32_t h, const volume::PreintegrationTable* table, const std::vector<float>* depth_limit);

// On both interval backends (support/backends.hpp): TEST_P, and PRISMOID_ON_BOTH_BACKENDS.
class ColorTest : public GpuTest, public OnBackend {
 public:
  // Colour through `tf` on this test's backend (`ordering` is the mesh backend's; the compute
  // backend orders each pixel itself), with a pre-integrated table of `table_size` (0: exact).
  // Static, so fixtures of other comparisons on the same backend can call it too; `backend`
  // overrides the test's. `depth_limit`: where rays end (volume::ResolveSettings), for the GPU
  // and the reference alike.
  static ColorComparison compare(const TetMesh& mesh, const volume::TransferFunction& tf, const Camera& camera, uint32_t w,
                                 uint32_t h, frame::Ordering ordering, uint32_t table_size = 0,
                                 std::optional<frame::IntervalBackend> backend = std::nullopt,
                                 std::shared_ptr<const std::vector<float>> depth_limit = nullptr);
};

}  // namespace prismoid::test
