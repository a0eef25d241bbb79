// FastAtlas on the GPU (lavapipe, validation on) against its CPU twins in double precision
// (renderer/surface/fastatlas/: visible_charts, triangle_box, pack_atlas, chart_map,
// hard_edge_filter) and reference::direct_light_at: the charts are the CPU union-find's on the
// same visibility, the boxes its boxes, the packing its packing of the same boxes, every shaded
// texel the direct light at its point, every pixel the hard-edge filter of its taps; the same
// frame twice gives the same atlas bit for bit; at scale 1 the image is the forward image; the
// hard cases (near-plane crossings, a chart larger than the atlas, nothing visible) hold.
#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <map>
#include <memory>
#include <set>
#include <vector>

#include <glm/geometric.hpp>
#include <glm/trigonometric.hpp>

#include "renderer/reference/direct_light.hpp"
#include "renderer/reference/tet_ray.hpp"
#include "renderer/rt/acceleration_structure.hpp"
#include "renderer/surface/fastatlas/atlas_filter.hpp"
#include "renderer/surface/fastatlas/atlas_map.hpp"
#include "renderer/surface/fastatlas/atlas_packing.hpp"
#include "renderer/surface/fastatlas/charts.hpp"
#include "renderer/surface/fastatlas/fastatlas_pass.hpp"
#include "renderer/surface/forward/forward_pass.hpp"
#include "scene/surface_generators.hpp"
#include "shaders/shared/fastatlas.h"
#include "support/gpu_fixture.hpp"
#include "surface/surface_test_scenes.hpp"
#include "surface/texture_space_checks.hpp"

namespace prismoid::test {
namespace {

constexpr uint32_t kW = 96, kH = 72;
constexpr uint32_t kNone = PRISMOID_FA_NONE;

surface::FastAtlasSettings settings(uint32_t atlas, double scale = 1.0) {
  surface::FastAtlasSettings s;
  s.atlas_width = s.atlas_height = atlas;
  s.shading_scale = scale;
  s.shadows = false;
  return s;
}

struct FaRig {
  FaRig(const vk::Device& device, SurfaceScene s, const surface::FastAtlasSettings& settings)
      : scene(std::move(s)),
        gpu(surface::upload(device, scene)),
        accel(device, scene),
        pass(std::make_unique<surface::FastAtlasPass>(device, scene, settings)),
        triangles(scene) {}
  surface::FastAtlasImage render(const vk::Device& device, const Camera& camera, uint32_t w = kW, uint32_t h = kH) {
    return surface::render_fastatlas(device, *pass, gpu, accel.tlas(), camera, {w, h});
  }
  SurfaceScene scene;
  surface::GpuSurfaceScene gpu;
  rt::SceneAccel accel;
  std::unique_ptr<surface::FastAtlasPass> pass;
  TriangleIndex triangles;
};

// The chart map of root r as the GPU's boxes, places and scale give it, in double.
fastatlas::ChartMap map_of(const std::vector<glm::ivec4>& boxes, const std::vector<glm::uvec4>& placed, uint32_t r, double scale) {
  const glm::ivec4 b = boxes[r];
  const glm::uvec4 p = placed[r];
  fastatlas::PixelBox box{double(b.x), double(b.y), double(-b.z), double(-b.w)};
  fastatlas::PlacedChart c{p.x, p.y, p.z & 0x7fffffffu, p.w, (p.z >> 31) != 0};
  return fastatlas::chart_map(box, c, scale, 1);
}

glm::dvec2 to_screen(const fastatlas::ChartMap& m, const glm::dvec2& texel) {
  glm::dvec2 d = (texel - m.atlas_origin) / m.scale;
  if (m.turned) d = glm::dvec2(d.y, d.x);
  return m.screen_origin + d;
}


// The last frame's atlases and per-chart buffers, read back.
struct AtlasReadback {
  std::vector<uint32_t> ids, parent;
  std::vector<glm::vec4> colors;
  std::vector<glm::ivec4> boxes;
  std::vector<glm::uvec4> placed;
  explicit AtlasReadback(const surface::FastAtlasPass& pass)
      : ids(pass.read_id_atlas()), parent(pass.read_parent()), colors(pass.read_color_atlas()), boxes(pass.read_boxes()),
        placed(pass.read_placed()) {}
  fastatlas::ChartMap map(uint32_t triangle, double scale) const { return map_of(boxes, placed, parent[triangle], scale); }
};

// The image against the forward pass's of the same view, over the pixels both cover: each channel
// within 2e-3 relative (the float mapping's 1e-4 texel of blending at scale 1). Returns the
// pixels compared.
size_t expect_forward_image(const vk::Device& device, const FaRig& rig, const surface::FastAtlasImage& img, const Camera& camera,
                            VkExtent2D extent) {
  surface::ForwardPass forward(device);
  const std::vector<float> fwd = surface::render_forward(device, forward, rig.gpu, camera, extent).rgba;
  size_t compared = 0, failures = 0;
  for (size_t i = 0; i < img.visibility.size(); ++i) {
    if (img.visibility[i].x == 0 || fwd[4 * i + 3] != 1.0f) continue;
    ++compared;
    for (size_t ch = 0; ch < 3; ++ch) {
      const double f = fwd[4 * i + ch], g = img.rgba[4 * i + ch];
      if (std::abs(f - g) > 2e-3 * std::max(1.0, std::abs(f)) && failures++ < 5) ADD_FAILURE() << "pixel " << i << ": " << g << ", forward " << f;
    }
  }
  EXPECT_EQ(failures, 0u);
  return compared;
}

class FastAtlasPassTest : public GpuTest {};

// Two spheres, one partly behind the other, and a floor: charts meet occlusion boundaries and
// silhouettes; the union-find must find exactly the CPU's components.
SurfaceScene two_spheres() {
  SurfaceScene s = sphere_scene({});
  s.meshes.push_back(sphere_mesh({0.9, 0.3, -1.5}, 0.8, 3, true, 0));
  s.meshes.push_back(horizontal_quad("floor", 0.0, -1.0, 0.0, 6.0, 0));
  return s;
}

TEST_F(FastAtlasPassTest, ChartsAreTheCpuUnionFindsOnTheSameVisibility) {
  FaRig rig(device(), two_spheres(), settings(512));
  const surface::FastAtlasImage img = rig.render(device(), rig.scene.camera);
  const std::vector<uint32_t> parent = rig.pass->read_parent();
  // Visible: exactly the triangles holding a pixel's sample.
  std::set<uint32_t> seen;
  for (const glm::uvec4& v : img.visibility)
    if (v.x != 0) seen.insert(v.x - 1);
  std::vector<uint8_t> visible(parent.size(), 0);
  for (size_t t = 0; t < parent.size(); ++t) {
    visible[t] = parent[t] != kNone;
    EXPECT_EQ(bool(visible[t]), seen.count(uint32_t(t)) == 1) << "triangle " << t;
  }
  const fastatlas::SceneAdjacency& adj = rig.pass->adjacency();
  const fastatlas::Charts cpu = fastatlas::visible_charts(adj.mesh, fastatlas::face_visibility(adj, visible));
  size_t checked = 0;
  for (uint32_t f = 0; f < adj.mesh.face_count(); ++f) {
    const uint32_t t = adj.mesh.triangle_of_face[f];
    if (!visible[t]) continue;
    const uint32_t cpu_root = adj.mesh.triangle_of_face[cpu.root[cpu.chart_of_face[f]]];
    EXPECT_EQ(parent[t], cpu_root) << "triangle " << t;
    ++checked;
  }
  EXPECT_EQ(img.counters.charts, cpu.root.size());
  EXPECT_EQ(img.counters.visible_triangles, checked);
  EXPECT_GE(cpu.root.size(), 3u);  // the spheres and the floor at least
  std::printf("%zu visible triangles in %zu charts, as the CPU union-find\n", checked, cpu.root.size());
}

// Each chart's box is the CPU's (triangle_box of its triangles, whole pixels) within one pixel
// (the GPU projects in float), and the packing is the CPU twin's on the GPU's boxes exactly:
// order, chosen candidate, every place; no two boxes overlap and all lie inside the atlas.
void expect_boxes_and_packing(FaRig& rig, const surface::FastAtlasImage& img, const Camera& camera, uint32_t atlas, double sf,
                              uint32_t w = kW, uint32_t h = kH) {
  const std::vector<uint32_t> parent = rig.pass->read_parent();
  const std::vector<glm::ivec4> boxes = rig.pass->read_boxes();
  const std::vector<glm::uvec4> placed = rig.pass->read_placed();
  const fastatlas::SceneAdjacency& adj = rig.pass->adjacency();
  std::map<uint32_t, fastatlas::PixelBox> cpu_boxes;
  for (uint32_t f = 0; f < adj.mesh.face_count(); ++f) {
    const uint32_t t = adj.mesh.triangle_of_face[f];
    if (parent[t] == kNone) continue;
    const auto& tri = adj.mesh.faces[f];
    const fastatlas::PixelBox b =
        fastatlas::triangle_box(adj.mesh.positions[tri[0]], adj.mesh.positions[tri[1]], adj.mesh.positions[tri[2]], camera, w, h);
    if (b.empty()) continue;
    auto [it, fresh] = cpu_boxes.try_emplace(parent[t], b);
    if (!fresh) it->second = {std::min(it->second.x0, b.x0), std::min(it->second.y0, b.y0), std::max(it->second.x1, b.x1),
                              std::max(it->second.y1, b.y1)};
  }
  std::vector<uint32_t> roots;
  std::vector<fastatlas::ChartBox> chart_boxes;
  for (size_t t = 0; t < parent.size(); ++t) {
    if (parent[t] != t) continue;
    roots.push_back(uint32_t(t));
    const glm::ivec4 g = boxes[t];
    chart_boxes.push_back({uint32_t(-g.z - g.x), uint32_t(-g.w - g.y), uint32_t(t)});
    ASSERT_TRUE(cpu_boxes.count(uint32_t(t))) << "root " << t;
    const fastatlas::PixelBox& c = cpu_boxes[uint32_t(t)];
    EXPECT_LE(std::abs(g.x - std::floor(c.x0)), 1) << "root " << t;
    EXPECT_LE(std::abs(g.y - std::floor(c.y0)), 1) << "root " << t;
    EXPECT_LE(std::abs(-g.z - std::ceil(c.x1)), 1) << "root " << t;
    EXPECT_LE(std::abs(-g.w - std::ceil(c.y1)), 1) << "root " << t;
  }
  fastatlas::PackingOptions o;
  o.atlas_width = o.atlas_height = atlas;
  o.largest_scale = sf;
  o.smallest_scale = sf / 64.0;
  const fastatlas::AtlasPacking cpu = fastatlas::pack_atlas(chart_boxes, o);
  ASSERT_TRUE(cpu.fits);
  EXPECT_TRUE(img.counters.fits);
  EXPECT_EQ(img.counters.candidate, cpu.candidate);
  EXPECT_EQ(img.counters.scale, cpu.scale);
  EXPECT_EQ(img.counters.rows_used, cpu.height_used);
  std::vector<uint32_t> cpu_order;
  for (uint32_t i : fastatlas::packing_order(chart_boxes)) cpu_order.push_back(roots[i]);
  EXPECT_EQ(rig.pass->read_sorted_charts(), cpu_order);
  for (size_t i = 0; i < roots.size(); ++i) {
    const glm::uvec4 g = placed[roots[i]];
    const fastatlas::PlacedChart& c = cpu.charts[i];
    EXPECT_EQ(g, glm::uvec4(c.x, c.y, c.width | (c.turned ? 0x80000000u : 0u), c.height)) << "root " << roots[i];
    EXPECT_LE(c.x + c.width, atlas);
    EXPECT_LE(c.y + c.height, atlas);
    for (size_t j = 0; j < i; ++j) {
      const fastatlas::PlacedChart& d = cpu.charts[j];
      EXPECT_FALSE(c.x < d.x + d.width && d.x < c.x + c.width && c.y < d.y + d.height && d.y < c.y + c.height)
          << "roots " << roots[i] << " and " << roots[j] << " overlap";
    }
  }
}

TEST_F(FastAtlasPassTest, BoxesAndPackingAreTheCpuTwinsOnTheSameFrame) {
  FaRig rig(device(), two_spheres(), settings(512));
  const surface::FastAtlasImage img = rig.render(device(), rig.scene.camera);
  expect_boxes_and_packing(rig, img, rig.scene.camera, 512, 1.0);
  EXPECT_EQ(img.counters.candidate, 0u);  // everything fits at one texel per pixel
  EXPECT_EQ(img.counters.hole_pixels, 0u);
}

// A chart larger than the atlas: the scale falls to the largest candidate that fits (the CPU
// twin's), and where shading is constant per face the image is still the forward one.
TEST_F(FastAtlasPassTest, AChartLargerThanTheAtlasLowersTheScale) {
  constexpr uint32_t w = 2 * kW, h = 2 * kH;  // the cube spans more than 64 pixels
  FaRig rig(device(), flat_cube_scene(), settings(64));
  const surface::FastAtlasImage img = rig.render(device(), rig.scene.camera, w, h);
  EXPECT_GT(img.counters.candidate, 0u);
  EXPECT_LT(img.counters.scale, 1.0);
  // Sander's stretch between screen and atlas, measured per pixel as for the other atlases: 1 / s
  // everywhere (the GPU differences atlas positions one pixel apart in float: 1e-4 of it, as
  // measured on the H200; the sum's fixed point rounds by 1e-4).
  EXPECT_NEAR(img.counters.stretch_l2, 1.0 / img.counters.scale, 1e-3 / img.counters.scale);
  EXPECT_NEAR(img.counters.stretch_linf, 1.0 / img.counters.scale, 1e-3 / img.counters.scale);
  expect_boxes_and_packing(rig, img, rig.scene.camera, 64, 1.0, w, h);
  EXPECT_EQ(img.counters.hole_pixels, 0u);
  const size_t compared = expect_equals_forward(device(), rig.gpu, rig.scene.camera, w, h, img.rgba, img.visibility);
  EXPECT_GT(compared, size_t(w * h / 5));
  std::printf("scale %.4f (candidate %u); %zu pixels equal to the forward image\n", img.counters.scale, img.counters.candidate, compared);
}

// The same frame twice, and a fresh pass, give the same atlas bit for bit.
TEST_F(FastAtlasPassTest, TheSameFrameGivesTheSameAtlasBitForBit) {
  FaRig rig(device(), two_spheres(), settings(256, 0.7));
  const surface::FastAtlasImage first = rig.render(device(), rig.scene.camera);
  const std::vector<uint32_t> ids = rig.pass->read_id_atlas();
  const std::vector<glm::vec4> colors = rig.pass->read_color_atlas();
  const std::vector<uint32_t> parent = rig.pass->read_parent();
  const std::vector<glm::uvec4> placed = rig.pass->read_placed();
  // Places are kept at the charts' roots only.
  auto root_places = [&](const std::vector<glm::uvec4>& all) {
    std::vector<glm::uvec4> out;
    for (size_t t = 0; t < parent.size(); ++t)
      if (parent[t] == t) out.push_back(all[t]);
    return out;
  };
  size_t held = 0;
  for (uint32_t id : ids) held += id != kNone;
  ASSERT_GT(held, 1000u);
  for (int run = 0; run < 2; ++run) {
    if (run == 1) rig.pass = std::make_unique<surface::FastAtlasPass>(device(), rig.scene, settings(256, 0.7));
    const surface::FastAtlasImage again = rig.render(device(), rig.scene.camera);
    EXPECT_EQ(rig.pass->read_id_atlas(), ids) << "run " << run;
    EXPECT_EQ(rig.pass->read_parent(), parent) << "run " << run;
    EXPECT_EQ(root_places(rig.pass->read_placed()), root_places(placed)) << "run " << run;
    const std::vector<glm::vec4> c = rig.pass->read_color_atlas();
    size_t differ = 0;
    for (size_t i = 0; i < ids.size(); ++i) differ += ids[i] != kNone && c[i] != colors[i];
    EXPECT_EQ(differ, 0u) << "run " << run;
    EXPECT_EQ(again.rgba, first.rgba) << "run " << run;
  }
}

// Only the rows a frame uses are cleared and drawn, so rows the last frame used beyond them must be
// cleared too: after a frame at scale 1, one at a quarter leaves nothing below its own rows.
TEST_F(FastAtlasPassTest, AFrameUsingFewerRowsLeavesNoneOfTheLastOnesBelow) {
  FaRig rig(device(), two_spheres(), settings(256, 1.0));
  const surface::FastAtlasImage big = rig.render(device(), rig.scene.camera);
  surface::FastAtlasSettings quarter = settings(256, 0.25);
  rig.pass->set_settings(quarter);
  const surface::FastAtlasImage small = rig.render(device(), rig.scene.camera);
  ASSERT_LT(small.counters.rows_used, big.counters.rows_used);
  const std::vector<uint32_t> ids = rig.pass->read_id_atlas();
  size_t stale = 0;
  for (size_t i = size_t(small.counters.rows_used) * 256; i < ids.size(); ++i) stale += ids[i] != kNone;
  EXPECT_EQ(stale, 0u);
  EXPECT_EQ(small.counters.hole_pixels, 0u);
}

// Every texel holding a triangle (border texels too) is the CPU direct light where the ray
// through its screen point meets that triangle's plane. The GPU maps the texel to the screen in
// float (an atlas coordinate below 256: within 3e-5 pixel), so the point may move by that much:
// 1e-4 of a triangle of a few pixels bounds it.
TEST_F(FastAtlasPassTest, EveryShadedTexelIsTheDirectLightAtItsPoint) {
  SphereSceneOptions o;
  o.lights = Lights::Point;
  FaRig rig(device(), sphere_scene(o), settings(256, 0.6));
  const Camera camera = rig.scene.camera;
  const surface::FastAtlasImage img = rig.render(device(), camera);
  const AtlasReadback a(*rig.pass);
  const std::vector<uint32_t>& ids = a.ids;
  std::vector<reference::ShadingPointQuery> queries;
  std::vector<glm::vec4> gpu;
  size_t border = 0;
  for (uint32_t y = 0; y < 256; ++y)
    for (uint32_t x = 0; x < 256; ++x) {
      const uint32_t id = ids[y * 256 + x];
      if (id == kNone) continue;
      const uint32_t t = id & PRISMOID_FA_TRIANGLE_MASK;
      border += (id & PRISMOID_FA_BORDER_BIT) != 0;
      const glm::dvec2 pixel = to_screen(a.map(t, img.counters.scale), glm::dvec2(x + 0.5, y + 0.5));
      const auto [mesh, local] = rig.triangles.local(t);
      queries.push_back({mesh, local, ray_plane_weights(rig.scene, rig.triangles, t, camera, kW, kH, pixel.x, pixel.y), camera.eye});
      gpu.push_back(a.colors[y * 256 + x]);
    }
  ASSERT_GT(queries.size(), 500u);
  EXPECT_GT(border, 0u);
  EXPECT_EQ(img.counters.shaded_texels, queries.size());
  EXPECT_EQ(img.counters.border_texels, border);
  // Alpha holds the texel's triangle + 1 (temporal reuse's check); the shading check wants 1.
  for (size_t k = 0; k < gpu.size(); ++k) {
    EXPECT_EQ(gpu[k].w, float(queries[k].triangle + 1)) << k;  // one mesh: local = global
    gpu[k].w = 1.0f;
  }
  const SampleCheck c = check_shaded_samples(rig.scene, queries, gpu, 1e-4);
  EXPECT_EQ(c.failures, 0u);
  std::printf("%zu texels (%zu border) against the reference; worst error %.3g of its tolerance\n", queries.size(), border, c.worst);
}

// The point of the triangle (corners a, b, c) nearest to the point of its plane with weights w, as
// weights: the double twin of fa_shade.glsl's nearest_on_triangle.
glm::dvec3 nearest_weights(const glm::dvec3& a, const glm::dvec3& b, const glm::dvec3& c, const glm::dvec3& w) {
  const glm::dvec3 p = w.x * a + w.y * b + w.z * c;
  // The plane point itself if it is inside, else the nearest point of the three edges.
  if (w.x >= 0.0 && w.y >= 0.0 && w.z >= 0.0) return w;
  glm::dvec3 best = w;
  double best_d = 1e300;
  const glm::dvec3 corners[3] = {a, b, c};
  for (int e = 0; e < 3; ++e) {
    const glm::dvec3 u = corners[e], v = corners[(e + 1) % 3];
    const double t = std::clamp(glm::dot(p - u, v - u) / glm::dot(v - u, v - u), 0.0, 1.0);
    const double d = glm::length(p - (u + t * (v - u)));
    if (d < best_d) {
      best_d = d;
      best = glm::dvec3(0.0);
      best[e] = 1.0 - t;
      best[(e + 1) % 3] = t;
    }
  }
  return best;
}

// Below half a texel per pixel, border texels are shaded at the point of their triangle nearest to
// where their pixel ray meets its plane (not at that plane point, which can lie far off the
// surface); texels inside keep their own point. Every texel against the direct light there.
TEST_F(FastAtlasPassTest, BelowHalfATexelPerPixelBorderTexelsAreShadedOnTheirTriangle) {
  SphereSceneOptions o;
  o.lights = Lights::Point;
  FaRig rig(device(), sphere_scene(o), settings(256, 0.2));
  const Camera camera = rig.scene.camera;
  const surface::FastAtlasImage img = rig.render(device(), camera);
  ASSERT_LT(img.counters.scale, PRISMOID_FA_EXTRAPOLATE_SCALE);
  const AtlasReadback a(*rig.pass);
  std::vector<reference::ShadingPointQuery> queries;
  std::vector<glm::vec4> gpu;
  size_t held = 0;
  for (uint32_t y = 0; y < 256; ++y)
    for (uint32_t x = 0; x < 256; ++x) {
      const uint32_t id = a.ids[y * 256 + x];
      if (id == kNone) continue;
      const uint32_t t = id & PRISMOID_FA_TRIANGLE_MASK;
      const glm::dvec2 pixel = to_screen(a.map(t, img.counters.scale), glm::dvec2(x + 0.5, y + 0.5));
      const auto [mesh, local] = rig.triangles.local(t);
      const SceneMesh& m = rig.scene.meshes[mesh];
      const auto& tri = m.triangles[local];
      glm::dvec3 w = ray_plane_weights(rig.scene, rig.triangles, t, camera, kW, kH, pixel.x, pixel.y);
      if (w.x < 0.0 || w.y < 0.0 || w.z < 0.0) {
        w = nearest_weights(m.positions[tri[0]], m.positions[tri[1]], m.positions[tri[2]], w);
        ++held;
      }
      queries.push_back({mesh, local, w, camera.eye});
      glm::vec4 g = a.colors[y * 256 + x];
      g.w = 1.0f;
      gpu.push_back(g);
    }
  ASSERT_GT(queries.size(), 100u);
  EXPECT_GT(held, 50u);
  const SampleCheck c = check_shaded_samples(rig.scene, queries, gpu, 1e-4);
  EXPECT_EQ(c.failures, 0u);
  std::printf("%zu texels (%zu held to their triangle) against the reference; worst error %.3g of its tolerance\n", queries.size(), held,
              c.worst);
}

// Every pixel is the hard-edge filter (the CPU twin) of its four taps at its atlas position; on a
// cube seen at scale 0.45, taps across its 90-degree edges do not count, and one, two, three and
// four usable taps all occur (none usable, where the nearest texel stands in, is rarer).
TEST_F(FastAtlasPassTest, EveryPixelIsTheHardEdgeFilterOfItsTaps) {
  FaRig rig(device(), flat_cube_scene(), settings(256, 0.45));
  const Camera camera = rig.scene.camera;
  const surface::FastAtlasImage img = rig.render(device(), camera);
  const AtlasReadback a(*rig.pass);
  const std::vector<uint32_t>& ids = a.ids;
  const std::vector<glm::vec4>& colors = a.colors;
  const fastatlas::SceneAdjacency& adj = rig.pass->adjacency();
  std::array<size_t, 5> cases{};
  size_t failures = 0, compared = 0;
  for (uint32_t py = 0; py < kH; ++py)
    for (uint32_t px = 0; px < kW; ++px) {
      const glm::uvec4 v = img.visibility[py * kW + px];
      if (v.x == 0) continue;
      const uint32_t t = v.x - 1;
      const glm::dvec2 u = fastatlas::to_atlas(a.map(t, img.counters.scale), glm::dvec2(px + 0.5, py + 0.5)) - 0.5;
      const glm::ivec2 base(int(std::floor(u.x)), int(std::floor(u.y)));
      const glm::dvec2 at = u - glm::dvec2(base);
      // Taps within 1e-3 texel of a texel boundary could land either side on the GPU: skipped.
      if (std::min({at.x, at.y, 1.0 - at.x, 1.0 - at.y}) < 1e-3) continue;
      fastatlas::FilterTaps taps;
      int n = 0;
      double peak = 0.0;
      for (int k = 0; k < 4; ++k) {
        const glm::ivec2 q = base + glm::ivec2(k & 1, k >> 1);
        const bool inside = q.x >= 0 && q.y >= 0 && q.x < 256 && q.y < 256;
        const uint32_t raw = inside ? ids[size_t(q.y) * 256 + size_t(q.x)] : kNone;
        const uint32_t id = raw == kNone ? kNone : raw & PRISMOID_FA_TRIANGLE_MASK;
        taps.value[size_t(k)] = raw == kNone ? glm::dvec3(0.0) : glm::dvec3(colors[size_t(q.y) * 256 + size_t(q.x)]);
        taps.held[size_t(k)] = raw != kNone;
        bool neighbour_smooth = false;
        for (int e = 0; e < 3; ++e) neighbour_smooth |= adj.neighbours[t][size_t(e)] == id && (adj.smooth[t] >> e & 1) != 0;
        taps.usable[size_t(k)] = id == t || (id != kNone && neighbour_smooth);
        n += taps.usable[size_t(k)];
        peak = std::max(peak, std::max({taps.value[size_t(k)].x, taps.value[size_t(k)].y, taps.value[size_t(k)].z}));
      }
      const glm::dvec3 expect = fastatlas::hard_edge_filter(taps, at);
      ++cases[size_t(n)];
      ++compared;
      // The GPU's position is within 1e-4 texel of this one: weights move by 2e-4 at most.
      const double tol = peak * 1e-3 + 1e-6;
      for (int ch = 0; ch < 3; ++ch)
        if (std::abs(double(img.rgba[4 * (py * kW + px) + size_t(ch)]) - expect[ch]) > tol && failures++ < 5)
          ADD_FAILURE() << "pixel " << px << " " << py << " (" << n << " usable taps): GPU " << img.rgba[4 * (py * kW + px) + size_t(ch)]
                        << ", filter " << expect[ch];
    }
  EXPECT_EQ(failures, 0u);
  EXPECT_GT(compared, size_t(kW * kH / 5));
  for (int n : {1, 2, 3, 4}) EXPECT_GT(cases[size_t(n)], 0u) << n << " usable taps never occurred";
  std::printf("%zu pixels; usable taps 0/1/2/3/4: %zu %zu %zu %zu %zu\n", compared, cases[0], cases[1], cases[2], cases[3], cases[4]);
}

// Two large triangles sharing a corner (one chart, through the vertex merge), the second partly
// behind the first: the chart overlaps itself on the screen, and the ID atlas's depth test
// decides which triangle a texel shows.
SurfaceScene overlapping_pair() {
  SurfaceScene s = sphere_scene({});
  s.meshes.clear();
  s.meshes.push_back({});
  SceneMesh& m = s.meshes.back();
  m.name = "pair";
  m.positions = {{0.0, 1.2, -1.0}, {-1.6, -1.0, 0.0}, {0.6, -1.0, 0.0}, {-0.6, -1.0, -2.0}, {1.6, -1.0, -2.0}};
  m.triangles = {{0, 3, 4}, {0, 1, 2}};  // the one behind first: the lower ID must not win by being lower
  s.camera.eye = {0.0, 0.0, 4.0};
  s.camera.target = {0.0, 0.0, -1.0};
  return s;
}

// The compute raster of the ID atlas (fa_raster.glsl) against a CPU ray cast in double: at every
// texel of every chart's box, the ray through the screen point the chart maps the texel centre to
// is cast against the chart's triangles. Where that point is a pixel centre at which the
// visibility pass found a triangle of the chart, the texel holds that triangle. Elsewhere, where
// a triangle of the chart holds the point clearly (weights above 1e-4, beyond the near plane, on
// the screen), the texel holds one that holds it, at the nearest depth up to 1e-5 (ties: either);
// where none holds it even loosely, the raster wrote nothing there; nothing the raster wrote lies
// outside its triangle. Scenes: spheres and a floor whose two large triangles go through the
// chunk pass, at scale 1 and at a scale where no texel centre is a pixel centre; the floor across
// the near plane; a chart overlapping itself (there, at 0.61, depth decides).
TEST_F(FastAtlasPassTest, TheIdAtlasHoldsTheNearestTriangleOfItsChartAtEachTexel) {
  SurfaceScene near_floor = two_spheres();
  near_floor.camera.eye = {0.0, -0.95, 2.5};
  near_floor.camera.target = {0.0, -0.9, 0.0};
  struct Case {
    const char* name;
    SurfaceScene scene;
    double scale;
  };
  Case cases[] = {{"two spheres", two_spheres(), 1.0}, {"two spheres at 0.61", two_spheres(), 0.61},
                  {"floor across the near plane", near_floor, 1.0}, {"overlapping pair", overlapping_pair(), 1.0},
                  {"overlapping pair at 0.61", overlapping_pair(), 0.61}};
  for (Case& k : cases) {
    SCOPED_TRACE(k.name);
    FaRig rig(device(), k.scene, settings(512, k.scale));
    const Camera& camera = rig.scene.camera;
    const surface::FastAtlasImage img = rig.render(device(), camera);
    ASSERT_TRUE(img.counters.fits);
    const AtlasReadback a(*rig.pass);
    std::map<uint32_t, std::vector<uint32_t>> chart_triangles;
    for (uint32_t t = 0; t < a.parent.size(); ++t)
      if (a.parent[t] != kNone) chart_triangles[a.parent[t]].push_back(t);
    const glm::dvec3 forward = glm::normalize(camera.target - camera.eye);
    struct Hit {
      uint32_t triangle;
      double depth;
      bool clear;  // weights above 1e-4, beyond the near plane by 1e-5 of it, on the screen by 1e-4 pixel
    };
    size_t covered = 0, overlapped = 0, as_seen = 0, failures = 0;
    for (const auto& [root, members] : chart_triangles) {
      const glm::uvec4 p = a.placed[root];
      const fastatlas::ChartMap map = a.map(root, img.counters.scale);
      for (uint32_t y = p.y; y < p.y + p.w; ++y)
        for (uint32_t x = p.x; x < p.x + (p.z & 0x7fffffffu); ++x) {
          const glm::dvec2 q = to_screen(map, {x + 0.5, y + 0.5});
          const uint32_t id = a.ids[size_t(y) * 512 + x];
          const bool rasterized = id != kNone && (id & (PRISMOID_FA_BORDER_BIT | PRISMOID_FA_SEED_BIT)) == 0;
          // A pixel centre where the visibility pass found a triangle of this chart: that one.
          const glm::dvec2 corner = q - 0.5;
          if (corner == glm::floor(corner) && corner.x >= 0 && corner.y >= 0 && corner.x < kW && corner.y < kH) {
            const uint32_t v = img.visibility[size_t(corner.y) * kW + size_t(corner.x)].x;
            if (v != 0 && a.parent[v - 1] == root) {
              ++as_seen;
              if (id != v - 1 && failures++ < 8)
                ADD_FAILURE() << "texel (" << x << ", " << y << "), chart " << root << ": " << id << ", the visibility pass saw " << v - 1;
              continue;
            }
          }
          const double margin = 1e-4;
          const bool on_screen = q.x >= -margin && q.y >= -margin && q.x <= kW + margin && q.y <= kH + margin;
          const bool well_on_screen = q.x >= margin && q.y >= margin && q.x <= kW - margin && q.y <= kH - margin;
          std::vector<Hit> hits;  // the chart's triangles holding the point, loosely
          if (on_screen) {
            const glm::dvec3 d = reference::ray_direction(camera, kW, kH, q.x, q.y);
            for (uint32_t t : members) {
              const glm::dvec3 w = ray_plane_weights(rig.scene, rig.triangles, t, camera, kW, kH, q.x, q.y);
              if (!(std::min({w.x, w.y, w.z}) >= -1e-4)) continue;
              const auto [mesh, local] = rig.triangles.local(t);
              const SceneMesh& m = rig.scene.meshes[mesh];
              const auto& tri = m.triangles[local];
              const glm::dvec3 point = w.x * m.positions[tri[0]] + w.y * m.positions[tri[1]] + w.z * m.positions[tri[2]];
              const double depth = glm::dot(point - camera.eye, forward);
              if (!(depth >= camera.near_distance * (1.0 - 1e-5)) || glm::dot(point - camera.eye, d) <= 0.0) continue;
              hits.push_back({t, depth, std::min({w.x, w.y, w.z}) > 1e-4 && depth > camera.near_distance * (1.0 + 1e-5) && well_on_screen});
            }
          }
          const bool clear = std::any_of(hits.begin(), hits.end(), [](const Hit& h) { return h.clear; });
          covered += clear;
          overlapped += clear && hits.size() >= 2 &&
                        std::any_of(hits.begin(), hits.end(), [&](const Hit& h) { return h.depth > hits[0].depth * 1.01 || h.depth < hits[0].depth * 0.99; });
          auto fail = [&](const std::string& what) {
            if (failures++ < 8) ADD_FAILURE() << "texel (" << x << ", " << y << "), chart " << root << ", id " << id << ": " << what;
          };
          if (clear && !rasterized) fail("the chart holds its centre, the raster left it empty");
          if (!rasterized) continue;
          const auto own = std::find_if(hits.begin(), hits.end(), [&](const Hit& h) { return h.triangle == id; });
          if (own == hits.end()) {
            fail("its triangle does not hold its centre");
            continue;
          }
          double nearest = own->depth;
          for (const Hit& h : hits) nearest = std::min(nearest, h.depth);
          if (own->depth > nearest * (1.0 + 1e-5)) fail("a nearer triangle of the chart holds its centre");
        }
    }
    EXPECT_EQ(failures, 0u);
    EXPECT_GT(double(covered + as_seen), kW * kH / 10 * k.scale * k.scale);
    if (std::string(k.name) == "overlapping pair at 0.61") {
      EXPECT_GT(overlapped, 100u);  // the depth test was needed
    }
    if (k.scale == 1.0) {
      EXPECT_GT(as_seen, size_t(kW * kH / 10));  // every texel centre a pixel centre
    }
    std::printf("%s: %zu texels where the visibility pass sampled; elsewhere %zu held clearly, %zu of them by more than one depth\n",
                k.name, as_seen, covered, overlapped);
  }
}

// A chunk list too short for the large triangles: they are covered in one invocation each
// (raster.comp's fallback), and the atlas is the same bit for bit.
TEST_F(FastAtlasPassTest, AFullChunkListGivesTheSameAtlas) {
  FaRig rig(device(), two_spheres(), settings(512));
  const surface::FastAtlasImage first = rig.render(device(), rig.scene.camera);
  const std::vector<uint32_t> ids = rig.pass->read_id_atlas();
  for (uint32_t capacity : {1u, 3u}) {
    surface::FastAtlasSettings s = settings(512);
    s.raster_chunks = capacity;
    rig.pass = std::make_unique<surface::FastAtlasPass>(device(), rig.scene, s);
    const surface::FastAtlasImage again = rig.render(device(), rig.scene.camera);
    EXPECT_EQ(rig.pass->read_id_atlas(), ids) << capacity << " chunks";
    EXPECT_EQ(again.rgba, first.rgba) << capacity << " chunks";
  }
}

// At scale 1 every pixel centre lands on a texel centre: the image is the forward image (a
// smooth sphere, a floor, shadows off) up to the float mapping's 1e-4 texel of blending.
TEST_F(FastAtlasPassTest, AtScaleOneTheImageIsTheForwardImage) {
  FaRig rig(device(), two_spheres(), settings(512));
  const Camera camera = rig.scene.camera;
  const surface::FastAtlasImage img = rig.render(device(), camera);
  EXPECT_GT(expect_forward_image(device(), rig, img, camera, {kW, kH}), size_t(kW * kH / 3));
}

// The camera just above a floor that reaches past it (its triangles cross the near plane) and
// inside a sphere's reach: boxes stay on the screen, nothing is NaN, no pixel finds no texel.
TEST_F(FastAtlasPassTest, TrianglesAcrossTheNearPlaneStayOnTheScreen) {
  SurfaceScene s = two_spheres();
  s.camera.eye = {0.0, -0.95, 2.5};
  s.camera.target = {0.0, -0.9, 0.0};
  FaRig rig(device(), s, settings(512));
  const surface::FastAtlasImage img = rig.render(device(), s.camera);
  EXPECT_TRUE(img.counters.fits);
  EXPECT_EQ(img.counters.hole_pixels, 0u);
  for (float v : img.rgba) ASSERT_TRUE(std::isfinite(v));
  for (const glm::ivec4& b : rig.pass->read_boxes()) {
    if (b.x == 0x7fffffff) continue;
    EXPECT_GE(b.x, 0);
    EXPECT_GE(b.y, 0);
    EXPECT_LE(-b.z, int(kW));
    EXPECT_LE(-b.w, int(kH));
  }
  expect_boxes_and_packing(rig, img, s.camera, 512, 1.0);
}

// At a low scale a small separate object (its own chart) can be smaller than a texel: no texel
// centre lies in any of its triangles, so the raster gives it none (the Cornell box's ceiling
// light at 96 x 72 and a quarter of a texel per pixel side). The seed pass gives it one, which
// the borders grow, so its pixels read its own shading (the light's emission), not a hole.
TEST_F(FastAtlasPassTest, AChartSmallerThanATexelIsSeeded) {
  SurfaceScene s = with_default_lighting(make_cornell_box(), make_cornell_box().camera);
  uint32_t first_light = 0, light_end = 0;
  for (const SceneMesh& m : s.meshes) {
    if (glm::length(s.materials[m.material].emission) > 0.0) {
      light_end = first_light + uint32_t(m.triangles.size());
      break;
    }
    first_light += uint32_t(m.triangles.size());
  }
  ASSERT_GT(light_end, first_light);
  FaRig rig(device(), s, settings(256, 0.25));
  const surface::FastAtlasImage img = rig.render(device(), rig.scene.camera);
  size_t light_pixels = 0;
  for (const glm::uvec4& v : img.visibility) light_pixels += v.x > first_light && v.x <= light_end;
  ASSERT_GT(light_pixels, 0u);
  size_t light_texels = 0, seeded = 0;
  for (uint32_t id : rig.pass->read_id_atlas()) {
    const uint32_t t = id & PRISMOID_FA_TRIANGLE_MASK;
    if (id == kNone || t < first_light || t >= light_end) continue;
    ++light_texels;
    seeded += (id & PRISMOID_FA_SEED_BIT) != 0;
  }
  EXPECT_GT(seeded, 0u);
  EXPECT_GT(light_texels, seeded);  // the border grew around the seed
  EXPECT_EQ(img.counters.hole_pixels, 0u);
  std::printf("the light: %zu pixels, %zu texels (%zu seeded)\n", light_pixels, light_texels, seeded);
}

// At a fiftieth of a texel per pixel a wall of the Cornell box holds a few texels, most of them
// border texels whose pixel rays meet its plane tens of pixels beyond it (outside the room, in the
// shadow of its walls): walls rendered black while no pixel counted as a hole (the left wall's mean
// was 0.17 of the reference's). Below half a texel per pixel a border texel's shading point is held
// to its triangle, so every surface keeps shading of its own: its mean within a factor of 3 of the
// reference's (a few texels per wall cannot follow the light's falloff and shadows across it). At
// a hundredth, one or two texels per surface, a surface whose samples all fall in shadow is dark
// by sampling alone, and no such bound holds.
TEST_F(FastAtlasPassTest, AtAFiftiethOfATexelPerPixelEverySurfaceKeepsItsShading) {
  const SurfaceScene s = with_default_lighting(make_cornell_box(), make_cornell_box().camera);
  constexpr uint32_t w = 256, h = 192;
  reference::DirectLightOptions options;
  options.shadows = true;
  const std::vector<glm::dvec3> ref = reference::supersampled_direct_light(s, s.camera, w, h, 1, options);
  for (double scale : {0.02}) {
    surface::FastAtlasSettings fa = settings(256, scale);
    fa.shadows = true;
    FaRig rig(device(), s, fa);
    const surface::FastAtlasImage img = rig.render(device(), rig.scene.camera, w, h);
    std::map<uint32_t, glm::dvec3> sums;  // per mesh: FastAtlas, reference, pixels
    for (size_t i = 0; i < img.visibility.size(); ++i) {
      const uint32_t v = img.visibility[i].x;
      if (v == 0) continue;
      glm::dvec3& sum = sums[rig.triangles.local(v - 1).first];
      const double shown = (double(img.rgba[4 * i]) + double(img.rgba[4 * i + 1]) + double(img.rgba[4 * i + 2])) / 3.0;
      sum += glm::dvec3(shown, (ref[i].x + ref[i].y + ref[i].z) / 3.0, 1.0);
    }
    size_t surfaces = 0;
    for (const auto& [mesh, sum] : sums) {
      if (sum.z < 200.0 || sum.y <= 0.0) continue;
      ++surfaces;
      const double ratio = sum.x / sum.y;
      EXPECT_GT(ratio, 1.0 / 3.0) << "scale " << scale << ", mesh " << mesh << " (" << sum.z << " pixels)";
      EXPECT_LT(ratio, 3.0) << "scale " << scale << ", mesh " << mesh;
      std::printf("scale %.2f, mesh %u: %.0f pixels, mean %.4f against the reference's %.4f\n", scale, mesh, sum.z, sum.x / sum.z,
                  sum.y / sum.z);
    }
    EXPECT_GE(surfaces, 5u);
  }
}

// A million visible triangles: a grid in a plane facing the camera, each 2 x 1 pixel quad split
// along its diagonal so that each triangle holds exactly one pixel centre (a quarter pixel from
// the diagonal) of a 1024 x 1024 image. Every triangle is visible, all in one chart, packed at
// scale 1 in a 2K atlas, and the image is the forward image.
TEST_F(FastAtlasPassTest, AMillionVisibleTrianglesMakeOneChart) {
  constexpr uint32_t kSide = 1024;
  SurfaceScene s = sphere_scene({});
  s.meshes.clear();
  s.point_lights.clear();
  s.meshes.push_back({});
  SceneMesh& grid = s.meshes.back();
  grid.name = "grid";
  Camera& c = s.camera;
  c.eye = {0.0, 0.0, 4.0};
  c.target = {0.0, 0.0, 0.0};
  c.up = {0.0, 1.0, 0.0};
  c.fovy_degrees = 40.0;
  const double pixel = 2.0 * 4.0 * std::tan(glm::radians(20.0)) / kSide;  // world size of a pixel in the plane z = 0
  const double x0 = -0.5 * kSide * pixel, y0 = 0.5 * kSide * pixel;      // the image's top-left corner
  for (uint32_t j = 0; j <= kSide; ++j)
    for (uint32_t i = 0; i <= kSide / 2; ++i) grid.positions.push_back({x0 + 2.0 * i * pixel, y0 - double(j) * pixel, 0.0});
  const uint32_t row = kSide / 2 + 1;
  for (uint32_t j = 0; j < kSide; ++j)
    for (uint32_t i = 0; i < kSide / 2; ++i) {
      const uint32_t a = j * row + i, b = a + 1, cc = a + row, d = cc + 1;
      grid.triangles.push_back({a, d, b});   // above the diagonal from the top-left to the bottom-right corner
      grid.triangles.push_back({a, cc, d});  // below it
    }
  FaRig rig(device(), s, settings(2048));
  const surface::FastAtlasImage img = rig.render(device(), c, kSide, kSide);
  EXPECT_EQ(img.counters.visible_triangles, grid.triangles.size());
  EXPECT_GE(img.counters.visible_triangles, 1000000u);
  EXPECT_EQ(img.counters.charts, 1u);
  EXPECT_TRUE(img.counters.fits);
  EXPECT_EQ(img.counters.scale, 1.0);
  EXPECT_EQ(img.counters.hole_pixels, 0u);
  EXPECT_EQ(expect_forward_image(device(), rig, img, c, {kSide, kSide}), size_t(kSide) * kSide);  // every pixel covered
}

// Temporal reuse (appendix D) with a refresh every 3 frames, the camera orbiting a diffuse sphere
// lit by a point light (shading that does not depend on the eye): the frames between refreshes take
// most texels from the last atlas, shade the rest, and draw the image a fresh frame draws within
// what moving a point by half a texel changes; every third frame shades everything again; no
// reused texel carries another triangle's shading (each carries its own triangle in alpha).
TEST_F(FastAtlasPassTest, TemporalReuseCarriesShadingBetweenRefreshes) {
  SphereSceneOptions o;
  o.lights = Lights::Point;
  surface::FastAtlasSettings s = settings(512);
  s.refresh = 3;
  FaRig rig(device(), sphere_scene(o), s);
  FaRig fresh(device(), sphere_scene(o), settings(512));
  Camera c = rig.scene.camera;
  double peak = 0.0;
  for (int frame = 0; frame < 7; ++frame) {
    c.eye = glm::dvec3(4.0 * std::sin(0.01 * frame), 0.0, 4.0 * std::cos(0.01 * frame));  // 0.57 degrees a frame
    const surface::FastAtlasImage img = rig.render(device(), c);
    const bool refresh = frame % 3 == 0;
    EXPECT_EQ(img.counters.temporal, !refresh) << "frame " << frame;
    if (refresh) {
      EXPECT_EQ(img.counters.reused_texels, 0u) << "frame " << frame;
      continue;
    }
    const uint32_t all = img.counters.reused_texels + img.counters.shaded_texels;
    EXPECT_GT(img.counters.reused_texels, all / 2) << "frame " << frame;
    EXPECT_GT(img.counters.shaded_texels, 0u) << "frame " << frame << ": texels new to the view are shaded";
    // Every texel holds its own triangle's shading, reused or not.
    const AtlasReadback a(*rig.pass);
    size_t foreign = 0;
    for (size_t i = 0; i < a.ids.size(); ++i)
      if (a.ids[i] != kNone) foreign += a.colors[i].w != float((a.ids[i] & PRISMOID_FA_TRIANGLE_MASK) + 1);
    EXPECT_EQ(foreign, 0u) << "frame " << frame;
    const surface::FastAtlasImage truth = fresh.render(device(), c);
    double worst = 0.0;
    for (size_t i = 0; i < img.rgba.size(); ++i) {
      worst = std::max(worst, double(std::abs(img.rgba[i] - truth.rgba[i])));
      peak = std::max(peak, double(truth.rgba[i]));
    }
    // Diffuse shading under a point light moves by at most a few percent of the peak over half a
    // texel of the sphere (a texel is a pixel here: 1/40 of the sphere's radius).
    EXPECT_LT(worst, 0.05 * peak) << "frame " << frame;
  }
}

// Nothing in view: no charts, nothing shaded, the sky.
TEST_F(FastAtlasPassTest, NothingVisibleGivesAnEmptyAtlas) {
  SphereSceneOptions o;
  o.sky = true;
  SurfaceScene s = sphere_scene(o);
  s.camera.target = {0.0, 0.0, 8.0};  // looking away
  FaRig rig(device(), s, settings(128));
  const surface::FastAtlasImage img = rig.render(device(), s.camera);
  EXPECT_EQ(img.counters.charts, 0u);
  EXPECT_EQ(img.counters.shaded_texels, 0u);
  EXPECT_TRUE(img.counters.fits);
  for (size_t i = 0; i < img.visibility.size(); ++i) {
    EXPECT_EQ(img.visibility[i].x, 0u);
    EXPECT_EQ(img.rgba[4 * i + 3], 0.0f);
  }
}

}  // namespace
}  // namespace prismoid::test
