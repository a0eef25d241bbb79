// The meshlet shading atlas's passes on the GPU (lavapipe, validation on) against the CPU side:
// every seen meshlet gets a block of the size its density asks for (renderer/surface/msa/msa_pass's
// msa_class_for from the GPU's densities, which are the CPU's from the pixel rays), blocks never
// overlap, every shaded texel is the direct-light reference at its chart point's surface point,
// every displayed pixel the bilinear lookup of its block, a still camera shades nothing new, the
// amortization period and the budget do what they say, and where shading is constant per face the
// image is the forward backend's.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <cstring>
#include <memory>

#include <glm/geometric.hpp>

#include "renderer/reference/direct_light.hpp"
#include "renderer/reference/tet_ray.hpp"
#include "renderer/rt/acceleration_structure.hpp"
#include "renderer/surface/forward/forward_pass.hpp"
#include "renderer/surface/msa/msa_pass.hpp"
#include "shaders/shared/msa.h"
#include "scene/surface_generators.hpp"
#include "scene/surface_refine.hpp"
#include "support/gpu_fixture.hpp"
#include "surface/forward_comparison.hpp"
#include "surface/htex_fixture.hpp"
#include "surface/surface_test_scenes.hpp"
#include "surface/texture_space_checks.hpp"

namespace prismoid::test {
namespace {

constexpr uint32_t kW = 96, kH = 72;

surface::MsaSettings unshadowed() {
  surface::MsaSettings s;
  s.shadows = false;
  s.superblocks = 8;
  return s;
}

struct MsaRig {
  MsaRig(const vk::Device& device, SurfaceScene s, const surface::MsaSettings& settings, msa::Clustering clustering = msa::Clustering::NormalCone,
         msa::Parametrization parametrization = msa::Parametrization::Projection)
      : scene(std::move(s)),
        gpu(surface::upload(device, scene)),
        accel(device, scene),
        meshlets(msa::build_meshlets(scene, {.clustering = clustering, .parametrization = parametrization})),
        pass(std::make_unique<surface::MsaPass>(device, meshlets, settings)),
        triangles(scene) {}
  surface::MsaImage render(const vk::Device& device, const Camera& camera) { return surface::render_msa(device, *pass, gpu, accel.tlas(), camera, {kW, kH}); }
  template <typename T>
  std::vector<T> read(const vk::Buffer& buffer) const {
    return read_as<T>(*pass, buffer);
  }
  std::pair<uint32_t, uint32_t> local_triangle(uint32_t global) const { return triangles.local(global); }
  glm::dvec2 chart_point(uint32_t triangle, const glm::dvec3& b) const {
    const auto& c = meshlets.corner_chart[triangle];
    return b.x * c[0] + b.y * c[1] + b.z * c[2];
  }

  SurfaceScene scene;
  surface::GpuSurfaceScene gpu;
  rt::SceneAccel accel;
  msa::MeshletSet meshlets;
  std::unique_ptr<surface::MsaPass> pass;
  TriangleIndex triangles;
};

float as_float(uint32_t bits) {
  float f;
  std::memcpy(&f, &bits, 4);
  return f;
}

glm::dvec3 ray_plane_barycentric(const MsaRig& rig, const Camera& camera, uint32_t triangle, double x, double y) {
  return ray_plane_weights(rig.scene, rig.triangles, triangle, camera, kW, kH, x, y);
}

// The CPU's rule for a block texel: its chart point's triangle (the first in id order that
// contains it), else the nearest within sqrt(2) texels. `ambiguous` when float rounding could
// choose differently (a containment margin or distance tie within 1e-4 texel).
struct TexelChoice {
  uint32_t triangle = PRISMOID_MSA_NONE;
  glm::dvec3 bary{0.0};
  bool ambiguous = false;
};
double segment_distance(const glm::dvec2& q, const glm::dvec2& a, const glm::dvec2& b) {
  const glm::dvec2 ab = b - a;
  const double l = glm::dot(ab, ab);
  const double t = l > 0.0 ? std::clamp(glm::dot(q - a, ab) / l, 0.0, 1.0) : 0.0;
  return glm::length(q - (a + t * ab));
}
// Per-frame charts: the corners' camera depths, and a surface point's depth along the view.
glm::dvec3 corner_depths(const MsaRig& rig, const Camera& camera, uint32_t t) {
  const auto [mesh, local] = rig.local_triangle(t);
  const SceneMesh& m = rig.scene.meshes[mesh];
  glm::dvec3 z;
  for (int k = 0; k < 3; ++k) z[k] = glm::dot(m.positions[m.triangles[local][size_t(k)]] - camera.eye, glm::normalize(camera.target - camera.eye));
  return z;
}
// A perspective chart's image weights to surface weights (w_i / z_i renormalized), and back.
glm::dvec3 surface_weights(const glm::dvec3& w, const glm::dvec3& z) {
  const glm::dvec3 b = w / z;
  return b / (b.x + b.y + b.z);
}
glm::dvec3 image_weights(const glm::dvec3& b, const glm::dvec3& z) {
  const glm::dvec3 w = b * z;
  return w / (w.x + w.y + w.z);
}

// With per-frame charts (`frame`, made for `camera`), the chart corners are the frame's, a
// perspective meshlet's chart weights are turned into surface weights, and of the triangles
// containing the point the nearest along the view is taken (the GPU's rule where the projection
// folds; two at the same depth on the same chart point are the same surface point, as on a shared
// edge, so either is right).
TexelChoice choose(const MsaRig& rig, uint32_t meshlet, const glm::dvec2& q, double s, const msa::FrameCharts* frame = nullptr,
                   const Camera* camera = nullptr) {
  std::vector<uint32_t> tris = rig.meshlets.meshlets[meshlet].triangles;
  std::sort(tris.begin(), tris.end());
  TexelChoice c;
  const double reach = std::sqrt(2.0) / s, margin = 1e-4 / s;
  double best = 1e300, second = 1e300;
  uint32_t nearest = PRISMOID_MSA_NONE;
  glm::dvec3 nearest_bary(0.0);
  double nearest_depth = 1e300;
  for (uint32_t t : tris) {
    const auto& k = frame ? frame->corner_chart[t] : rig.meshlets.corner_chart[t];
    const glm::dvec2 d1 = k[1] - k[0], d2 = k[2] - k[0], r = q - k[0];
    const double det = d1.x * d2.y - d1.y * d2.x;
    if (det == 0.0) continue;
    const double b1 = (r.x * d2.y - r.y * d2.x) / det, b2 = (d1.x * r.y - d1.y * r.x) / det;
    glm::dvec3 w(1.0 - b1 - b2, b1, b2);
    const bool inside = std::min({w.x, w.y, w.z}) >= 0.0;
    if (frame && frame->perspective[meshlet]) w = surface_weights(w, corner_depths(rig, *camera, t));
    if (frame && inside) {  // the nearest containing triangle along the view
      const double depth = glm::dot(w, corner_depths(rig, *camera, t));
      if (c.triangle == PRISMOID_MSA_NONE || depth < nearest_depth) {
        c.triangle = t;
        c.bary = w;
        nearest_depth = depth;
      }
    }
    const double dist = inside ? 0.0 : std::min({segment_distance(q, k[0], k[1]), segment_distance(q, k[1], k[2]), segment_distance(q, k[2], k[0])});
    const double edge = std::min({segment_distance(q, k[0], k[1]), segment_distance(q, k[1], k[2]), segment_distance(q, k[2], k[0])});
    if (inside && c.triangle == PRISMOID_MSA_NONE) {
      c.triangle = t;  // the first containing one in id order
      c.bary = w;
    }
    if (edge < margin && c.triangle != t) c.ambiguous = c.ambiguous || !inside || c.triangle != PRISMOID_MSA_NONE;  // on an edge: rounding decides
    if (dist < best) {
      second = best;
      best = dist;
      nearest = t;
      // The GPU's rule: beyond a triangle's width out, the nearest point of the triangle.
      const double lowest = std::min({w.x, w.y, w.z});
      nearest_bary = w;
      if (lowest < -1.0) {
        glm::dvec3 b = glm::max(w, glm::dvec3(0.0));
        nearest_bary = b / (b.x + b.y + b.z);
      }
      if (std::abs(lowest + 1.0) < 1e-3) c.ambiguous = true;
    } else {
      second = std::min(second, dist);
    }
  }
  if (c.triangle != PRISMOID_MSA_NONE) return c;
  if (std::abs(best - reach) < margin) c.ambiguous = true;  // at the dilation's reach
  if (best <= reach) {
    c.triangle = nearest;
    c.bary = nearest_bary;
    if (second - best < margin) c.ambiguous = true;  // two triangles equally near
  }
  return c;
}


class MsaPassTest : public GpuTest {};

TEST_F(MsaPassTest, EverySeenMeshletGetsADisjointBlockOfTheSizeItsPixelsAskFor) {
  MsaRig rig(device(), sphere_scene({}), unshadowed());
  const Camera camera = rig.scene.camera;
  const surface::MsaImage img = rig.render(device(), camera);
  const auto blocks = rig.read<gpu::MsaBlockGpu>(rig.pass->blocks());
  const auto density = rig.read<uint32_t>(rig.pass->density());
  const surface::MsaCounters& c = img.counters;
  EXPECT_FALSE(c.out_of_superblocks);
  EXPECT_EQ(c.meshlets_without_block, 0u);
  EXPECT_EQ(c.hole_pixels, 0u);
  EXPECT_FLOAT_EQ(c.budget_factor, 1.0f);
  // The densities: the CPU's from the pixel rays in double, within float rounding (1e-3 relative).
  std::vector<double> want(rig.meshlets.meshlets.size(), 0.0);
  for (size_t i = 0; i < img.visibility.size(); ++i) {
    if (img.visibility[i].x == 0) continue;
    const uint32_t t = img.visibility[i].x - 1;
    const double x = double(i % kW) + 0.5, y = double(i / kW) + 0.5;
    const glm::dvec2 p = rig.chart_point(t, ray_plane_barycentric(rig, camera, t, x, y));
    const double fx = glm::length(rig.chart_point(t, ray_plane_barycentric(rig, camera, t, x + 1.0, y)) - p);
    const double fy = glm::length(rig.chart_point(t, ray_plane_barycentric(rig, camera, t, x, y + 1.0)) - p);
    const uint32_t m = rig.meshlets.meshlet_of_triangle[t];
    want[m] = std::max(want[m], 1.0 / std::max(fx, fy));
  }
  size_t seen = 0, class_checked = 0;
  for (size_t m = 0; m < want.size(); ++m) {
    const double gpu_density = as_float(density[m]);
    ASSERT_EQ(want[m] > 0.0, density[m] != 0u) << "meshlet " << m;
    if (want[m] == 0.0) {
      EXPECT_EQ(blocks[m].block.z, PRISMOID_MSA_NONE) << "an unseen meshlet holds a block";
      continue;
    }
    ++seen;
    EXPECT_NEAR(gpu_density, want[m], 1e-3 * want[m]) << "meshlet " << m;
    const glm::dvec2 extent = rig.meshlets.meshlets[m].extent;
    const uint32_t lo = surface::msa_class_for(extent, gpu_density * (1.0 - 1e-6)), hi = surface::msa_class_for(extent, gpu_density * (1.0 + 1e-6));
    ASSERT_NE(blocks[m].block.z, PRISMOID_MSA_NONE) << "meshlet " << m;
    EXPECT_TRUE(blocks[m].block.z == lo || blocks[m].block.z == hi) << "meshlet " << m << " class " << blocks[m].block.z << " wanted " << lo;
    class_checked += lo == hi;
  }
  EXPECT_EQ(seen, c.seen_meshlets);
  EXPECT_GT(class_checked, seen / 2);
  // Disjoint blocks inside the atlas, each inside one superblock.
  std::vector<uint8_t> owner(size_t(rig.pass->atlas_width()) * rig.pass->atlas_height(), 0);
  uint64_t held = 0;
  for (size_t m = 0; m < blocks.size(); ++m) {
    if (blocks[m].block.z == PRISMOID_MSA_NONE) continue;
    const glm::uvec2 size = surface::msa_class_size(blocks[m].block.z), o(blocks[m].block.x, blocks[m].block.y);
    held += uint64_t(size.x) * size.y;
    ASSERT_LE(o.x + size.x, rig.pass->atlas_width());
    ASSERT_LE(o.y + size.y, rig.pass->atlas_height());
    EXPECT_EQ(o.x / PRISMOID_MSA_SUPERBLOCK, (o.x + size.x - 1) / PRISMOID_MSA_SUPERBLOCK);
    EXPECT_EQ(o.y / PRISMOID_MSA_SUPERBLOCK, (o.y + size.y - 1) / PRISMOID_MSA_SUPERBLOCK);
    for (uint32_t y = o.y; y < o.y + size.y; ++y)
      for (uint32_t x = o.x; x < o.x + size.x; ++x) ASSERT_EQ(owner[size_t(y) * rig.pass->atlas_width() + x]++, 0) << "blocks overlap at " << x << "," << y;
  }
  EXPECT_EQ(held, c.held_texels);
  std::printf("%zu meshlets (%zu seen), %u blocks, %llu block texels for %zu pixels; %u superblocks free\n", want.size(), seen, c.allocated_blocks,
              static_cast<unsigned long long>(held), img.visibility.size(), c.free_superblocks);
}

// Both charts: the orthogonal projection (GGX and diffuse) and the conformal one (diffuse).
TEST_F(MsaPassTest, ShadesEveryBlockTexelAndDisplaysTheBilinearLookup) {
  // Variants: diffuse, GGX, conformal charts, and the per-frame perspective (MSA-P) and
  // orthographic (MSA-O) charts, whose corners are the CPU twin's (msa::frame_charts).
  for (const int variant : {0, 1, 2, 3, 4}) {
    const bool ggx = variant == 1;
    const msa::Parametrization charts = variant == 2   ? msa::Parametrization::Conformal
                                        : variant == 3 ? msa::Parametrization::Perspective
                                        : variant == 4 ? msa::Parametrization::Orthographic
                                                       : msa::Parametrization::Projection;
    SphereSceneOptions o;
    o.ggx = ggx;
    o.sky = true;
    surface::MsaSettings settings = unshadowed();
    settings.frame_charts = charts;
    if (variant == 4) settings.superblocks = 32;  // its blocks come in more size classes, a superblock each
    MsaRig rig(device(), sphere_scene(o), settings, msa::Clustering::NormalCone, charts);
    const Camera camera = rig.scene.camera;
    const surface::MsaImage img = rig.render(device(), camera);
    const bool per_frame = msa::per_frame(charts);
    const msa::FrameCharts frame = msa::frame_charts(rig.scene, rig.meshlets, camera, kW, kH, per_frame ? charts : msa::Parametrization::Orthographic);
    const auto meshlet_table = rig.read<gpu::MsaMeshletGpu>(rig.pass->meshlet_table());
    // The extent the GPU sized the block from (per-frame: its own float projection's).
    auto extent_of = [&](uint32_t m) {
      return per_frame ? glm::dvec2(meshlet_table[m].extent.x, meshlet_table[m].extent.y) : rig.meshlets.meshlets[m].extent;
    };
    const auto blocks = rig.read<gpu::MsaBlockGpu>(rig.pass->blocks());
    const auto tasks = rig.read<uint32_t>(rig.pass->tasks());
    const auto result = rig.read<glm::vec4>(rig.pass->result());
    const uint32_t width = rig.pass->atlas_width();
    ASSERT_GT(img.counters.shaded_tiles, 0u);
    std::vector<reference::ShadingPointQuery> queries;
    std::vector<size_t> slots;
    size_t ambiguous = 0, empty = 0, wrong_empty = 0;
    for (uint32_t k = 0; k < img.counters.shaded_tiles; ++k) {
      const uint32_t m = tasks[k] >> 12, tile = tasks[k] & 0xfff;
      const glm::uvec2 size = surface::msa_class_size(blocks[m].block.z);
      const double s = surface::msa_block_scale(extent_of(m), blocks[m].block.z);
      for (uint32_t q = 0; q < 64; ++q) {
        const glm::uvec2 local((tile % (size.x / 8)) * 8 + q % 8, (tile / (size.x / 8)) * 8 + q / 8);
        const size_t slot = size_t(blocks[m].block.y + local.y) * width + blocks[m].block.x + local.x;
        const TexelChoice ch = choose(rig, m, (glm::dvec2(local) + 0.5 - 1.0) / s, s, per_frame ? &frame : nullptr, &camera);
        if (ch.ambiguous) {
          ++ambiguous;
          continue;
        }
        if (ch.triangle == PRISMOID_MSA_NONE) {
          ++empty;
          wrong_empty += result[slot].w != 0.0f;
          continue;
        }
        const auto [mesh, local_tri] = rig.local_triangle(ch.triangle);
        queries.push_back({mesh, local_tri, ch.bary, camera.eye});
        slots.push_back(slot);
      }
    }
    EXPECT_EQ(wrong_empty, 0u) << "texels outside every meshlet triangle must stay empty";
    // Per-frame charts fold where a meshlet turns from the eye: a farther layer's edges near a texel
    // mark it ambiguous too (the CPU rule counts every edge within the margin), about 5 % here.
    EXPECT_LT(double(ambiguous), (per_frame ? 0.08 : 0.01) * double(queries.size()));
    std::vector<glm::vec4> gpu_values;
    for (size_t k : slots) gpu_values.push_back(result[k]);
    const SampleCheck shading = check_shaded_samples(rig.scene, queries, gpu_values);
    EXPECT_EQ(shading.failures, 0u);
    // Display: the blend of the GPU's texels at the CPU's taps (bilinear_pixel_error).
    size_t display_failures = 0, pixels = 0;
    double worst_display = 0.0;
    for (size_t i = 0; i < img.visibility.size(); ++i) {
      if (img.visibility[i].x == 0) continue;
      ++pixels;
      const uint32_t t = img.visibility[i].x - 1, m = rig.meshlets.meshlet_of_triangle[t];
      const glm::uvec2 size = surface::msa_class_size(blocks[m].block.z);
      const double s = surface::msa_block_scale(extent_of(m), blocks[m].block.z);
      glm::dvec3 b = stored_barycentrics(img.visibility[i]);
      glm::dvec2 chart = rig.chart_point(t, b);
      if (per_frame) {
        if (frame.perspective[m]) b = image_weights(b, corner_depths(rig, camera, t));
        const auto& k = frame.corner_chart[t];
        chart = b.x * k[0] + b.y * k[1] + b.z * k[2];
      }
      const glm::dvec2 f = 1.0 + chart * s - 0.5;
      const glm::dvec2 fl = glm::floor(f), a = f - fl;
      const double w[4] = {(1 - a.x) * (1 - a.y), a.x * (1 - a.y), (1 - a.x) * a.y, a.x * a.y};
      std::vector<std::pair<glm::vec4, double>> taps;
      for (uint32_t k = 0; k < 4; ++k) {
        const glm::ivec2 tap = glm::clamp(glm::ivec2(fl) + glm::ivec2(k & 1, k >> 1), glm::ivec2(0), glm::ivec2(size) - 1);
        const glm::vec4 g = result[size_t(blocks[m].block.y + uint32_t(tap.y)) * width + blocks[m].block.x + uint32_t(tap.x)];
        if (g.w != 0.0f) taps.emplace_back(g, w[k]);
      }
      const double e = bilinear_pixel_error(&img.rgba[4 * i], taps);
      worst_display = std::max(worst_display, e);
      if (e > 1.0 && display_failures++ < 5) ADD_FAILURE() << "pixel " << i << ": " << e << " of the tolerance";
    }
    EXPECT_EQ(display_failures, 0u);
    EXPECT_EQ(img.counters.hole_pixels, 0u);
    std::printf("[ %s ] %zu texels of %u tiles checked (%zu empty, %zu ambiguous): worst %.3g of tolerance; display %zu pixels, worst %.3g of "
                "tolerance; %zu meshlets\n",
                variant == 4   ? "diffuse, orthographic per-frame charts (MSA-O)"
                : variant == 3 ? "diffuse, perspective per-frame charts (MSA-P)"
                : variant == 2 ? "diffuse, conformal charts"
                : ggx          ? "GGX"
                               : "diffuse",
                queries.size(), img.counters.shaded_tiles, empty, ambiguous, shading.worst, pixels, worst_display,
                rig.meshlets.meshlets.size());
  }
}

TEST_F(MsaPassTest, FlatShadedCubeEqualsTheForwardImage) {
  MsaRig rig(device(), flat_cube_scene(), unshadowed());
  const surface::MsaImage img = rig.render(device(), rig.scene.camera);
  EXPECT_GT(expect_equals_forward(device(), rig.gpu, rig.scene.camera, kW, kH, img.rgba, img.visibility), size_t(kW * kH / 5));
}

// A still camera: the second frame keeps every block and shades nothing, drawing the same image;
// invalidate_shading() shades every block again; with an amortization period of 3 the blocks are
// shaded again on the third frame after the last shading, and not before.
// Per-frame charts (MSA-P, MSA-O): the charts the GPU made this frame are the CPU twin's
// projections (msa::frame_charts): pixels for perspective charts (float: within 1e-3 pixel),
// camera-space world units for orthographic ones; a sphere's meshlets are all beyond the near
// plane, so every one is perspective under MSA-P.
TEST_F(MsaPassTest, PerFrameChartsAreTheCamerasProjections) {
  for (const msa::Parametrization kind : {msa::Parametrization::Perspective, msa::Parametrization::Orthographic}) {
    surface::MsaSettings s = unshadowed();
    s.frame_charts = kind;
    MsaRig rig(device(), sphere_scene({}), s, msa::Clustering::NormalCone, kind);
    const Camera camera = rig.scene.camera;
    rig.render(device(), camera);
    const auto triangles = rig.read<gpu::MsaTriangleGpu>(rig.pass->triangle_table());
    const auto meshlets = rig.read<gpu::MsaMeshletGpu>(rig.pass->meshlet_table());
    const msa::FrameCharts cpu = msa::frame_charts(rig.scene, rig.meshlets, camera, kW, kH, kind);
    const double tol = kind == msa::Parametrization::Perspective ? 1e-3 : 1e-5;
    size_t failures = 0;
    for (size_t t = 0; t < cpu.corner_chart.size(); ++t) {
      const glm::dvec2 g[3] = {glm::dvec2(triangles[t].c01.x, triangles[t].c01.y), glm::dvec2(triangles[t].c01.z, triangles[t].c01.w),
                               glm::dvec2(triangles[t].c2.x, triangles[t].c2.y)};
      for (int k = 0; k < 3; ++k)
        if (glm::length(g[k] - cpu.corner_chart[t][size_t(k)]) > tol && failures++ < 5)
          ADD_FAILURE() << msa::parametrization_name(kind) << " triangle " << t << " corner " << k << ": GPU " << g[k].x << " " << g[k].y
                        << ", CPU " << cpu.corner_chart[t][size_t(k)].x << " " << cpu.corner_chart[t][size_t(k)].y;
    }
    // Stretch: a perspective chart's unit is a pixel, so each pixel's stretch is 1 / its block's
    // scale: the largest over the seen meshlets, and the root mean square over the pixels.
    if (kind == msa::Parametrization::Perspective) {
      const surface::MsaImage img = rig.render(device(), camera);
      const auto blocks = rig.read<gpu::MsaBlockGpu>(rig.pass->blocks());
      double sum = 0.0, worst = 0.0;
      size_t pixels = 0;
      for (const glm::uvec4& v : img.visibility) {
        if (v.x == 0) continue;
        const uint32_t m = rig.meshlets.meshlet_of_triangle[v.x - 1];
        const double g = 1.0 / surface::msa_block_scale(glm::dvec2(meshlets[m].extent.x, meshlets[m].extent.y), blocks[m].block.z);
        sum += g * g;
        worst = std::max(worst, g);
        ++pixels;
      }
      // The GPU differences chart points one pixel apart in float, through the ray-plane weights
      // and the perspective conversion: ~1e-4 of the stretch each.
      EXPECT_NEAR(img.counters.stretch_l2, std::sqrt(sum / double(pixels)), 1e-3);
      EXPECT_NEAR(img.counters.stretch_linf, worst, 1e-3 * worst);
      std::printf("MSA-P stretch: L2 %.4f, L-infinity %.4f\n", img.counters.stretch_l2, img.counters.stretch_linf);
    }
    for (size_t m = 0; m < cpu.extent.size(); ++m) {
      EXPECT_NEAR(meshlets[m].extent.x, cpu.extent[m].x, tol) << m;
      EXPECT_NEAR(meshlets[m].extent.y, cpu.extent[m].y, tol) << m;
      EXPECT_EQ(meshlets[m].info.z, uint32_t(cpu.perspective[m])) << m;
      if (kind == msa::Parametrization::Perspective) {
        EXPECT_EQ(cpu.perspective[m], 1u) << m;
      }
    }
    EXPECT_EQ(failures, 0u);
  }
}

// Where shading is constant per face, per-frame charts draw the forward image: the perspective
// chart's image-to-surface weights and the nearest triangle where the projection folds are right.
// The optional refinement of large triangles (refine_large_triangles, as the paper prepares its
// scenes): at 1920 x 1080 the Cornell box's walls, two triangles each, span more pixels than a
// 256-texel block holds, so MSA-P undersamples them (stretch above 1.5); split until no triangle
// spans 16 pixels, every meshlet fits its block (stretch at most 1, up to rounding) and the image
// keeps its covered pixels.
TEST_F(MsaPassTest, RefinedTrianglesLetEveryPerFrameChartFitItsBlock) {
  size_t covered[2] = {0, 0};
  for (const bool refined : {false, true}) {
    SurfaceScene box = make_cornell_box();
    if (refined) box = refine_large_triangles(box, box.camera, 1920, 1080, 16.0);
    surface::MsaSettings s = unshadowed();
    s.frame_charts = msa::Parametrization::Perspective;
    s.superblocks = 128;  // 128 MiB: what lavapipe's storage-buffer range allows
    MsaRig rig(device(), box, s, msa::Clustering::NormalCone, msa::Parametrization::Perspective);
    const surface::MsaImage img = surface::render_msa(device(), *rig.pass, rig.gpu, rig.accel.tlas(), box.camera, {1920, 1080});
    if (refined) {
      EXPECT_LE(img.counters.stretch_linf, 1.0 + 1e-3);
      // More tiles than a launch may have groups along z (65,535 on the H200, where such a frame
      // came out unshaded while the tiles were z): the launch stacks them along y.
      EXPECT_GT(img.counters.shaded_tiles, 65535u);
      EXPECT_EQ(img.counters.shading_launch, (img.counters.shaded_tiles + PRISMOID_MSA_TILES_PER_LAUNCH - 1) / PRISMOID_MSA_TILES_PER_LAUNCH);
      EXPECT_LE(img.counters.shading_launch, 65535u);
      EXPECT_EQ(img.counters.hole_pixels, 0u);
      EXPECT_GT(rig.meshlets.meshlets.size(), 4 * msa::build_meshlets(make_cornell_box(), {}).meshlets.size());
    } else {
      EXPECT_GT(img.counters.stretch_linf, 1.5);
    }
    for (size_t i = 3; i < img.rgba.size(); i += 4) covered[refined] += img.rgba[i] == 1.0f;
    std::printf("%s: %zu meshlets, stretch L2 %.3f, L-infinity %.3f\n", refined ? "refined" : "as built", rig.meshlets.meshlets.size(),
                img.counters.stretch_l2, img.counters.stretch_linf);
  }
  EXPECT_NEAR(double(covered[0]), double(covered[1]), 1e-5 * double(covered[0]));  // the new edges' rounding moves a pixel or two
}

TEST_F(MsaPassTest, PerFrameChartsDrawTheFlatCubeAsForward) {
  for (const msa::Parametrization kind : {msa::Parametrization::Perspective, msa::Parametrization::Orthographic}) {
    surface::MsaSettings s = unshadowed();
    s.frame_charts = kind;
    MsaRig rig(device(), flat_cube_scene(), s, msa::Clustering::NormalCone, kind);
    const surface::MsaImage img = rig.render(device(), rig.scene.camera);
    EXPECT_GT(expect_equals_forward(device(), rig.gpu, rig.scene.camera, kW, kH, img.rgba, img.visibility), size_t(kW * kH / 5))
        << msa::parametrization_name(kind);
    EXPECT_EQ(img.counters.hole_pixels, 0u);
  }
}

TEST_F(MsaPassTest, StillCameraReusesBlocksAndAmortizationShadesEveryNthFrame) {
  MsaRig rig(device(), sphere_scene({}), unshadowed());
  const Camera camera = rig.scene.camera;
  const surface::MsaImage first = rig.render(device(), camera);
  ASSERT_GT(first.counters.shaded_tiles, 0u);
  const surface::MsaImage second = rig.render(device(), camera);
  EXPECT_EQ(second.counters.allocated_blocks, 0u);
  EXPECT_EQ(second.counters.released_blocks, 0u);
  EXPECT_EQ(second.counters.shaded_tiles, 0u);
  EXPECT_EQ(second.rgba, first.rgba);
  rig.pass->invalidate_shading();
  EXPECT_EQ(rig.render(device(), camera).counters.shaded_tiles, first.counters.shaded_tiles);
  surface::MsaSettings s = unshadowed();
  s.shade_every = 3;
  rig.pass->set_settings(s);
  std::vector<uint32_t> shaded;
  for (int f = 0; f < 6; ++f) shaded.push_back(rig.render(device(), camera).counters.shaded_tiles);
  uint32_t full = 0;
  for (uint32_t n : shaded) {
    EXPECT_TRUE(n == 0u || n == first.counters.shaded_tiles) << n;
    full += n == first.counters.shaded_tiles;
  }
  EXPECT_EQ(full, 2u);  // 6 frames, every 3rd
}

// The budget: block texels wanted beyond it scale every meshlet's density by sqrt(budget /
// demand), the GPU's factor is that, and the blocks held shrink.
TEST_F(MsaPassTest, ShadingBudgetScalesTheBlocksDown) {
  MsaRig rig(device(), sphere_scene({}), unshadowed());
  const Camera camera = rig.scene.camera;
  const surface::MsaImage free_run = rig.render(device(), camera);
  surface::MsaSettings s = unshadowed();
  s.budget_texels = uint32_t(free_run.counters.demand_texels / 4);
  rig.pass->set_settings(s);
  rig.pass->invalidate_shading();
  const surface::MsaImage budgeted = rig.render(device(), camera);
  EXPECT_EQ(budgeted.counters.demand_texels, free_run.counters.demand_texels);
  EXPECT_NEAR(budgeted.counters.budget_factor, std::sqrt(double(s.budget_texels) / double(free_run.counters.demand_texels)), 1e-6);
  EXPECT_LT(budgeted.counters.held_texels, free_run.counters.held_texels / 2);
  EXPECT_EQ(budgeted.counters.hole_pixels, 0u);
  std::printf("no budget: %llu block texels (%u texels shaded); budget %u: factor %.3f, %llu block texels (%u shaded)\n",
              static_cast<unsigned long long>(free_run.counters.held_texels), free_run.counters.shaded_texels, s.budget_texels,
              double(budgeted.counters.budget_factor), static_cast<unsigned long long>(budgeted.counters.held_texels), budgeted.counters.shaded_texels);
}

// One superblock is too small for the view: the frame says so and counts the pixels it could
// not draw; the next frame starts from an empty atlas.
TEST_F(MsaPassTest, AnAtlasTooSmallIsReportedAndReset) {
  surface::MsaSettings s = unshadowed();
  s.superblocks = 1;
  MsaRig rig(device(), sphere_scene({}), s);
  Camera camera = rig.scene.camera;
  camera.fovy_degrees = 0.5;  // magnified: every seen meshlet wants the largest block, a superblock each
  const surface::MsaImage img = rig.render(device(), camera);
  const bool short_of_space = img.counters.out_of_superblocks || img.counters.meshlets_without_block > 0;
  ASSERT_TRUE(short_of_space) << "the test needs a view that one superblock cannot hold";
  EXPECT_GT(img.counters.meshlets_without_block, 0u);
  EXPECT_GT(img.counters.hole_pixels, 0u);
  for (float v : img.rgba) ASSERT_TRUE(std::isfinite(v));
  const surface::MsaImage next = rig.render(device(), camera);
  EXPECT_GT(next.counters.allocated_blocks, 0u);  // allocated afresh after the reset
}

}  // namespace
}  // namespace prismoid::test
