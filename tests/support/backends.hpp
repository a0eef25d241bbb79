#pragma once
// Volume tests that compare against the CPU reference run on both interval backends with the
// same tolerances: their fixtures take the backend as a test parameter (TEST_P in place of
// TEST_F) and are instantiated once per fixture with PRISMOID_ON_BOTH_BACKENDS(Fixture),
// which names each test .../Mesh and .../Compute.
#include <gtest/gtest.h>

#include <string>

#include "renderer/frame/frame_plan.hpp"

namespace prismoid::test {

// A fixture's mixin: the backend its frames use.
class OnBackend : public ::testing::WithParamInterface<frame::IntervalBackend> {
 protected:
  static frame::IntervalBackend backend() { return GetParam(); }
  static bool compute() { return GetParam() == frame::IntervalBackend::Compute; }
  // Default settings, on this test's backend.
  static frame::FrameSettings settings_on_backend() {
    frame::FrameSettings s;
    s.backend = GetParam();
    return s;
  }
};

inline std::string backend_test_name(const ::testing::TestParamInfo<frame::IntervalBackend>& info) {
  return info.param == frame::IntervalBackend::Mesh ? "Mesh" : "Compute";
}

}  // namespace prismoid::test

#define PRISMOID_ON_BOTH_BACKENDS(Fixture)                                                                                 \
  INSTANTIATE_TEST_SUITE_P(Backends, Fixture,                                                                              \
                           ::testing::Values(::prismoid::frame::IntervalBackend::Mesh, ::prismoid::frame::IntervalBackend::Compute), \
                           ::prismoid::test::backend_test_name)
// For the tests of what only one backend has (mesh-shader workgroup sizes, tetlets, draw orders).
#define PRISMOID_ON_MESH_BACKEND(Fixture) \
  INSTANTIATE_TEST_SUITE_P(MeshShader, Fixture, ::testing::Values(::prismoid::frame::IntervalBackend::Mesh), ::prismoid::test::backend_test_name)
// For the tests of what only the compute backend has (k-buffer, tiles, pair buffers).
#define PRISMOID_ON_COMPUTE_BACKEND(Fixture) \
  INSTANTIATE_TEST_SUITE_P(ComputeOnly, Fixture, ::testing::Values(::prismoid::frame::IntervalBackend::Compute), ::prismoid::test::backend_test_name)
