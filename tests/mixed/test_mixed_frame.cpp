// A volume inside its geometry (renderer/mixed): a box of constant extinction with an opaque
// square in, before and behind it, on both volume backends. Each pixel's optical depth is the
// extinction times the chord of its ray through the box up to the square, in closed form (double,
// slab intersection): the surfaces' depth, read back from the forward pass, ends the volume's
// rays. Tolerance per pixel: the interval stages' float (2^-16 of the largest optical depth, far
// above their 2^-20 and the depth's 2^-24 rounding), plus the rasterizer's vertex snapping (2^-b
// pixel, b = subPixelPrecisionBits): the square's, times the optical depth's change per pixel
// (from the closed form itself), and every cell's own (reference::snapping_variation_image). Pixels within 0.75 pixel of an edge (the box's or the square's silhouette),
// where the snapped edge decides what the centre sees, are not compared.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>
#include <optional>
#include <string>
#include <vector>

#include <glm/geometric.hpp>

#include "renderer/mixed/mixed_frame.hpp"
#include "renderer/reference/tet_ray.hpp"
#include "scene/generators.hpp"
#include "scene/input_error.hpp"
#include "scene/surface_scene.hpp"
#include "scene/tet_mesh.hpp"
#include "mixed/square_scene.hpp"
#include "support/backends.hpp"
#include "support/gpu_fixture.hpp"

namespace prismoid {
namespace {

using test::Square;
using test::square_scene;

constexpr double kSigma = 0.7;
constexpr uint32_t kW = 64, kH = 48;

// The closed form: sigma times the chord of the ray through image point (px, py) inside the box
// [-1, 1]^3, beyond the near plane and before the square. nullopt where the point lies within
// `margin` pixels of an edge (what the ray meets changes there).
struct Chord {
  double tau = 0.0;
  int what = 0;  // 1: meets the box, 2: meets the square (bits)
};
Chord chord(const Camera& camera, const Square& s, double px, double py) {
  const glm::dvec3 d = reference::ray_direction(camera, kW, kH, px, py), o = camera.eye;
  const double along = glm::dot(d, glm::normalize(camera.target - camera.eye));
  double t0 = camera.near_distance / along, t1 = std::numeric_limits<double>::infinity();
  double in = 0.0, out = std::numeric_limits<double>::infinity();
  for (int a = 0; a < 3; ++a) {
    const double ta = (-1.0 - o[a]) / d[a], tb = (1.0 - o[a]) / d[a];
    in = std::max(in, std::min(ta, tb));
    out = std::min(out, std::max(ta, tb));
  }
  Chord c;
  if (in < out && out > t0) c.what |= 1;
  const double ts = (s.z - o.z) / d.z;
  const glm::dvec3 p = o + ts * d;
  if (ts > t0 && p.x >= s.x0 && p.x <= s.x1 && p.y >= s.y0 && p.y <= s.y1) {
    c.what |= 2;
    t1 = ts;
  }
  if (c.what & 1) c.tau = kSigma * std::max(0.0, std::min(out, t1) - std::max(in, t0));
  return c;
}

struct Check {
  size_t compared = 0, covered = 0, failures = 0;
  size_t ended = 0;  // compared pixels whose ray meets both the box and the square
  double worst = 0.0;
  std::string first;
};

class MixedFrameTest : public test::GpuTest, public test::OnBackend {
 protected:
  Check check(const Camera& camera, const Square& s, volume::Quantity quantity) {
    const TetMesh box = make_box_mesh(glm::dvec3(-1.0), glm::dvec3(1.0), 3, [](const glm::dvec3&) { return kSigma; });
    mixed::MixedRenderer renderer(device(), box, square_scene(s));
    frame::FrameSettings settings = settings_on_backend();
    settings.resolve.quantity = quantity;
    const mixed::MixedFrame f = renderer.render(camera, settings, {kW, kH});
    EXPECT_EQ(f.display.size(), size_t(kW) * kH * 4);
    const double snap = std::ldexp(1.0, -int(device().capabilities().subpixel_precision_bits));
    // The mesh backend snaps each cell's proxy on its own: neighbouring cells' changes need not
    // cancel (interval_comparison.cpp), so each cell's own largest change counts (over the whole
    // box, beyond the square too: a bound).
    const std::vector<double> cells = reference::snapping_variation_image(box, camera, kW, kH, 2.0 * snap);
    Check c;
    double tau_max = 0.0;
    for (uint32_t y = 0; y < kH; ++y)
      for (uint32_t x = 0; x < kW; ++x) tau_max = std::max(tau_max, chord(camera, s, x + 0.5, y + 0.5).tau);
    for (uint32_t y = 0; y < kH; ++y)
      for (uint32_t x = 0; x < kW; ++x) {
        const size_t i = size_t(y) * kW + x;
        const Chord centre = chord(camera, s, x + 0.5, y + 0.5);
        bool edge = false;
        double change = 0.0;
        for (const auto& [dx, dy] : {std::pair{0.75, 0.0}, {-0.75, 0.0}, {0.0, 0.75}, {0.0, -0.75}}) {
          const Chord n = chord(camera, s, x + 0.5 + dx, y + 0.5 + dy);
          edge = edge || n.what != centre.what;
          change = std::max(change, std::abs(n.tau - centre.tau) / 0.75);
        }
        if (edge) continue;
        ++c.compared;
        c.covered += centre.tau > 0.0;
        c.ended += centre.what == 3;
        const double expected = quantity == volume::Quantity::OpticalDepth ? centre.tau : std::exp(-centre.tau);
        // exp(-tau) moves by at most tau's error: the same tolerance serves transmittance.
        const double tolerance = std::ldexp(1.0, -16) * std::max(tau_max, 1.0) + 2.0 * snap * change + cells[i];
        const double got = f.volume.quantity[i], error = std::abs(got - expected);
        EXPECT_TRUE(std::isfinite(got));
        if (!(error <= tolerance)) {
          if (c.failures++ == 0)
            c.first = "pixel (" + std::to_string(x) + "," + std::to_string(y) + "): " + std::to_string(got) + ", closed form " +
                      std::to_string(expected) + ", tolerance " + std::to_string(tolerance);
        } else {
          c.worst = std::max(c.worst, error / tolerance);
        }
        // The composite shows the surface (or the sky) through the medium.
        if (quantity == volume::Quantity::Transmittance)
          for (int k = 0; k < 3; ++k) {
            const double want = double(settings.resolve.medium[k]) * (1.0 - got) + got * double(f.surface_rgba[4 * i + k]);
            EXPECT_NEAR(f.display[4 * i + k], want, 1e-6 * std::max(1.0, std::abs(want))) << "pixel " << i;
          }
      }
    return c;
  }
  void expect(const Check& c, const std::string& what) {
    EXPECT_EQ(c.failures, 0u) << what << ": " << c.first;
    EXPECT_GT(c.compared, size_t(kW) * kH / 2) << what;
    std::printf("[ %s ] %zu pixels (%zu through the volume) match the closed form, worst at %.3f of the tolerance\n", what.c_str(),
                c.compared, c.covered, c.worst);
  }
};

Camera outside() { return test::view_of_origin({0.9, 0.6, 4.5}, 45.0); }

// A square inside the box ends the rays that meet it; the others cross the whole box.
TEST_P(MixedFrameTest, ASquareInsideTheVolumeEndsItsRays) {
  const Square inside{0.25, -0.5, 0.6, -0.4, 0.5};
  for (const auto q : {volume::Quantity::OpticalDepth, volume::Quantity::Transmittance}) {
    const Check c = check(outside(), inside, q);
    expect(c, q == volume::Quantity::OpticalDepth ? "inside, optical depth" : "inside, transmittance");
    EXPECT_GT(c.ended, 100u) << "the square must end enough rays for the comparison to tell";
  }
}

// The camera nearly in the square's plane (8 degrees above it): the square a sliver a few pixels
// tall across the view, its depth changing fast from pixel to pixel; each ray still ends where it
// meets it.
TEST_P(MixedFrameTest, AGrazingSquareEndsTheRaysItMeets) {
  Camera c;
  c.eye = {4.5, 0.3, 0.9};
  c.target = {0.0, 0.0, 0.25};
  c.fovy_degrees = 45.0;
  c.near_distance = 0.1;
  const Check check_grazing = check(c, {0.25, -0.9, 0.9, -0.8, 0.8}, volume::Quantity::OpticalDepth);
  expect(check_grazing, "grazing");
  EXPECT_GT(check_grazing.ended, 20u) << "the sliver must end enough rays for the comparison to tell";
}

// Entirely in front of the volume: zero where it covers; entirely behind: the full chord.
TEST_P(MixedFrameTest, ASquareInFrontHidesTheVolumeAndOneBehindHidesNothing) {
  expect(check(outside(), {1.5, -0.5, 0.6, -0.4, 0.5}, volume::Quantity::OpticalDepth), "in front");
  expect(check(outside(), {-1.5, -2.0, 2.0, -2.0, 2.0}, volume::Quantity::OpticalDepth), "behind");
}

// The camera inside the volume, looking at a square: the chord runs from the near plane.
TEST_P(MixedFrameTest, TheCameraInsideTheVolumeSeesUpToTheSquare) {
  Camera c;
  c.eye = {0.1, 0.05, 0.6};
  c.target = {0.0, 0.0, -1.0};
  c.fovy_degrees = 60.0;
  c.near_distance = 0.01;
  expect(check(c, {-0.5, -0.6, 0.5, -0.5, 0.4}, volume::Quantity::OpticalDepth), "camera inside");
}

// What cannot end at a surface is refused by name, as is a depth limit of the caller's own.
TEST_P(MixedFrameTest, WhatFollowsNoDepthLimitIsRefused) {
  const TetMesh box = make_box_mesh(glm::dvec3(-1.0), glm::dvec3(1.0), 2, [](const glm::dvec3&) { return kSigma; });
  mixed::MixedRenderer renderer(device(), box, square_scene({0.25, -0.5, 0.6, -0.4, 0.5}));
  frame::FrameSettings settings = settings_on_backend();
  settings.resolve.quantity = volume::Quantity::Isosurface;
  EXPECT_THROW(renderer.render(outside(), settings, {kW, kH}), InputError);
  settings.resolve.quantity = volume::Quantity::OpticalDepth;
  settings.resolve.depth_limit = std::make_shared<const std::vector<float>>(size_t(kW) * kH, 1.0f);
  EXPECT_THROW(renderer.render(outside(), settings, {kW, kH}), InputError);
}

PRISMOID_ON_BOTH_BACKENDS(MixedFrameTest);

}  // namespace
}  // namespace prismoid
