// The Htex backend's passes on the GPU (lavapipe, validation on) against the double-precision
// CPU side: the marked shadels are the footprints of the visible pixels at the levels the GPU
// chose (and those levels are the CPU's level of detail, rounded), every shaded texel is the
// direct-light reference at its texel point, every gathered pixel is htex_lookup over the
// shaded texels, and the allocator biases, persists, releases and overflows as documented.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <set>

#include <glm/geometric.hpp>

#include "renderer/reference/direct_light.hpp"
#include "renderer/reference/htex_reference.hpp"
#include "renderer/reference/tet_ray.hpp"
#include "scene/input_error.hpp"
#include "support/gpu_fixture.hpp"
#include "surface/forward_comparison.hpp"
#include "surface/htex_fixture.hpp"
#include "surface/surface_test_scenes.hpp"
#include "surface/texture_space_checks.hpp"

namespace prismoid::test {
namespace {

constexpr double kU = 0x1p-24;
constexpr uint32_t kW = 96, kH = 72;

htex::LayoutOptions density(double texels_per_unit) {
  htex::LayoutOptions o;
  o.texels_per_unit = texels_per_unit;
  return o;
}

surface::HtexSettings unshadowed(uint32_t pages = 256) {
  surface::HtexSettings s;
  s.pool_pages = pages;
  s.shadows = false;
  return s;
}

SurfaceScene diffuse_sphere() { return sphere_scene({}); }

std::set<uint32_t> marked_shadels(const HtexRig& rig) {
  const auto occupancy = rig.read<uint32_t>(rig.pass->occupancy());
  const uint32_t group_columns = rig.geometry.group_columns(), shadel_columns = rig.geometry.layout.shadel_columns();
  std::set<uint32_t> out;
  for (uint32_t g = 0; g < rig.geometry.group_count(); ++g)
    for (uint32_t bit = 0; bit < 64; ++bit)
      if (occupancy[2 * g + bit / 32] & (1u << (bit % 32)))
        out.insert(((g / group_columns) * 8 + bit / 8) * shadel_columns + (g % group_columns) * 8 + bit % 8);
  return out;
}

struct PixelPoint {
  uint32_t mesh = 0, triangle = 0, face = 0, level = 0;
  glm::dvec3 bary{0.0};
};
// The covered pixels' stored points (triangle, face, level and weights as the gather reads them).
std::vector<std::pair<size_t, PixelPoint>> pixel_points(const HtexRig& rig, const surface::HtexImage& img) {
  std::vector<std::pair<size_t, PixelPoint>> out;
  for (size_t i = 0; i < img.visibility.size(); ++i) {
    const glm::uvec4 v = img.visibility[i];
    if (v.x == 0 || v.y == PRISMOID_HTEX_NONE) continue;
    PixelPoint p;
    std::tie(p.mesh, p.triangle) = rig.local_triangle(v.x - 1);
    p.face = uint32_t(rig.geometry.meshes[p.mesh].face_of_triangle[p.triangle]);
    p.level = v.y;
    p.bary = stored_barycentrics(v);
    out.emplace_back(i, p);
  }
  return out;
}

class HtexPassTest : public GpuTest {};

// Marking: the marked shadels are exactly the union of the pixels' footprints at the GPU's
// levels. A texel the float footprint may list or not (its weight within rounding of 0, or its
// tap within rounding of a texel boundary) may be marked or not: required are the texels of
// weight > 1e-5, allowed the taps of s +- 1e-5 texel. The levels are the CPU's level of detail
// from the pixel rays in double, rounded to nearest, except within 1e-3 of a rounding boundary.
TEST_F(HtexPassTest, MarksExactlyTheFootprintsOfVisiblePixelsAtTheChosenLevel) {
  for (const bool close : {false, true}) {
  HtexRig rig(device(), diffuse_sphere(), density(close ? 160.0 : 48.0), unshadowed());
  Camera camera = rig.scene.camera;
  if (close) camera.eye = glm::dvec3(0.3, 0.2, 2.4);  // levels 0 to 3 across the sphere
  const uint32_t w = close ? 120 : kW, h = close ? 90 : kH;
  const surface::HtexImage img = rig.render(device(), camera, w, h);
  const std::set<uint32_t> gpu = marked_shadels(rig);
  const auto& layout = rig.geometry.layout;
  std::set<uint32_t> required, allowed, exact;
  size_t level_checked = 0, level_ambiguous = 0, level_wrong = 0;
  double worst_bary = 0.0;
  size_t bary_failures = 0;
  std::set<uint32_t> levels_seen;
  for (const auto& [i, p] : pixel_points(rig, img)) {
    const HalfedgeMesh& mesh = rig.geometry.meshes[p.mesh];
    const reference::HtexFootprint fp = reference::htex_footprint(rig.geometry.meshes, layout, p.mesh, p.face, p.bary, p.level);
    for (uint32_t k = 0; k < fp.count; ++k) {
      const uint32_t s = layout.shadel_of(layout.virtual_texel(fp.texels[k].texel));
      exact.insert(s);
      if (fp.texels[k].weight > 1e-5) required.insert(s);
    }
    const uint32_t n = layout.meshes()[p.mesh].side(p.level);
    for (const htex::QuadPoint& q : htex::face_point_quads(mesh, p.face, p.bary)) {
      const glm::dvec2 s = q.xy * double(n) - 0.5;
      for (int64_t j = int64_t(std::floor(s.y - 1e-5)); j <= int64_t(std::floor(s.y + 1e-5)) + 1; ++j)
        for (int64_t t = int64_t(std::floor(s.x - 1e-5)); t <= int64_t(std::floor(s.x + 1e-5)) + 1; ++t)
          if (t >= 0 && j >= 0 && t < n && j < n)
            allowed.insert(layout.shadel_of(layout.virtual_texel({layout.meshes()[p.mesh].first_quad + q.edge, p.level, uint32_t(t), uint32_t(j)})));
    }
    // The level and the weights from the pixel's ray in double.
    const auto& tri = rig.scene.meshes[p.mesh].triangles[p.triangle];
    const auto& pos = rig.scene.meshes[p.mesh].positions;
    // The float ray-plane intersection's error: every product of tv = eye - p0, d and the
    // edges is off by a few u of its magnitude (inputs rounded to float included), divided by
    // det = e1 . (d x e2): 64 u (|tv| + |eye| + |p0|) |d| (|e1| + |e2|) / |det| bounds it.
    double bary_tol = 0.0;
    auto bary_at = [&](double px, double py) {
      const glm::dvec3 d = reference::ray_direction(camera, w, h, px, py);
      const glm::dvec3 e1 = pos[tri[1]] - pos[tri[0]], e2 = pos[tri[2]] - pos[tri[0]];
      const glm::dvec3 pv = glm::cross(d, e2), tv = camera.eye - pos[tri[0]];
      const double det = glm::dot(e1, pv);
      const double b1 = glm::dot(tv, pv) / det, b2 = glm::dot(d, glm::cross(tv, e1)) / det;
      const glm::dvec3 o = rig.gpu.origin;
      bary_tol = 64.0 * kU * (glm::length(tv) + glm::length(camera.eye - o) + glm::length(pos[tri[0]] - o)) * glm::length(d) *
                 (glm::length(e1) + glm::length(e2)) / std::abs(det);
      return glm::dvec3(1.0 - b1 - b2, b1, b2);
    };
    const double x = double(i % w) + 0.5, y = double(i / w) + 0.5;
    const glm::dvec3 b = bary_at(x, y);
    const double tol_here = bary_tol;
    const bool inside = b.x >= 0.0 && b.y >= 0.0 && b.z >= 0.0;
    if (inside) {
      worst_bary = std::max(worst_bary, glm::length(b - p.bary) / tol_here);
      bary_failures += glm::length(b - p.bary) > tol_here;
    }
    const double lod = reference::htex_level_of_detail(layout.meshes()[p.mesh], p.face, b, bary_at(x + 1.0, y) - b, bary_at(x, y + 1.0) - b);
    const double r = lod + 0.5;
    const uint32_t levels = layout.meshes()[p.mesh].levels;
    const auto expected = uint32_t(std::clamp(std::floor(r), 0.0, double(levels - 1)));
    levels_seen.insert(p.level);
    if (std::abs(r - std::round(r)) < 1e-3 && std::round(r) >= 0.0) {
      ++level_ambiguous;
    } else {
      ++level_checked;
      level_wrong += p.level != expected;
    }
  }
  ASSERT_GT(required.size(), 50u);
  size_t missing = 0, extra = 0;
  for (uint32_t s : required) missing += !gpu.count(s);
  for (uint32_t s : gpu) extra += !allowed.count(s);
  EXPECT_EQ(missing, 0u) << "shadels read by a pixel's footprint but not marked";
  EXPECT_EQ(extra, 0u) << "marked shadels no pixel's footprint reads";
  EXPECT_EQ(level_wrong, 0u) << "of " << level_checked << " pixels";
  EXPECT_GT(level_checked, 1000u);
  EXPECT_GE(levels_seen.size(), close ? 2u : 1u);
  EXPECT_EQ(bary_failures, 0u);
  size_t differ = 0;
  for (uint32_t s : gpu) differ += !exact.count(s);
  for (uint32_t s : exact) differ += !gpu.count(s);
  std::printf("[ marking ] %zu marked shadels, %zu in the exact union (%zu differ, all within rounding), %zu pixels' levels checked "
              "(%zu within 1e-3 of rounding), levels used %zu, stored weights within %.2g of their bound from the double ray's\n",
              gpu.size(), exact.size(), differ, level_checked, level_ambiguous, levels_seen.size(), worst_bary);
  }
}

// Shading and gather: every texel of every task is the direct-light reference at its texel
// point (vertex corners at the vertex, ghosts in the plane), within the forward test's rounding
// budget plus the reference's change over a few float roundings of the point; every covered
// pixel is htex_lookup over those texels at the GPU's level and weights.
TEST_F(HtexPassTest, ShadesEveryTaskTexelAndGathersTheHtexLookup) {
  for (const bool ggx : {false, true}) {
    SphereSceneOptions o;
    o.ggx = ggx;
    o.sky = true;
    HtexRig rig(device(), sphere_scene(o), density(40.0), unshadowed());
    const Camera camera = rig.scene.camera;
    const surface::HtexImage img = rig.render(device(), camera, kW, kH);
    const surface::HtexCounters& c = img.counters;
    ASSERT_GT(c.shaded_shadels, 0u);
    EXPECT_EQ(c.hole_pixels, 0u);
    EXPECT_FALSE(c.overflow);
    EXPECT_EQ(c.bias_levels, 0u);
    EXPECT_EQ(c.shaded_shadels, c.marked_shadels);
    const auto& layout = rig.geometry.layout;
    const auto tasks = rig.read<uint32_t>(rig.pass->tasks());
    const auto pages = rig.read<uint32_t>(rig.pass->page_table());
    const auto pool = rig.read<glm::vec4>(rig.pass->pool());

    // Every task texel, and its CPU twin.
    std::vector<reference::ShadingPointQuery> queries;
    std::vector<size_t> slots;
    std::vector<htex::TexelAddress> addresses;
    for (uint32_t t = 0; t < c.shaded_shadels; ++t) {
      const uint32_t shadel = tasks[t];
      const glm::uvec2 origin((shadel % layout.shadel_columns()) * 8, (shadel / layout.shadel_columns()) * 8);
      for (uint32_t k = 0; k < 64; ++k) {
        const glm::uvec2 v = origin + glm::uvec2(k % 8, k / 8);
        const auto a = layout.texel_at(v);
        if (!a) continue;
        const uint32_t page = pages[layout.group_of(v)];
        ASSERT_NE(page, PRISMOID_HTEX_NOT_RESIDENT);
        const uint32_t mesh = layout.mesh_of_quad(a->quad);
        const htex::MeshLayout& ml = layout.meshes()[mesh];
        const htex::TexelPoint tp = htex::texel_point(rig.geometry.meshes[mesh], a->quad - ml.first_quad, ml.side(a->level), a->i, a->j);
        queries.push_back({mesh, rig.geometry.meshes[mesh].triangle_of_face[tp.face], tp.bary, camera.eye});
        slots.push_back(size_t(page) * 4096 + (v.y % 64) * 64 + v.x % 64);
        addresses.push_back(*a);
      }
    }
    EXPECT_EQ(queries.size(), c.shaded_texels);
    // Each texel against the CPU direct light at its point (texture_space_checks.hpp).
    std::vector<glm::vec4> gpu_values;
    for (size_t k : slots) gpu_values.push_back(pool[k]);
    const SampleCheck shading = check_shaded_samples(rig.scene, queries, gpu_values);
    EXPECT_EQ(shading.failures, 0u);
    EXPECT_GT(shading.peak, 0.1);
    reference::HtexTexture texture(layout, 3);
    for (size_t k = 0; k < queries.size(); ++k)
      texture.set(addresses[k], glm::dvec4(double(pool[slots[k]].x), double(pool[slots[k]].y), double(pool[slots[k]].z), 0.0));

    // Gather. The float lookup's quad coordinates are off by at most 4 u (two subtractions from
    // the stored weights), so s = x n - 1/2 by 6 n u, each bilinear weight by 12 n u; with at
    // most 12 taps and alpha >= 1/4 the normalized blend moves by 12 * 12 n u * 4 * 2 max|texel|,
    // plus the float sum's 16 u max|texel|.
    size_t gather_failures = 0, covered = 0, sky = 0;
    double worst_gather = 0.0;
    const auto points = pixel_points(rig, img);
    for (const auto& [i, p] : points) {
      ++covered;
      const reference::HtexFootprint fp = reference::htex_footprint(rig.geometry.meshes, layout, p.mesh, p.face, p.bary, p.level);
      double maxv = 0.0;
      for (uint32_t k = 0; k < fp.count; ++k) maxv = std::max(maxv, glm::length(texture.get(fp.texels[k].texel)));
      const glm::dvec4 expect = reference::htex_lookup(rig.geometry.meshes, layout, texture, p.mesh, p.face, p.bary, p.level);
      const double n = layout.meshes()[p.mesh].side(p.level);
      const double tol = maxv * kU * (1152.0 * n + 16.0) + 1e-30;
      bool ok = img.rgba[4 * i + 3] == 1.0f;
      for (int ch = 0; ch < 3; ++ch) {
        const double e = std::abs(double(img.rgba[4 * i + size_t(ch)]) - expect[ch]);
        worst_gather = std::max(worst_gather, e / tol);
        ok = ok && e <= tol;
      }
      if (!ok && gather_failures++ < 5) ADD_FAILURE() << "pixel " << i << ": GPU " << img.rgba[4 * i] << ", lookup " << expect.x << ", tolerance " << tol;
    }
    for (size_t i = 0; i < img.visibility.size(); ++i) {
      if (img.visibility[i].x != 0) continue;
      ++sky;
      const glm::dvec3 d = reference::ray_direction(camera, kW, kH, double(i % kW) + 0.5, double(i / kW) + 0.5);
      const glm::dvec3 L = rig.scene.sky.radiance(glm::normalize(d));
      EXPECT_EQ(img.rgba[4 * i + 3], 0.0f);
      for (int ch = 0; ch < 3; ++ch) EXPECT_NEAR(img.rgba[4 * i + size_t(ch)], L[ch], 1e-5);
    }
    EXPECT_EQ(gather_failures, 0u);
    EXPECT_GT(covered, size_t(kW * kH / 5));
    EXPECT_GT(sky, size_t(kW * kH / 5));
    std::printf("[ shading %s ] %zu texels of %u shadels: worst error %.3g of tolerance (peak %.3g); gather: %zu pixels, worst %.3g of "
                "tolerance; %zu sky pixels; pool %llu bytes, %u resident groups\n",
                ggx ? "GGX" : "diffuse", queries.size(), c.shaded_shadels, shading.worst, shading.peak, covered, worst_gather, sky,
                static_cast<unsigned long long>(c.pool_bytes), c.resident_groups);
  }
}

// Every covered pixel's footprint texels are resident.
size_t pixels_with_holes(const HtexRig& rig, const surface::HtexImage& img) {
  const auto pages = rig.read<uint32_t>(rig.pass->page_table());
  const auto& layout = rig.geometry.layout;
  size_t holes = 0;
  for (const auto& [i, p] : pixel_points(rig, img)) {
    const reference::HtexFootprint fp = reference::htex_footprint(rig.geometry.meshes, layout, p.mesh, p.face, p.bary, p.level);
    bool hole = false;
    for (uint32_t k = 0; k < fp.count; ++k)
      hole = hole || pages[layout.group_of(layout.virtual_texel(fp.texels[k].texel))] == PRISMOID_HTEX_NOT_RESIDENT;
    holes += hole;
  }
  return holes;
}

bool finite(const surface::HtexImage& img) {
  for (float v : img.rgba)
    if (!std::isfinite(v)) return false;
  return true;
}

// A pool too small for the level of detail: the allocator biases (and says so), the result fits
// and has no holes.
TEST_F(HtexPassTest, SmallPoolForcesTheBiasPass) {
  constexpr uint32_t kPages = 12;
  HtexRig rig(device(), diffuse_sphere(), density(160.0), unshadowed(kPages));
  Camera camera = rig.scene.camera;
  camera.eye = glm::dvec3(0.0, 0.0, 2.2);  // the sphere fills the view: level 0 over most of it
  const surface::HtexImage a = rig.render(device(), camera, 160, 120);
  const surface::HtexCounters& c = a.counters;
  EXPECT_GT(c.marked_groups_unbiased, kPages);
  EXPECT_GT(c.bias_levels, 0u);
  EXPECT_LE(c.marked_groups, kPages);
  EXPECT_FALSE(c.overflow);
  EXPECT_EQ(c.unallocated_groups, 0u);
  EXPECT_EQ(c.hole_pixels, 0u);
  EXPECT_EQ(pixels_with_holes(rig, a), 0u);
  EXPECT_TRUE(finite(a));
  for (const glm::uvec4& v : a.visibility) {
    if (v.x != 0) {
      EXPECT_GE(v.y, std::min(c.bias_levels, rig.geometry.layout.meshes()[0].levels - 1));
    }
  }
  // The loop stopped at the bias that fits: DECIDE sized its remaining steps to nothing, so its
  // later iterations launch no workgroup.
  const std::vector<gpu::HtexStateGpu> state = rig.read<gpu::HtexStateGpu>(rig.pass->state());
  ASSERT_EQ(state.size(), 1u);
  EXPECT_EQ(state[0].marking.w, PRISMOID_HTEX_PHASE_DONE);
  EXPECT_EQ(state[0].marking.z, c.bias_levels);
  EXPECT_EQ(state[0].loop_groups, glm::uvec4(0u));
  EXPECT_EQ(state[0].loop_pixels, glm::uvec4(0u));
  std::printf("[ allocation ] %u groups wanted at level of detail, %u after %u bias level(s) in %u pages\n", c.marked_groups_unbiased,
              c.marked_groups, c.bias_levels, kPages);
}

// The same camera again keeps every page where it was (and the image); a moved camera releases
// the pages of groups no longer seen and leaves resident exactly the marked groups.
TEST_F(HtexPassTest, PagesPersistWhileMarkedAndAreReleasedWhenNot) {
  constexpr uint32_t kPages = 64;
  HtexRig rig(device(), diffuse_sphere(), density(160.0), unshadowed(kPages));
  Camera camera = rig.scene.camera;
  camera.eye = glm::dvec3(0.0, 0.0, 2.6);
  const surface::HtexImage a = rig.render(device(), camera, 120, 90);
  EXPECT_EQ(a.counters.bias_levels, 0u);
  const auto pages_a = rig.read<uint32_t>(rig.pass->page_table());
  const surface::HtexImage b = rig.render(device(), camera, 120, 90);
  EXPECT_EQ(rig.read<uint32_t>(rig.pass->page_table()), pages_a) << "a group that stays marked keeps its page";
  EXPECT_EQ(b.counters.allocated_pages, 0u);
  EXPECT_EQ(b.counters.released_pages, 0u);
  EXPECT_EQ(b.rgba, a.rgba);

  camera.eye = glm::dvec3(1.5, 0.8, -1.8);  // the sphere's other side
  const surface::HtexImage m = rig.render(device(), camera, 120, 90);
  EXPECT_GT(m.counters.released_pages, 0u);
  EXPECT_GT(m.counters.allocated_pages, 0u);
  EXPECT_EQ(m.counters.hole_pixels, 0u);
  EXPECT_EQ(pixels_with_holes(rig, m), 0u);
  const auto occupancy = rig.read<uint32_t>(rig.pass->occupancy());
  const auto pages_m = rig.read<uint32_t>(rig.pass->page_table());
  std::set<uint32_t> used;
  for (uint32_t g = 0; g < rig.geometry.group_count(); ++g) {
    const bool marked = occupancy[2 * g] != 0 || occupancy[2 * g + 1] != 0;
    EXPECT_EQ(marked, pages_m[g] != PRISMOID_HTEX_NOT_RESIDENT) << "group " << g;
    if (pages_m[g] != PRISMOID_HTEX_NOT_RESIDENT) {
      EXPECT_LT(pages_m[g], kPages);
      EXPECT_TRUE(used.insert(pages_m[g]).second) << "page " << pages_m[g] << " given twice";
    }
  }
  EXPECT_EQ(m.counters.free_pages + used.size(), kPages);
  std::printf("[ persistence ] %u resident groups kept their pages; moved: %u released, %u allocated\n", a.counters.resident_groups,
              m.counters.released_pages, m.counters.allocated_pages);
}

// Shading reuse (HtexSettings::reuse_shading): a still camera shades nothing again and draws the
// same image to the last bit; after a move the planner invalidates (plan_shading_reuse: the
// shading depends on the eye), and the image is the one a pass without reuse draws.
TEST_F(HtexPassTest, ReusedShadingIsWhatShadingAgainGives) {
  SphereSceneOptions o;
  o.lights = Lights::Directional;
  o.sky = true;
  surface::HtexSettings reuse = unshadowed(64);
  reuse.reuse_shading = true;
  HtexRig rig(device(), sphere_scene(o), density(160.0), reuse);
  HtexRig fresh(device(), sphere_scene(o), density(160.0), unshadowed(64));
  Camera camera = rig.scene.camera;
  camera.eye = glm::dvec3(0.0, 0.0, 2.6);
  const surface::HtexImage a = rig.render(device(), camera, 120, 90);
  EXPECT_EQ(a.counters.reused_shadels, 0u);
  EXPECT_EQ(a.counters.shaded_shadels, a.counters.marked_shadels);
  const surface::HtexImage b = rig.render(device(), camera, 120, 90);
  EXPECT_EQ(b.counters.shaded_shadels, 0u);
  EXPECT_EQ(b.counters.reused_shadels, b.counters.marked_shadels);
  EXPECT_EQ(b.rgba, a.rgba);

  // The view turned with the eye still (the target moved): the pixels see other texels, those
  // already shaded are reused, the new ones shaded; the image is a fresh pass's.
  Camera turned = camera;
  turned.target = glm::dvec3(0.25, 0.1, 0.0);
  const surface::HtexImage c = rig.render(device(), turned, 120, 90);
  const surface::HtexImage f = fresh.render(device(), turned, 120, 90);
  EXPECT_GT(c.counters.reused_shadels, 0u);
  EXPECT_EQ(c.counters.reused_shadels + c.counters.shaded_shadels, c.counters.marked_shadels);
  EXPECT_EQ(c.counters.hole_pixels, 0u);
  EXPECT_EQ(c.rgba, f.rgba);

  // A moved eye: invalidated, everything marked is shaded again, as from scratch.
  camera.eye = glm::dvec3(0.9, 0.3, 2.4);
  rig.pass->invalidate_shading();
  const surface::HtexImage d = rig.render(device(), camera, 120, 90);
  const surface::HtexImage g = fresh.render(device(), camera, 120, 90);
  EXPECT_EQ(d.counters.shaded_shadels, d.counters.marked_shadels);
  EXPECT_EQ(d.counters.reused_shadels, 0u);
  EXPECT_EQ(d.rgba, g.rgba);
  std::printf("[ reuse ] still camera: %u of %u shadels reused; turned view: %u reused, %u shaded\n", b.counters.reused_shadels,
              b.counters.marked_shadels, c.counters.reused_shadels, c.counters.shaded_shadels);
}

// A pool too small even at the coarsest level: reported, nothing written outside it, no crash,
// a finite image; the pixels that missed texels are counted.
TEST_F(HtexPassTest, PoolTooSmallEvenAtTheCoarsestLevelIsReported) {
  HtexRig rig(device(), diffuse_sphere(), density(160.0), unshadowed(1));
  const surface::HtexImage img = rig.render(device(), rig.scene.camera, kW, kH);
  EXPECT_TRUE(img.counters.overflow);
  EXPECT_GT(img.counters.unallocated_groups, 0u);
  EXPECT_EQ(img.counters.resident_groups, 1u);
  EXPECT_GT(img.counters.hole_pixels, 0u);
  EXPECT_EQ(img.counters.hole_pixels, pixels_with_holes(rig, img));
  EXPECT_TRUE(finite(img));
  EXPECT_LE(img.counters.shaded_shadels, 64u);
}

TEST_F(HtexPassTest, RejectsAnEmptyPool) {
  const SurfaceScene scene = diffuse_sphere();
  const surface::HtexGeometry g(scene, density(40.0));
  EXPECT_THROW(surface::HtexPass(device(), g, unshadowed(0)), InputError);
  EXPECT_THROW(surface::HtexPass(device(), g, unshadowed(0x7fffffff)), InputError);
}

}  // namespace
}  // namespace prismoid::test
