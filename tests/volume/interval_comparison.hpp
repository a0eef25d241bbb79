#pragma once
// The interval-shading test fixture: renders optical depth on the device and compares every
// pixel with the CPU double-precision reference, within per-pixel tolerances derived in
// interval_comparison.cpp. Any non-finite pixel fails the calling test.
#include <cstdint>
#include <string>
#include <vector>

#include "scene/camera.hpp"
#include "scene/tet_mesh_fwd.hpp"
#include "support/backends.hpp"
#include "support/gpu_fixture.hpp"

namespace prismoid::test {

// On both interval backends (support/backends.hpp): TEST_P, and PRISMOID_ON_BOTH_BACKENDS.
class IntervalShadingTest : public GpuTest, public OnBackend {
 public:
  std::vector<float> render(const TetMesh& mesh, const Camera& camera, uint32_t w, uint32_t h);

  struct Comparison {
    size_t failures = 0;
    size_t covered = 0;
    double max_error = 0.0;
    double max_relative_to_tolerance = 0.0;  // how close the worst pixel came to failing
    std::string first_failure;
    std::vector<size_t> failed_pixels;       // row-major indices, the first 64
  };

  Comparison compare(const TetMesh& mesh, const Camera& camera, uint32_t w, uint32_t h);
  // The same comparison for an optical-depth image the caller rendered (a march of a linear
  // field, which the midpoint rule integrates exactly), with `extra` added to each pixel's
  // tolerance (none when empty).
  Comparison compare_image(const std::vector<float>& gpu, const TetMesh& mesh, const Camera& camera, uint32_t w, uint32_t h,
                           const std::vector<double>& extra = {});
};

}  // namespace prismoid::test
