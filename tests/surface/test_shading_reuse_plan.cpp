// The frame planner's rule for reusing Htex shading across frames (renderer/surface/
// surface_renderer.hpp): when it keeps the shading, when it shades again, and why.
#include <gtest/gtest.h>

#include "renderer/surface/surface_renderer.hpp"

namespace prismoid::test {
namespace {

using surface::plan_shading_reuse;
using surface::ReuseInputs;

TEST(ShadingReusePlan, KeepsShadingOnlyWhileTheEyeAndTheSettingsStayPut) {
  ReuseInputs in;
  EXPECT_TRUE(plan_shading_reuse(in).invalidate);  // the first frame shades
  in.first_frame = false;
  EXPECT_FALSE(plan_shading_reuse(in).invalidate);  // nothing changed: reuse
  EXPECT_NE(plan_shading_reuse(in).reason.find("reused"), std::string::npos);
  in.eye_moved = true;
  EXPECT_TRUE(plan_shading_reuse(in).invalidate);
  EXPECT_NE(plan_shading_reuse(in).reason.find("eye moved"), std::string::npos);
  in.eye_moved = false;
  in.settings_changed = true;
  EXPECT_TRUE(plan_shading_reuse(in).invalidate);
  EXPECT_NE(plan_shading_reuse(in).reason.find("shadows"), std::string::npos);
}

// Amortized (msa's shade_every): a moving eye keeps the shading; the first frame and a changed
// setting still shade.
TEST(ShadingReusePlan, AmortizedShadingIsKeptWhileTheEyeMoves) {
  ReuseInputs in;
  in.amortized = true;
  EXPECT_TRUE(plan_shading_reuse(in).invalidate);
  in.first_frame = false;
  in.eye_moved = true;
  EXPECT_FALSE(plan_shading_reuse(in).invalidate);
  EXPECT_NE(plan_shading_reuse(in).reason.find("amortized"), std::string::npos);
  in.settings_changed = true;
  EXPECT_TRUE(plan_shading_reuse(in).invalidate);
}

}  // namespace
}  // namespace prismoid::test
