// Colour of a volume inside its geometry against the CPU reference of the whole mixed frame
// (renderer/mixed/mixed_reference.hpp), on both volume backends, through the renderer's API, the
// surfaces shaded forward without shadows and with them.
//
// The composite is C = C_v + (1 - A_v) S per channel (C_v, A_v the volume's premultiplied colour
// and alpha up to the surface, S the shaded surface or the sky). Its tolerance per pixel and
// channel is built from its parts' own, each derived where that part is tested alone:
//  - t_v, the volume's colour and alpha (volume/color_comparison.cpp: snapping, float inputs of
//    each segment, the blend), with the reference's rays ending at the reference's surface depth;
//  - t_d, where the rays end: the GPU ends them at the rasterized surface's depth (vertices
//    snapped to 2^-b pixel, z = near / d interpolated in float), so by at most the reference
//    depth's largest change within 2 * 2^-b pixel plus 2^-20 of it. Extending a ray only adds
//    non-negative premultiplied emission and opacity, so C_v and A_v are monotone in the depth:
//    the reference with every depth moved by that much either way bounds the change;
//  - t_s, the surfaces (surface/forward_comparison.hpp: snapping and float rounding, twice the
//    snapping term with shadows); pixels on a silhouette of a square are not compared (which
//    surface a rasterized edge pixel shows is not fixed), nor, with shadows, pixels whose shadow
//    ray passes within float's reach of an occluder's edge;
//  - the composite's own float rounding: 2^-22 of the magnitudes.
// Bound: |dC| <= t_v + t_d + (t_v + t_d) |S| + (1 - A_v + t_v + t_d) t_s + 2^-22 (|C| + |S|).
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <string>
#include <vector>

#include "mixed/square_scene.hpp"
#include "renderer/mixed/mixed_frame.hpp"
#include "renderer/mixed/mixed_reference.hpp"
#include "renderer/reference/direct_light.hpp"
#include "renderer/reference/emission_absorption.hpp"
#include "scene/generators.hpp"
#include "scene/tet_mesh.hpp"
#include "support/backends.hpp"
#include "support/gpu_fixture.hpp"
#include "surface/forward_comparison.hpp"
#include "volume/color_comparison.hpp"

namespace prismoid {
namespace {

constexpr uint32_t kW = 40, kH = 30;

volume::TransferFunction blob_tf() {
  volume::TransferFunction tf = volume::preset("viridis");
  tf.opacity = {{0.0, 0.0}, {0.2, 0.3}, {0.6, 0.8}, {1.0, 1.0}};
  tf.range_lo = 0.0;
  tf.range_hi = 6.0;
  tf.density_scale = 4.0;  // the square shows through the thinner parts, and is hidden by the blobs
  return tf;
}

struct Result {
  size_t compared = 0, silhouettes = 0, failures = 0;
  size_t cut = 0;        // compared pixels whose volume colour the square ends (beyond the tolerance)
  size_t showing = 0;    // compared pixels where the square shows through the volume (beyond the tolerance)
  size_t shadowed = 0;   // compared pixels whose surface a shadow darkens (beyond the tolerance)
  double worst = 0.0, max_error = 0.0;
  std::string first;
};

class MixedColorTest : public test::GpuTest, public test::OnBackend {
 protected:
  // The surfaces shaded forward, with shadow rays or without (the surface renderer's setting).
  Result compare(const Camera& camera, const SurfaceScene& surfaces, bool shadows) {
    const TetMesh mesh = make_default_volume();  // point scalars: the Gaussian blobs' density
    frame::FrameSettings settings = settings_on_backend();
    settings.resolve.quantity = volume::Quantity::Color;
    settings.resolve.transfer = blob_tf();
    settings.ordering = frame::Ordering::Exact;  // a Kuhn-split box: convex and acyclic, exact
    mixed::MixedRenderer renderer(device(), mesh, surfaces);
    renderer.surface_renderer().set_shadows(shadows);
    const mixed::MixedFrame gpu = renderer.render(camera, settings, {kW, kH});
    EXPECT_EQ(gpu.shadows, shadows);
    const mixed::MixedFrame ref = mixed::render_mixed_reference(mesh, surfaces, camera, settings.resolve, {kW, kH}, shadows);

    const uint32_t bits = device().capabilities().subpixel_precision_bits;
    const auto surface_tol = test::forward_tolerances(bits, surfaces, camera, kW, kH, glm::dvec2(0.0), shadows);
    const auto unshadowed = reference::direct_light_image(surfaces, camera, kW, kH);
    const test::ColorReference volume_tol =
        test::color_reference(bits, mesh, settings.resolve.transfer, camera, kW, kH, nullptr, &ref.surface_depth);
    // The depth's reach: its largest change within the snapping radius, plus 2^-20 of it.
    const double r = 2.0 * std::ldexp(1.0, -int(bits));
    std::vector<float> nearer = ref.surface_depth, farther = ref.surface_depth;
    for (const auto& [dx, dy] : {std::pair{r, 0.0}, {-r, 0.0}, {0.0, r}, {0.0, -r}}) {
      const auto probe = mixed::first_hit_depth(reference::direct_light_image(surfaces, camera, kW, kH, dx, dy), camera);
      for (size_t i = 0; i < probe.size(); ++i) {
        const double d = ref.surface_depth[i];
        if (!std::isfinite(d) || !std::isfinite(probe[i])) continue;  // silhouettes: not compared
        const double reach = std::abs(double(probe[i]) - d) + std::ldexp(d, -20);
        nearer[i] = std::min(nearer[i], float(d - reach));
        farther[i] = std::max(farther[i], float(d + reach));
      }
    }
    const auto& tf = settings.resolve.transfer;
    const auto near_image = reference::emission_absorption_image(mesh, tf, camera, kW, kH, 0.0, 0.0, nullptr, nullptr, &nearer);
    const auto far_image = reference::emission_absorption_image(mesh, tf, camera, kW, kH, 0.0, 0.0, nullptr, nullptr, &farther);
    const auto whole = reference::emission_absorption_image(mesh, tf, camera, kW, kH);

    Result res;
    for (size_t i = 0; i < size_t(kW) * kH; ++i) {
      for (int k = 0; k < 4; ++k) EXPECT_TRUE(std::isfinite(gpu.display[4 * i + k])) << "pixel " << i;
      const test::ForwardTolerance& s = surface_tol[i];
      if (!s.compared()) {  // a silhouette, or an ambiguous shadow ray
        ++res.silhouettes;
        continue;
      }
      ++res.compared;
      for (int k = 0; k < 3; ++k)
        if (std::abs(unshadowed.pixels[i].radiance[k] - s.centre.radiance[k]) > 4.0 * s.tolerance) {
          ++res.shadowed;
          break;
        }
      const glm::dvec4 v = volume_tol.image.pixels[i];
      double t_d = 0.0;
      for (int k = 0; k < 4; ++k)
        t_d = std::max(t_d, std::max(std::abs(far_image.pixels[i][k] - v[k]), std::abs(near_image.pixels[i][k] - v[k])));
      const double t_v = volume_tol.tolerance[i];
      bool cut = false;
      for (int k = 0; k < 4; ++k) cut = cut || std::abs(whole.pixels[i][k] - v[k]) > 4.0 * (t_v + t_d);
      res.cut += cut;
      bool ok = true, showing = false;
      for (int k = 0; k < 3; ++k) {
        const double behind = std::abs(double(ref.surface_rgba[4 * i + k]));
        const double want = ref.display[4 * i + k], got = gpu.display[4 * i + k];
        const double tol = t_v + t_d + (t_v + t_d) * behind + (1.0 - v.a + t_v + t_d) * s.tolerance +
                           std::ldexp(std::abs(want) + behind, -22);
        const double error = std::abs(got - want);
        res.max_error = std::max(res.max_error, error);
        res.worst = std::max(res.worst, error / tol);
        ok = ok && error <= tol;
        showing = showing || ((1.0 - v.a) * behind > 4.0 * tol && s.centre.hit);
        if (!ok && res.failures++ == 0)
          res.first = "pixel (" + std::to_string(i % kW) + "," + std::to_string(i / kW) + ") channel " + std::to_string(k) + ": gpu " +
                      std::to_string(got) + ", reference " + std::to_string(want) + ", tolerance " + std::to_string(tol) +
                      " (volume " + std::to_string(t_v) + ", depth " + std::to_string(t_d) + ", surface " +
                      std::to_string(s.tolerance) + ")";
        if (!ok) break;
      }
      res.showing += showing;
    }
    return res;
  }

  void expect(const Result& r, const char* what) {
    EXPECT_EQ(r.failures, 0u) << what << ": " << r.first;
    EXPECT_GT(r.compared, size_t(kW) * kH * 3 / 4) << what;
    // The comparison can tell: the square ends rays that would have gathered more colour, and
    // shows through where the volume is thin.
    EXPECT_GT(r.cut, 30u) << what;
    EXPECT_GT(r.showing, 30u) << what;
    std::printf("[ %s ] %zu pixels compared (%zu on silhouettes not), %zu cut by the square, %zu showing it, %zu in shadow; "
                "largest difference %.3g, worst at %.3f of the tolerance\n",
                what, r.compared, r.silhouettes, r.cut, r.showing, r.shadowed, r.max_error, r.worst);
  }
};

TEST_P(MixedColorTest, ColourMatchesTheMixedReference) {
  Camera outside;
  outside.eye = {2.0, 1.5, 4.5};
  outside.target = {0.0, 0.0, 0.0};
  outside.fovy_degrees = 40.0;
  outside.near_distance = 0.05;
  expect(compare(outside, test::square_scene({0.1, -0.6, 0.5, -0.5, 0.6}), false), "camera outside, square inside the volume");
}

// Shadowed forward under the volume: a second square between the light and the first casts a
// shadow on it (and hides part of the volume in front of it).
TEST_P(MixedColorTest, ShadowedSurfacesUnderTheVolumeMatchTheMixedReference) {
  Camera outside;
  outside.eye = {2.0, 1.5, 4.5};
  outside.target = {0.0, 0.0, 0.0};
  outside.fovy_degrees = 40.0;
  outside.near_distance = 0.05;
  const SurfaceScene surfaces = test::with_square(test::square_scene({0.1, -0.6, 0.5, -0.5, 0.6}), {1.4, -0.35, 0.2, -0.3, 0.25});
  mixed::MixedRenderer probe(device(), make_box_mesh(glm::dvec3(-1.0), glm::dvec3(1.0), 1, [](const glm::dvec3&) { return 1.0; }),
                             surfaces);
  if (!probe.surface_renderer().can_shadow()) GTEST_SKIP() << device().capabilities().name << " traces no rays";
  const Result r = compare(outside, surfaces, true);
  expect(r, "camera outside, with shadows");
  EXPECT_GT(r.shadowed, 30u) << "the occluder must shadow enough of the square for the comparison to tell";
}

TEST_P(MixedColorTest, ColourMatchesTheMixedReferenceWithTheCameraInside) {
  Camera inside;
  inside.eye = {0.1, 0.05, 0.6};
  inside.target = {0.0, 0.0, -1.0};
  inside.fovy_degrees = 60.0;
  inside.near_distance = 0.01;
  expect(compare(inside, test::square_scene({-0.3, -0.6, 0.5, -0.5, 0.4}), false), "camera inside, looking at the square");
}

PRISMOID_ON_BOTH_BACKENDS(MixedColorTest);

}  // namespace
}  // namespace prismoid
