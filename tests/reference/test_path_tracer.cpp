// The CPU path tracer against closed forms, independent quadrature and itself. Tolerances are
// statistical: a pixel's estimate has standard error se = sqrt(sample variance / N), and a
// value is accepted within k se of its expectation (k = 5 per pixel: over ~10^3 pixel-channels
// a false failure has probability ~ 10^-3; the seeds are fixed, so a pass is reproducible);
// averages over many pixels use k = 4 with the standard error of the average.
//
// The sample variance is a trustworthy se only when the rare outcomes of a pixel's samples
// occur many times among its N samples. Russian roulette makes rare survivors that carry weight
// 1/q (q = 1/16 after four reflections in the A = 0.5 furnace: with 64 samples, 1.6% of pixels
// see none, and their mean and variance are both low); a specular lobe that loses 3% of its
// samples below the horizon is a Bernoulli(0.03) event. So per-pixel bounds use either no
// roulette (roulette_after = max_bounces) or enough samples that N q >> 1; roulette itself is
// checked on image averages, where thousands of samples meet the normal approximation.
#include "renderer/reference/path_tracer.hpp"

#include <cmath>
#include <cstdio>
#include <numbers>

#include <glm/geometric.hpp>
#include <gtest/gtest.h>

#include "reference/ggx_albedo.hpp"
#include "renderer/metrics/image_error.hpp"
#include "renderer/reference/tet_ray.hpp"
#include "scene/generators.hpp"
#include "scene/input_error.hpp"
#include "scene/surface_generators.hpp"

namespace prismoid::reference {
namespace {

constexpr double kPi = std::numbers::pi;

PathTracerSettings settings_of(uint32_t size, uint32_t spp, uint32_t max_bounces, uint64_t seed = 1) {
  PathTracerSettings s;
  s.width = size;
  s.height = size;
  s.samples_per_pixel = spp;
  s.max_bounces = max_bounces;
  s.seed = seed;
  return s;
}

bool finite(const glm::dvec3& v) { return std::isfinite(v.x) && std::isfinite(v.y) && std::isfinite(v.z); }

void expect_clean(const PathTracedImage& image) {
  EXPECT_EQ(image.counts.non_finite, 0u);
  EXPECT_EQ(image.counts.zero_pdf, 0u);
  for (size_t p = 0; p < image.mean.size(); ++p) {
    ASSERT_TRUE(finite(image.mean[p]) && finite(image.variance[p])) << "pixel " << p;
    ASSERT_GE(std::min(image.variance[p].x, std::min(image.variance[p].y, image.variance[p].z)), 0.0);
  }
}

// The average over all pixels of one channel and its standard error (pixels are independent).
struct Average {
  double mean = 0.0, se = 0.0;
};
Average image_average(const PathTracedImage& image, int channel) {
  Average a;
  double var = 0.0;
  for (size_t p = 0; p < image.mean.size(); ++p) {
    a.mean += image.mean[p][channel];
    var += image.variance[p][channel] / image.samples_per_pixel;
  }
  const double n = double(image.mean.size());
  a.mean /= n;
  a.se = std::sqrt(var) / n;
  return a;
}

// The pixel-centre rays of the camera, as the path tracer makes them with jitter off.
std::vector<SurfaceRay> pixel_rays(const Camera& camera, uint32_t width, uint32_t height) {
  std::vector<SurfaceRay> rays;
  const glm::dvec3 forward = glm::normalize(camera.target - camera.eye);
  for (uint32_t y = 0; y < height; ++y)
    for (uint32_t x = 0; x < width; ++x) {
      const glm::dvec3 d = ray_direction(camera, width, height, x + 0.5, y + 0.5);
      rays.push_back({camera.eye, d, camera.near_distance / glm::dot(d, forward)});
    }
  return rays;
}

// Gauss-Legendre nodes and weights on [0, 1] (Newton's iteration on P_n).
void gauss_legendre(int n, std::vector<double>& x, std::vector<double>& w) {
  x.assign(size_t(n), 0.0);
  w.assign(size_t(n), 0.0);
  for (int i = 0; i < n; ++i) {
    double z = std::cos(kPi * (i + 0.75) / (n + 0.5)), dp = 0.0;
    for (int iter = 0; iter < 100; ++iter) {
      double p0 = 1.0, p1 = z;
      for (int k = 2; k <= n; ++k) {
        const double p2 = ((2.0 * k - 1.0) * z * p1 - (k - 1.0) * p0) / k;
        p0 = p1;
        p1 = p2;
      }
      dp = n * (z * p1 - p0) / (z * z - 1.0);
      const double dz = p1 / dp;
      z -= dz;
      if (std::abs(dz) < 1e-16) break;
    }
    x[size_t(i)] = 0.5 * (1.0 - z);
    w[size_t(i)] = 1.0 / ((1.0 - z * z) * dp * dp);  // 2 / ((1 - z^2) P'^2), halved for [0, 1]
  }
}

// ---------------------------------------------------------------------------------------------
// Furnace: closed, uniformly emitting diffuse enclosure; radiance Le / (1 - A) everywhere.

// The depth cap D removes the paths with more than D reflections: the estimator's expectation
// is Le (1 - A^(D+1)) / (1 - A), below the closed form by Le A^(D+1) / (1 - A).
double furnace_truncated(double albedo, double le, uint32_t depth) {
  return le * (1.0 - std::pow(albedo, depth + 1.0)) / (1.0 - albedo);
}

TEST(PathTracer, FurnaceConvergesToItsClosedForm) {
  for (const auto& [albedo, depth] : {std::pair{0.5, 20u}, std::pair{0.8, 40u}}) {
    const double le = 1.5;
    const SurfaceScene scene = make_furnace(albedo, le, 2);
    PathTracerSettings settings = settings_of(12, 64, depth);
    settings.roulette_after = depth;  // no roulette: per-pixel bounds (see the top of this file)
    const PathTracedImage image = path_trace(scene, scene.camera, settings);
    expect_clean(image);
    EXPECT_EQ(image.counts.backfacing_normals, 0u);
    const double exact = furnace_radiance(albedo, le);
    const double expected = furnace_truncated(albedo, le, depth);
    const double bias = le * std::pow(albedo, depth + 1.0) / (1.0 - albedo);
    EXPECT_NEAR(exact - expected, bias, 1e-12);
    EXPECT_LT(bias, 2e-4 * exact);  // the stated bias at these depths
    double worst = 0.0;
    for (size_t p = 0; p < image.mean.size(); ++p)
      for (int c = 0; c < 3; ++c) {
        const double se = image.standard_error(p)[c];
        ASSERT_GT(se, 0.0);  // a noisy estimate: the bound below is a real one
        EXPECT_NEAR(image.mean[p][c], expected, 5.0 * se) << "pixel " << p << " albedo " << albedo;
        EXPECT_NEAR(image.mean[p][c], exact, 5.0 * se + bias) << "pixel " << p << " albedo " << albedo;
        worst = std::max(worst, std::abs(image.mean[p][c] - expected) / se);
      }
    const Average all = image_average(image, 1);
    EXPECT_NEAR(all.mean, expected, 4.0 * all.se);
    std::printf("furnace A=%.1f Le=%.1f D=%u: closed form %.6f, truncated %.6f (bias %.1e), image mean %.6f +- %.6f (se), "
                "worst pixel %.2f se, %.3f s\n",
                albedo, le, depth, exact, expected, bias, all.mean, all.se, worst, image.seconds);
  }
}

TEST(PathTracer, RussianRouletteLeavesTheFurnaceUnbiased) {
  // Roulette after 3 reflections (the default), survival = the largest throughput channel:
  // unbiased, so the image average meets the closed form; with 1024 samples per pixel every
  // pixel sees enough survivors for its own bound too.
  const double albedo = 0.5, le = 1.0, exact = furnace_radiance(albedo, le);
  const uint32_t depth = 40;
  const double expected = furnace_truncated(albedo, le, depth);  // within 1e-12 of exact
  const SurfaceScene scene = make_furnace(albedo, le, 2);
  const PathTracedImage wide = path_trace(scene, scene.camera, settings_of(32, 32, depth, 17));
  expect_clean(wide);
  const Average a = image_average(wide, 0);
  EXPECT_NEAR(a.mean, expected, 4.0 * a.se);
  const PathTracedImage deep = path_trace(scene, scene.camera, settings_of(8, 1024, depth, 18));
  expect_clean(deep);
  for (size_t p = 0; p < deep.mean.size(); ++p) EXPECT_NEAR(deep.mean[p].y, expected, 5.0 * deep.standard_error(p).y);
  std::printf("furnace A=0.5 with roulette: image mean %.5f +- %.5f (exact %.1f), %.3f + %.3f s\n", a.mean, a.se, exact, wide.seconds,
              deep.seconds);
}

TEST(PathTracer, FurnaceDepthCapGivesTheStatedTruncation) {
  const SurfaceScene scene = make_furnace(0.5, 1.0, 2);
  // D = 0: only the emission seen directly, exactly 1 in every sample.
  const PathTracedImage direct = path_trace(scene, scene.camera, settings_of(8, 8, 0));
  for (size_t p = 0; p < direct.mean.size(); ++p) {
    EXPECT_EQ(direct.mean[p], glm::dvec3(1.0));
    EXPECT_EQ(direct.variance[p], glm::dvec3(0.0));
  }
  // D = 2: 1 + 1/2 + 1/4 = 1.75, short of the closed form 2 by Le A^3 / (1 - A) = 0.25.
  const PathTracedImage capped = path_trace(scene, scene.camera, settings_of(16, 64, 2));
  expect_clean(capped);
  const Average a = image_average(capped, 0);
  EXPECT_NEAR(a.mean, 1.75, 4.0 * a.se);
  EXPECT_GT(std::abs(a.mean - 2.0), 20.0 * a.se);  // the truncation is resolved, not hidden in noise
  std::printf("furnace A=0.5 D=2: %.6f +- %.6f, expected 1.75 (closed form 2)\n", a.mean, a.se);
}

TEST(PathTracer, AllThreeEstimatorsAgreeInTheFurnace) {
  // Light sampling alone, BSDF sampling alone and their MIS combination are different
  // estimators of the same integral; a wrong MIS weight or light pdf separates them. Without
  // roulette, BSDF sampling alone is exact here (every direction finds the emission, weight A),
  // which checks the depth cap to rounding.
  const SurfaceScene scene = make_furnace(0.6, 1.0, 2);
  const uint32_t depth = 20;
  const double expected = furnace_truncated(0.6, 1.0, depth);
  for (LightSampling mode : {LightSampling::Mis, LightSampling::BsdfOnly, LightSampling::LightOnly}) {
    PathTracerSettings s = settings_of(10, 64, depth, 7);
    s.roulette_after = s.max_bounces;  // per-pixel bounds: no roulette
    s.light_sampling = mode;
    const PathTracedImage image = path_trace(scene, scene.camera, s);
    expect_clean(image);
    const Average a = image_average(image, 2);
    EXPECT_NEAR(a.mean, expected, 4.0 * a.se + 1e-12) << "mode " << int(mode);
    for (size_t p = 0; p < image.mean.size(); ++p)
      EXPECT_NEAR(image.mean[p].z, expected, 5.0 * image.standard_error(p).z + 1e-12) << "mode " << int(mode);
    if (mode == LightSampling::BsdfOnly) {
      EXPECT_LT(image.variance[0].x, 1e-24);  // every sample the same sum, up to rounding
    }
  }
}

// ---------------------------------------------------------------------------------------------
// White furnace with GGX: an inward-facing cube of uniform emission 1, albedo 0, F0 = 1. With
// one reflection the radiance is 1 + E(theta_o): emission plus the GGX lobe's directional
// albedo under uniform incident radiance, which single scattering keeps below 1.

SurfaceScene ggx_cube(double roughness) {
  SurfaceScene s;
  s.name = "ggx cube";
  s.materials = {{"mirror-ish", glm::dvec3(0.0), glm::dvec3(1.0), roughness, glm::dvec3(1.0)}};
  SceneMesh m;
  for (int axis = 0; axis < 3; ++axis)
    for (double side : {-1.0, 1.0}) {
      const int u = (axis + 1) % 3, v = (axis + 2) % 3;
      const auto base = static_cast<uint32_t>(m.positions.size());
      for (const auto& [a, b] : {std::pair{-1.0, -1.0}, std::pair{1.0, -1.0}, std::pair{1.0, 1.0}, std::pair{-1.0, 1.0}}) {
        glm::dvec3 p(0.0);
        p[axis] = side;
        p[u] = a;
        p[v] = b;
        m.positions.push_back(p);
      }
      for (std::array<uint32_t, 3> t : {std::array<uint32_t, 3>{base, base + 1, base + 2}, {base, base + 2, base + 3}}) {
        const glm::dvec3 n = glm::cross(m.positions[t[1]] - m.positions[t[0]], m.positions[t[2]] - m.positions[t[0]]);
        if (n[axis] * side > 0.0) std::swap(t[1], t[2]);  // face inwards
        m.triangles.push_back(t);
      }
    }
  s.meshes.push_back(m);
  s.camera.eye = {0.35, -0.25, 0.4};
  s.camera.target = {1.0, 0.8, -1.0};
  s.camera.fovy_degrees = 100.0;
  s.camera.near_distance = 1e-3;
  return s;
}

TEST(PathTracer, GgxWhiteFurnaceLosesOnlyTheSingleScatteringEnergy) {
  for (double roughness : {0.3, 0.6, 1.0}) {
    const SurfaceScene scene = ggx_cube(roughness);
    // 1024 samples: the few percent of specular samples lost below the horizon (a Bernoulli
    // event) occur tens of times per pixel, so each pixel's sample variance is reliable.
    PathTracerSettings s = settings_of(16, 1024, 1, 3);
    s.jitter = false;
    const PathTracedImage image = path_trace(scene, scene.camera, s);
    expect_clean(image);
    const double alpha = std::max(roughness * roughness, kMinGgxAlpha);
    const auto rays = pixel_rays(scene.camera, s.width, s.height);
    double worst = 0.0, min_albedo = 1.0, sum_diff = 0.0, sum_var = 0.0;
    for (size_t p = 0; p < rays.size(); ++p) {
      // Which face the pixel ray leaves the cube through (slabs), and its cosine there.
      const glm::dvec3& o = rays[p].origin;
      const glm::dvec3& d = rays[p].direction;
      double t_exit = std::numeric_limits<double>::infinity(), cos_o = 0.0;
      for (int i = 0; i < 3; ++i) {
        if (d[i] == 0.0) continue;
        const double t = ((d[i] > 0.0 ? 1.0 : -1.0) - o[i]) / d[i];
        if (t < t_exit) {
          t_exit = t;
          cos_o = std::abs(d[i]);
        }
      }
      const double e = test::ggx_albedo_quadrature(cos_o, alpha, 1000, 128);
      min_albedo = std::min(min_albedo, e);
      const double se = image.standard_error(p).x;
      // Quadrature error at this resolution is below 1e-3 (SurfaceBsdf tests compare resolutions).
      EXPECT_NEAR(image.mean[p].x, 1.0 + e, 5.0 * se + 1e-3) << "pixel " << p << " roughness " << roughness;
      EXPECT_LE(image.mean[p].x, 2.0 + 5.0 * se) << "more light reflected than arrives";
      worst = std::max(worst, std::abs(image.mean[p].x - 1.0 - e) / se);
      sum_diff += image.mean[p].x - 1.0 - e;
      sum_var += se * se;
    }
    const double n = double(rays.size());
    EXPECT_NEAR(sum_diff / n, 0.0, 4.0 * std::sqrt(sum_var) / n + 1e-3);
    std::printf("GGX white furnace r=%.1f: largest single-scattering loss in view %.4f, mean(image - (1+E)) %.2e, "
                "se of that %.2e, worst pixel %.2f se, %.3f s\n",
                roughness, 1.0 - min_albedo, sum_diff / n, std::sqrt(sum_var) / n, worst, image.seconds);
  }
}

// ---------------------------------------------------------------------------------------------
// Cornell box, direct light only: equals the integral over the light quad, by Gauss-Legendre.

TEST(PathTracer, CornellDirectLightMatchesQuadratureOverTheLight) {
  const SurfaceScene scene = make_cornell_box();
  const Camera& camera = scene.camera;
  PathTracerSettings s = settings_of(20, 512, 1, 5);
  s.jitter = false;
  const PathTracedImage image = path_trace(scene, camera, s);
  expect_clean(image);
  const auto rays = pixel_rays(camera, s.width, s.height);
  const auto hits = first_hits(scene, rays);

  const SceneMesh& light = scene.meshes.back();
  const glm::dvec3 le = scene.materials[light.material].emission;
  const glm::dvec3 corner = light.positions[0];                      // (343, y, 227)
  const glm::dvec3 edge_u = light.positions[1] - light.positions[0];  // +105 along z
  const glm::dvec3 edge_v = light.positions[3] - light.positions[0];  // -130 along x
  const double area = glm::length(edge_u) * glm::length(edge_v);
  const glm::dvec3 light_normal(0.0, -1.0, 0.0);
  std::vector<double> x24, w24, x48, w48;
  gauss_legendre(24, x24, w24);
  gauss_legendre(48, x48, w48);
  // Unoccluded irradiance-weighted integral over the light: (1/pi) int Le cos_x cos_y / d^2 dA.
  auto integral = [&](const glm::dvec3& x, const glm::dvec3& n, const std::vector<double>& nodes,
                      const std::vector<double>& weights, bool& smooth) {
    double sum = 0.0;
    smooth = true;
    for (size_t i = 0; i < nodes.size(); ++i)
      for (size_t j = 0; j < nodes.size(); ++j) {
        const glm::dvec3 y = corner + nodes[i] * edge_u + nodes[j] * edge_v;
        const glm::dvec3 to = y - x;
        const double d2 = glm::dot(to, to), d = std::sqrt(d2);
        const double cos_x = glm::dot(n, to) / d, cos_y = -glm::dot(light_normal, to) / d;
        if (cos_x <= 0.0 || cos_y <= 0.0) smooth = false;
        sum += weights[i] * weights[j] * std::max(cos_x, 0.0) * std::max(cos_y, 0.0) / d2;
      }
    return sum * area / kPi;
  };

  // Visibility of the 24 x 24 nodes from every pixel's point, by shadow rays.
  std::vector<SurfaceRay> shadow;
  std::vector<glm::dvec3> normals(hits.size());
  for (size_t p = 0; p < hits.size(); ++p) {
    if (!hits[p].hit) continue;
    normals[p] = glm::dot(hits[p].normal, rays[p].direction) < 0.0 ? hits[p].normal : -hits[p].normal;
    const glm::dvec3 x = hits[p].position + 1e-6 * normals[p];
    for (double u : x24)
      for (double v : x24) shadow.push_back({x, corner + u * edge_u + v * edge_v - x, 0.0});
  }
  const auto blockers = first_hits(scene, shadow);
  const uint32_t light_mesh = static_cast<uint32_t>(scene.meshes.size() - 1);
  size_t compared = 0, zero_checked = 0, k = 0;
  double worst = 0.0, worst_rel = 0.0;
  for (size_t p = 0; p < hits.size(); ++p) {
    if (!hits[p].hit) {
      EXPECT_EQ(image.mean[p], glm::dvec3(0.0));  // out of the open front: black sky
      continue;
    }
    size_t visible = 0;
    for (size_t i = 0; i < x24.size() * x24.size(); ++i, ++k)
      if (!blockers[k].hit || blockers[k].t >= 1.0 - 1e-9 || blockers[k].mesh == light_mesh) ++visible;
    if (hits[p].mesh == light_mesh) continue;  // the light itself: its emission
    const glm::dvec3 albedo = scene.materials[scene.meshes[hits[p].mesh].material].albedo;
    if (hits[p].mesh == 1) {  // the ceiling sees only the light's back: exactly dark
      EXPECT_EQ(image.mean[p], glm::dvec3(0.0)) << "pixel " << p;
      ++zero_checked;
      continue;
    }
    if (visible != x24.size() * x24.size()) continue;  // (partly) shadowed: no smooth quadrature
    bool smooth24 = false, smooth48 = false;
    const double q24 = integral(hits[p].position, normals[p], x24, w24, smooth24);
    const double q48 = integral(hits[p].position, normals[p], x48, w48, smooth48);
    if (!smooth24 || !smooth48 || std::abs(q24 - q48) > 1e-7 * q48) continue;  // quadrature not converged here
    ++compared;
    for (int c = 0; c < 3; ++c) {
      const double expected = albedo[c] * le[c] * q48;
      const double se = image.standard_error(p)[c];
      EXPECT_NEAR(image.mean[p][c], expected, 5.0 * se + 1e-9 * expected) << "pixel " << p << " channel " << c;
      if (se > 0.0) worst = std::max(worst, std::abs(image.mean[p][c] - expected) / se);
      worst_rel = std::max(worst_rel, std::abs(image.mean[p][c] - expected) / expected);
    }
  }
  EXPECT_GT(compared, 150u);  // most of the 400 pixels: walls, floor and block tops in full view of the light
  EXPECT_GT(zero_checked, 10u);
  std::printf("Cornell direct light: %zu pixels against quadrature, worst %.2f se, worst relative %.4f; %zu ceiling "
              "pixels exactly 0; %.3f s\n",
              compared, worst, worst_rel, zero_checked, image.seconds);
}

TEST(PathTracer, CornellEstimatorsAgree) {
  // Global illumination (4 reflections) in the Cornell box by MIS, light sampling alone and
  // BSDF sampling alone: the same expectation. BSDF sampling alone is noisy and heavy-tailed
  // here (the light subtends ~1% of the hemisphere), so it is compared on the image average.
  const SurfaceScene scene = make_cornell_box();
  PathTracerSettings s = settings_of(12, 256, 4, 9);
  const PathTracedImage mis = path_trace(scene, scene.camera, s);
  s.light_sampling = LightSampling::LightOnly;
  s.seed = 10;
  const PathTracedImage light_only = path_trace(scene, scene.camera, s);
  s.light_sampling = LightSampling::BsdfOnly;
  s.seed = 11;
  const PathTracedImage bsdf_only = path_trace(scene, scene.camera, s);
  for (const auto* image : {&mis, &light_only, &bsdf_only}) expect_clean(*image);
  for (size_t p = 0; p < mis.mean.size(); ++p)
    for (int c = 0; c < 3; ++c) {
      const double se = std::hypot(mis.standard_error(p)[c], light_only.standard_error(p)[c]);
      EXPECT_NEAR(mis.mean[p][c], light_only.mean[p][c], 5.0 * se) << "pixel " << p;
    }
  for (int c = 0; c < 3; ++c) {
    const Average a = image_average(mis, c), b = image_average(light_only, c), d = image_average(bsdf_only, c);
    EXPECT_NEAR(a.mean, b.mean, 4.0 * std::hypot(a.se, b.se)) << "channel " << c;
    EXPECT_NEAR(a.mean, d.mean, 4.0 * std::hypot(a.se, d.se)) << "channel " << c;
    if (c == 0)
      std::printf("Cornell average red: MIS %.5f +- %.5f, light only %.5f +- %.5f, BSDF only %.5f +- %.5f\n", a.mean, a.se,
                  b.mean, b.se, d.mean, d.se);
  }
}

TEST(PathTracer, RmseHalvesWhenSamplesQuadruple) {
  // Against an independent 1024-sample render, the expected squared error of an N-sample image
  // is mean(variance) (1/N + 1/1024); N = 16 -> 64 should divide the RMSE by
  // sqrt((1/16 + 1/1024) / (1/64 + 1/1024)) = 1.96. Pixel centres only and no roulette, so
  // that no pixel's error is dominated by rare samples (the light's edge in a jittered pixel,
  // a roulette survivor) and the RMSE over 1200 pixel-channels is a steady estimate.
  const SurfaceScene scene = make_cornell_box();
  auto settings = [](uint32_t spp, uint64_t seed) {
    PathTracerSettings s = settings_of(20, spp, 5, seed);
    s.roulette_after = s.max_bounces;
    s.jitter = false;
    return s;
  };
  const PathTracedImage reference = path_trace(scene, scene.camera, settings(1024, 100));
  const PathTracedImage n16 = path_trace(scene, scene.camera, settings(16, 200));
  const PathTracedImage n64 = path_trace(scene, scene.camera, settings(64, 300));
  double mean_variance = 0.0;
  for (const auto& v : reference.variance) mean_variance += (v.x + v.y + v.z) / 3.0;
  mean_variance /= double(reference.variance.size());
  const auto rgb_ref = reference.rgb();
  const double rmse16 = image_error(n16.rgb(), rgb_ref, 1.0).rmse;
  const double rmse64 = image_error(n64.rgb(), rgb_ref, 1.0).rmse;
  const double predicted16 = std::sqrt(mean_variance * (1.0 / 16 + 1.0 / 1024));
  const double predicted64 = std::sqrt(mean_variance * (1.0 / 64 + 1.0 / 1024));
  // The measured RMSE is itself an estimate from 1200 squared errors (relative spread of a few
  // percent for these tails); 20% and a ratio within 0.3 leave room for that and fail for an
  // estimator whose error does not fall as 1/sqrt(N).
  EXPECT_NEAR(rmse16 / predicted16, 1.0, 0.2);
  EXPECT_NEAR(rmse64 / predicted64, 1.0, 0.2);
  EXPECT_NEAR(rmse16 / rmse64, predicted16 / predicted64, 0.3);
  std::printf("RMSE vs 1024 spp: 16 spp %.5f (predicted %.5f), 64 spp %.5f (predicted %.5f), ratio %.3f (predicted %.3f); "
              "reference %.2f s\n",
              rmse16, predicted16, rmse64, predicted64, rmse16 / rmse64, predicted16 / predicted64, reference.seconds);
}

TEST(PathTracer, ImageDoesNotDependOnTheThreadCount) {
  const SurfaceScene scene = make_cornell_box();
  PathTracerSettings s = settings_of(10, 8, 8, 4);
  s.threads = 1;
  const PathTracedImage one = path_trace(scene, scene.camera, s);
  s.threads = 3;
  const PathTracedImage three = path_trace(scene, scene.camera, s);
  EXPECT_EQ(one.mean, three.mean);
  EXPECT_EQ(one.variance, three.variance);
  EXPECT_EQ(one.counts.rays, three.counts.rays);
  s.seed = 5;
  EXPECT_NE(path_trace(scene, scene.camera, s).mean, one.mean);  // the seed matters
}

// ---------------------------------------------------------------------------------------------
// Robustness: far from the origin, degenerate triangles, zeros.

TEST(PathTracer, FarFromTheOriginGivesTheSameImage) {
  const SurfaceScene scene = make_cornell_box();
  SurfaceScene far = scene;
  const glm::dvec3 offset(1e6, -1e6, 1e6);
  for (auto& m : far.meshes)
    for (auto& p : m.positions) p += offset;
  far.camera.eye += offset;
  far.camera.target += offset;
  const PathTracerSettings s = settings_of(12, 32, 8, 21);
  const PathTracedImage a = path_trace(scene, scene.camera, s);
  const PathTracedImage b = path_trace(far, far.camera, s);
  expect_clean(b);
  double largest_relative = 0.0;
  for (size_t p = 0; p < a.mean.size(); ++p)
    for (int c = 0; c < 3; ++c) {
      const double se = std::hypot(a.standard_error(p)[c], b.standard_error(p)[c]);
      EXPECT_NEAR(a.mean[p][c], b.mean[p][c], 5.0 * se + 1e-12) << "pixel " << p;
      if (a.mean[p][c] > 0.0) largest_relative = std::max(largest_relative, std::abs(a.mean[p][c] - b.mean[p][c]) / a.mean[p][c]);
    }
  // Same random numbers, so the same paths up to the rounding of the moved coordinates
  // (1e6 * 2^-52 ~ 2e-10) and the ray offsets, which grow with the coordinates (1e-10 of them:
  // 1e-4 mm here against 1e-7 mm at the origin, in a 550 mm box): the images agree to ~1e-6,
  // far more closely than their noise (~1e-2).
  const Average ma = image_average(a, 0), mb = image_average(b, 0);
  EXPECT_NEAR(ma.mean, mb.mean, 1e-5 * ma.mean);
  EXPECT_LT(largest_relative, 1e-3);
  std::printf("far from origin (1e6): image means %.9f vs %.9f, largest pixel relative difference %.2e\n", ma.mean, mb.mean,
              largest_relative);
}

TEST(PathTracer, DegenerateTrianglesAreSkippedWithoutChangingTheImage) {
  const SurfaceScene scene = make_cornell_box();
  SurfaceScene with_junk = scene;
  SceneMesh junk;
  junk.name = "junk";
  junk.positions = {{278, 273, 280}, {278, 273, 280}, {300, 300, 300}, {322, 327, 320}, {100, 100, 100}};
  junk.triangles = {{0, 1, 2}, {0, 2, 3}, {4, 4, 4}};  // repeated vertex, collinear, a point
  junk.material = 3;  // emissive: zero-area emitters must not become lights
  with_junk.meshes.push_back(junk);
  const PathTracerSettings s = settings_of(10, 16, 6, 2);
  const PathTracedImage a = path_trace(scene, scene.camera, s);
  const PathTracedImage b = path_trace(with_junk, with_junk.camera, s);
  expect_clean(b);
  EXPECT_EQ(b.counts.degenerate_triangles, 3u);
  EXPECT_EQ(a.counts.degenerate_triangles, 0u);
  EXPECT_EQ(a.mean, b.mean);
  EXPECT_EQ(a.variance, b.variance);

  // Slivers of tiny but non-zero area (one emissive) are real triangles: no NaN, no infinity.
  SurfaceScene slivers = scene;
  SceneMesh thin;
  thin.positions = {{200, 200, 200}, {400, 200, 200}, {300, 200 + 1e-12, 200}, {250, 300, 300}, {260, 300, 300}, {255, 300, 300 + 1e-13}};
  thin.triangles = {{0, 1, 2}, {3, 4, 5}};
  thin.material = 3;
  slivers.meshes.push_back(thin);
  const PathTracedImage c = path_trace(slivers, slivers.camera, s);
  expect_clean(c);
}

TEST(PathTracer, ZeroEmissionAndZeroAlbedoGiveExactZeros) {
  // No power anywhere: every pixel exactly 0, no NaN from an empty light list.
  SurfaceScene dark = make_cornell_box();
  dark.materials[3].emission = glm::dvec3(0.0);
  const PathTracedImage d = path_trace(dark, dark.camera, settings_of(10, 8, 8));
  expect_clean(d);
  for (size_t p = 0; p < d.mean.size(); ++p) {
    EXPECT_EQ(d.mean[p], glm::dvec3(0.0));
    EXPECT_EQ(d.variance[p], glm::dvec3(0.0));
  }
  // Black surfaces: only the light itself is seen, with exactly its emission.
  SurfaceScene black = make_cornell_box();
  for (auto& m : black.materials) m.albedo = glm::dvec3(0.0);
  PathTracerSettings s = settings_of(64, 2, 8);  // the light is ~2 pixel rows high at this size
  s.jitter = false;
  const PathTracedImage b = path_trace(black, black.camera, s);
  expect_clean(b);
  const auto hits = first_hits(black, pixel_rays(black.camera, s.width, s.height));
  size_t light_pixels = 0;
  for (size_t p = 0; p < hits.size(); ++p) {
    const bool light = hits[p].hit && hits[p].mesh == black.meshes.size() - 1;
    light_pixels += light;
    EXPECT_EQ(b.mean[p], light ? glm::dvec3(17.0, 12.0, 4.0) : glm::dvec3(0.0)) << "pixel " << p;
  }
  EXPECT_GT(light_pixels, 0u);
}

// A white-ish quad [-2, 2]^2 in z = 0 under a point light at height 1, with a small occluding
// square at z = 0.5: closed-form irradiance where lit, exactly 0 in the umbra.
TEST(PathTracer, PointLightGivesClosedFormIrradianceAndExactShadows) {
  SurfaceScene s;
  s.name = "point light";
  s.materials = {{"grey", glm::dvec3(0.5, 0.4, 0.3), glm::dvec3(0.0), 1.0, glm::dvec3(0.0)}};
  SceneMesh floor, blocker;
  floor.positions = {{-2, -2, 0}, {2, -2, 0}, {2, 2, 0}, {-2, 2, 0}};
  floor.triangles = {{0, 1, 2}, {0, 2, 3}};
  blocker.positions = {{-0.25, -0.25, 0.5}, {0.25, -0.25, 0.5}, {0.25, 0.25, 0.5}, {-0.25, 0.25, 0.5}};
  blocker.triangles = {{0, 1, 2}, {0, 2, 3}};
  s.meshes = {floor, blocker};
  const glm::dvec3 intensity(2.0, 3.0, 4.0);
  s.point_lights.push_back({{0.0, 0.0, 1.0}, intensity});
  s.camera.eye = {0.3, -3.0, 3.0};
  s.camera.target = {0.0, 0.0, 0.0};
  s.camera.fovy_degrees = 60.0;
  PathTracerSettings settings = settings_of(32, 2, 1);  // direct light only: a closed form
  settings.jitter = false;
  const PathTracedImage image = path_trace(s, s.camera, settings);
  expect_clean(image);
  const auto rays = pixel_rays(s.camera, settings.width, settings.height);
  size_t lit = 0, umbra = 0;
  for (size_t p = 0; p < rays.size(); ++p) {
    const glm::dvec3& o = rays[p].origin;
    const glm::dvec3& d = rays[p].direction;
    const glm::dvec3 on_blocker = o + d * ((0.5 - o.z) / d.z);
    if (std::abs(on_blocker.x) <= 0.26 && std::abs(on_blocker.y) <= 0.26) continue;  // sees the blocker
    const glm::dvec3 x = o + d * (-o.z / d.z);
    if (std::abs(x.x) > 2.0 || std::abs(x.y) > 2.0) {
      EXPECT_EQ(image.mean[p], glm::dvec3(0.0));
      continue;
    }
    // The segment to the light crosses z = 0.5 at (x + light) / 2: inside the blocker iff
    // |x|, |y| < 0.5. Keep away from the penumbra-free edge by a margin.
    const double m = std::max(std::abs(x.x), std::abs(x.y));
    if (m < 0.49) {
      EXPECT_EQ(image.mean[p], glm::dvec3(0.0)) << "pixel " << p << " should be in the umbra";
      ++umbra;
    } else if (m > 0.51) {
      const double r2 = x.x * x.x + x.y * x.y + 1.0;
      const double cos_theta = 1.0 / std::sqrt(r2);
      for (int c = 0; c < 3; ++c) {
        const double expected = s.materials[0].albedo[c] / kPi * intensity[c] * cos_theta / r2;
        EXPECT_NEAR(image.mean[p][c], expected, 1e-10 * expected) << "pixel " << p;
      }
      ++lit;
    }
  }
  EXPECT_GT(lit, 300u);
  EXPECT_GT(umbra, 10u);
}

TEST(PathTracer, DirectionalLightShowsPerVertexAndPerTriangleColours) {
  // Colour linear in position, per vertex: interpolation reproduces it exactly. Light straight
  // down with irradiance pi: radiance = albedo * colour.
  SurfaceScene s;
  s.name = "colours";
  s.materials = {{"white", glm::dvec3(0.8), glm::dvec3(0.0), 1.0, glm::dvec3(0.0)}};
  SceneMesh quad;
  quad.positions = {{-1, -1, 0}, {1, -1, 0}, {1, 1, 0}, {-1, 1, 0}};
  quad.triangles = {{0, 1, 2}, {0, 2, 3}};
  auto colour = [](const glm::dvec3& p) { return glm::dvec3((p.x + 1) / 2, (1 - p.x) / 2, (p.y + 1) / 4); };
  quad.color_binding = ColorBinding::PerVertex;
  for (const auto& p : quad.positions) quad.colors.push_back(colour(p));
  s.meshes = {quad};
  s.directional_lights.push_back({{0.0, 0.0, -1.0}, glm::dvec3(kPi)});
  s.camera.eye = {0.2, -1.5, 2.5};
  s.camera.target = {0.0, 0.0, 0.0};
  s.camera.fovy_degrees = 50.0;
  PathTracerSettings settings = settings_of(24, 2, 2);
  settings.jitter = false;
  const auto rays = pixel_rays(s.camera, settings.width, settings.height);
  const PathTracedImage per_vertex = path_trace(s, s.camera, settings);
  expect_clean(per_vertex);
  s.meshes[0].color_binding = ColorBinding::PerTriangle;
  s.meshes[0].colors = {{1.0, 0.0, 0.0}, {0.0, 0.0, 1.0}};  // below / above the diagonal y = x
  const PathTracedImage per_triangle = path_trace(s, s.camera, settings);
  size_t checked = 0;
  for (size_t p = 0; p < rays.size(); ++p) {
    const glm::dvec3 x = rays[p].origin + rays[p].direction * (-rays[p].origin.z / rays[p].direction.z);
    if (std::abs(x.x) > 0.999 || std::abs(x.y) > 0.999) continue;
    ++checked;
    const glm::dvec3 expected = 0.8 * colour(x);
    for (int c = 0; c < 3; ++c) EXPECT_NEAR(per_vertex.mean[p][c], expected[c], 1e-12) << "pixel " << p;
    if (std::abs(x.x - x.y) > 1e-3) {
      const glm::dvec3 want = x.y < x.x ? glm::dvec3(0.8, 0.0, 0.0) : glm::dvec3(0.0, 0.0, 0.8);
      for (int c = 0; c < 3; ++c) EXPECT_NEAR(per_triangle.mean[p][c], want[c], 1e-12) << "pixel " << p;
    }
  }
  EXPECT_GT(checked, 200u);
}

TEST(PathTracer, DefaultLightingIsNeverBlack) {
  // A surface from a file has no lights; with the rule applied every pixel is lit: the surface
  // by the headlight (from both sides: reflection is two-sided), the background by the sky.
  const SurfaceScene sphere = make_surface_scene(make_icosphere(glm::dvec3(1.0, 2.0, 3.0), 1.0, 2));
  SurfaceMesh back_facing;  // a quad wound away from the camera
  back_facing.name = "back";
  back_facing.points = {{-1, -1, 0}, {-1, 1, 0}, {1, 1, 0}, {1, -1, 0}};
  back_facing.triangles = {{0, 1, 2}, {0, 2, 3}};
  const SurfaceScene quad = make_surface_scene(back_facing);
  for (const SurfaceScene* scene : {&sphere, &quad}) {
    const PathTracedImage dark = path_trace(*scene, scene->camera, settings_of(12, 4, 4));
    for (const auto& m : dark.mean) EXPECT_EQ(m, glm::dvec3(0.0));  // as given: no light at all
    const SurfaceScene lit = with_default_lighting(*scene, scene->camera);
    const PathTracedImage image = path_trace(lit, lit.camera, settings_of(12, 16, 4));
    expect_clean(image);
    for (size_t p = 0; p < image.mean.size(); ++p)
      EXPECT_GT(std::min(image.mean[p].x, std::min(image.mean[p].y, image.mean[p].z)), 0.0) << scene->name << " pixel " << p;
  }
}

TEST(PathTracer, BackfacingShadingNormalsAreCountedAndHarmless) {
  // Per-vertex normals tilted 80 degrees away from the camera: many view directions fall
  // behind them; those points fall back to the geometric normal.
  SurfaceScene s;
  s.name = "tilted normals";
  s.materials = {{"white", glm::dvec3(0.7), glm::dvec3(0.5), 0.4, glm::dvec3(0.0)}};
  SceneMesh quad;
  quad.positions = {{-1, -1, 0}, {1, -1, 0}, {1, 1, 0}, {-1, 1, 0}};
  quad.triangles = {{0, 1, 2}, {0, 2, 3}};
  const glm::dvec3 tilted = glm::normalize(glm::dvec3(0.0, -5.67, 1.0));
  quad.normals.assign(4, tilted);
  s.meshes = {quad};
  s.sky = Sky{glm::dvec3(1.0), glm::dvec3(0.2), {0, 0, 1}};
  s.point_lights.push_back({{0.0, 0.0, 2.0}, glm::dvec3(4.0)});
  s.camera.eye = {0.0, 3.0, 1.0};
  s.camera.target = {0.0, 0.0, 0.0};
  const PathTracedImage image = path_trace(s, s.camera, settings_of(12, 16, 4));
  expect_clean(image);
  EXPECT_GT(image.counts.backfacing_normals, 0u);
}

TEST(PathTracer, RejectsBadInputWithInputError) {
  const SurfaceScene scene = make_furnace(0.5);
  EXPECT_THROW(path_trace(scene, scene.camera, settings_of(0, 4, 4)), InputError);
  EXPECT_THROW(path_trace(scene, scene.camera, settings_of(4, 0, 4)), InputError);
  Camera bad = scene.camera;
  bad.target = bad.eye;
  EXPECT_THROW(path_trace(scene, bad, settings_of(4, 4, 4)), InputError);
  SurfaceScene broken = scene;
  broken.meshes[0].triangles[0][0] = 1u << 30;
  EXPECT_THROW(path_trace(broken, broken.camera, settings_of(4, 4, 4)), InputError);
}

}  // namespace
}  // namespace prismoid::reference
