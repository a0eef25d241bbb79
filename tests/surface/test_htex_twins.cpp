// The GLSL twins of the Htex charts, atlas addressing, texel points, footprint and level of
// detail (shaders/surface/htex/htex.glsl) against the double-precision C++ (htex_layout.hpp,
// htex_reference.hpp), at thousands of points of a sphere, a cube and an open quad (boundary
// edges: ghost texels), through a test-only compute shader (htex/twin_test.comp). The GPU gets
// float inputs; the C++ gets the same floats widened, so every difference is the GPU's float
// arithmetic, bounded per quantity below.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdlib>
#include <cstdio>
#include <cstring>
#include <random>
#include <set>

#include "renderer/reference/htex_reference.hpp"
#include "renderer/surface/htex/htex_tables.hpp"
#include "renderer/vk/device.hpp"
#include "renderer/vk/pipeline.hpp"
#include "surface/htex_fixture.hpp"
#include "scene/generators.hpp"
#include "support/gpu_fixture.hpp"
#include "surface/surface_test_scenes.hpp"

namespace prismoid::test {
namespace {

struct TwinQuery {
  glm::uvec4 ids;  // mesh, global face, level, snap
  glm::vec4 bary, dx, dy;
  glm::uvec4 texel;  // global edge, n, i, j
};
struct TwinResult {
  glm::ivec4 locate;
  glm::vec4 uv;
  glm::uvec4 quad_edges;
  glm::vec4 quad_xy[3];
  glm::vec4 lod;
  glm::uvec4 fp_texel[12];
  glm::vec4 fp_weight[3];
  glm::uvec4 fp_virtual[12];
  glm::uvec4 fp_back[12];
  glm::uvec4 tp;
  glm::vec4 tp_bary;
};
static_assert(sizeof(TwinQuery) == 80);
static_assert(sizeof(TwinResult) == 768);

constexpr double kU = 0x1p-24;  // float unit roundoff

// The float's value as a double, read back through memory: with GCC 12 here, double(float(x))
// of a double x was seen to give x itself (the rounding to float elided), which would hand the
// C++ other inputs than the GPU gets.
double widen(float f) {
  volatile float v = f;
  return static_cast<double>(v);
}

SurfaceScene twin_scene() {
  SurfaceScene s = sphere_scene({});  // icosphere (closed) and a quad light (open: boundary edges)
  SceneMesh cube;
  cube.name = "cube";
  const SurfaceMesh c = make_cube_surface(glm::dvec3(2.5, 0.0, 0.0), 0.7, 2);
  cube.positions = c.points;
  cube.triangles = c.triangles;
  s.meshes.push_back(cube);
  return s;
}

class HtexTwinTest : public GpuTest {};

TEST_F(HtexTwinTest, GlslTwinsMatchTheDoublePrecisionHtex) {
  const SurfaceScene scene = twin_scene();
  htex::LayoutOptions options;
  options.texels_per_unit = 40.0;
  const surface::HtexGeometry g(scene, options);
  const surface::HtexTables tables = surface::upload_htex_tables(device(), g, 1);

  std::mt19937_64 gen(7);
  std::uniform_real_distribution<double> u01(0.0, 1.0), sym(-1.0, 1.0);
  std::vector<TwinQuery> queries;
  struct Cpu {
    uint32_t mesh, face, level, edge, n, i, j;
    bool snap;
    glm::dvec3 bary, dx, dy;
  };
  std::vector<Cpu> cpu;
  for (int k = 0; k < 6000; ++k) {
    Cpu c{};
    c.mesh = uint32_t(k % g.meshes.size());
    const HalfedgeMesh& m = g.meshes[c.mesh];
    const htex::MeshLayout& ml = g.layout.meshes()[c.mesh];
    c.face = uint32_t(gen() % m.face_count());
    double a = u01(gen), b = u01(gen);
    if (k % 7 == 0) b = 1.0 - a;                // on an edge of the face
    if (k % 11 == 0) a = b = 1.0 / 3.0;         // the centroid: a corner of every chart
    if (k % 13 == 0) { a = 1.0; b = 0.0; }      // a vertex
    if (a + b > 1.0) { a = 1.0 - a; b = 1.0 - b; }
    const float b0 = float(1.0 - a - b), b1 = float(a), b2 = float(b);
    const glm::vec3 bf(b0, b1, b2);
    c.bary = glm::dvec3(widen(b0), widen(b1), widen(b2));
    const double scale = std::ldexp(1.0, -int(gen() % 8)) / double(ml.side(0));
    const glm::vec3 dxf(float(sym(gen) * scale), float(sym(gen) * scale), float(sym(gen) * scale));
    const glm::vec3 dyf(float(sym(gen) * scale), float(sym(gen) * scale), float(sym(gen) * scale));
    c.dx = glm::dvec3(widen(dxf.x), widen(dxf.y), widen(dxf.z));
    c.dy = glm::dvec3(widen(dyf.x), widen(dyf.y), widen(dyf.z));
    c.level = uint32_t(gen() % ml.levels);
    c.edge = uint32_t(gen() % m.edge_count());
    c.n = ml.side(uint32_t(gen() % ml.levels));
    c.i = uint32_t(gen() % c.n);
    c.j = uint32_t(gen() % c.n);
    if (k % 5 == 0) { c.i = c.n - 1; c.j = 0; }  // vertex corners
    if (k % 5 == 1) { c.i = 0; c.j = c.n - 1; }
    c.snap = k % 3 != 0;
    cpu.push_back(c);
    TwinQuery q{};
    q.ids = glm::uvec4(c.mesh, g.first_face[c.mesh] + c.face, c.level, c.snap ? 1u : 0u);
    q.bary = glm::vec4(bf, 0.0f);
    q.dx = glm::vec4(dxf, 0.0f);
    q.dy = glm::vec4(dyf, 0.0f);
    q.texel = glm::uvec4(ml.first_quad + c.edge, c.n, c.i, c.j);
    queries.push_back(q);
  }

  // Run the twins.
  const std::vector<TwinResult> results = run_htex_twin_shader<TwinResult>(device(), tables, "surface/htex/twin_test.comp", queries);

  size_t failures = 0, footprint_texels = 0, ghosts = 0, vertices = 0, set_differences = 0;
  double worst_uv = 0.0, worst_xy = 0.0, worst_weight_ratio = 0.0, worst_lod_ratio = 0.0, worst_tp = 0.0;
  auto fail = [&](size_t k, const std::string& what) {
    if (failures++ < 10 || std::getenv("HTEX_TWIN_ALL")) ADD_FAILURE() << "query " << k << ": " << what;
  };
  for (size_t k = 0; k < cpu.size(); ++k) {
    const Cpu& c = cpu[k];
    const TwinResult& r = results[k];
    const HalfedgeMesh& m = g.meshes[c.mesh];
    const htex::MeshLayout& ml = g.layout.meshes()[c.mesh];
    const int32_t h0 = int32_t(3 * g.first_face[c.mesh]);
    // Charts: the same halfedge triangle (the same float comparisons), (u, v) one subtraction each.
    const htex::HalfedgePoint p = htex::locate_in_face(c.face, c.bary);
    if (r.locate.x != h0 + p.halfedge) fail(k, "locate_in_face chose another halfedge: GPU " + std::to_string(r.locate.x - h0) + ", C++ " + std::to_string(p.halfedge));
    const double duv = std::max(std::abs(double(r.uv.x) - p.uv.x), std::abs(double(r.uv.y) - p.uv.y));
    worst_uv = std::max(worst_uv, duv / kU);
    if (duv > kU) fail(k, "uv off by " + std::to_string(duv));
    // Quads: the same edges; coordinates from (u, v) by sign changes and 1 - x (one more rounding).
    const auto quads = htex::face_point_quads(m, c.face, c.bary);
    for (int q = 0; q < 3; ++q) {
      if (r.quad_edges[q] != ml.first_quad + quads[q].edge) fail(k, "face_point_quads: another edge");
      const double d = std::max(std::abs(double(r.quad_xy[q].x) - quads[q].xy.x), std::abs(double(r.quad_xy[q].y) - quads[q].xy.y));
      worst_xy = std::max(worst_xy, d / kU);
      if (d > 2.0 * kU) fail(k, "quad coordinates off by " + std::to_string(d));
    }
    // Footprint: s = x n - 1/2 is off by at most n 2 u + n u + u (x's error, the product, the
    // difference), so each bilinear weight (a product of two factors in [0, 1]) by 2 (3 n + 1) u
    // plus its own rounding, and the normalized weights (alpha >= 1/4, at most 12 taps) by
    // 4 * 12 * that + 2 u. A texel only one side lists must have a weight within that bound.
    const uint32_t n = ml.side(c.level);
    const double weight_tol = 48.0 * (2.0 * (3.0 * n + 1.0) + 2.0) * kU + 2.0 * kU;
    const reference::HtexFootprint fp = reference::htex_footprint(g.meshes, g.layout, c.mesh, c.face, c.bary, c.level);
    auto gpu_weight = [&](uint32_t idx) { return double(r.fp_weight[idx / 4][idx % 4]); };
    std::set<size_t> matched;
    for (uint32_t a = 0; a < fp.count; ++a) {
      const htex::TexelAddress& t = fp.texels[a].texel;
      bool found = false;
      for (uint32_t b = 0; b < uint32_t(r.lod.z); ++b)
        if (r.fp_texel[b] == glm::uvec4(t.quad, t.level, t.i, t.j)) {
          found = true;
          matched.insert(b);
          const double d = std::abs(gpu_weight(b) - fp.texels[a].weight);
          worst_weight_ratio = std::max(worst_weight_ratio, d / weight_tol);
          if (d > weight_tol) fail(k, "footprint weight off by " + std::to_string(d));
          // Atlas addressing: exact.
          const glm::uvec2 v = g.layout.virtual_texel(t);
          if (r.fp_virtual[b].x != v.x || r.fp_virtual[b].y != v.y) fail(k, "virtual_texel differs");
          if (r.fp_virtual[b].w != g.layout.shadel_of(v)) fail(k, "shadel_of differs");
          if (r.fp_virtual[b].z != 1u || r.fp_back[b] != glm::uvec4(t.quad, t.level, t.i, t.j)) fail(k, "texel_at does not invert virtual_texel");
          ++footprint_texels;
        }
      if (!found) {
        ++set_differences;
        if (fp.texels[a].weight > weight_tol) fail(k, "the GPU footprint misses a texel of weight " + std::to_string(fp.texels[a].weight));
      }
    }
    for (uint32_t b = 0; b < uint32_t(r.lod.z); ++b)
      if (!matched.count(b)) {
        ++set_differences;
        if (gpu_weight(b) > weight_tol) fail(k, "the GPU footprint has an extra texel of weight " + std::to_string(gpu_weight(b)));
      }
    // Level of detail: the local derivative vectors are differences of floats (each component
    // off by 2 u max|d|), their length relatively by 2 u max|d| / |local| + 2 u, log2 by that / ln 2.
    {
      const int kc = HalfedgeMesh::corner(p.halfedge), mc = (kc + 2) % 3;
      auto local = [&](const glm::dvec3& d) { return glm::dvec2(d[kc] - d[mc], d[(kc + 1) % 3] - d[mc]); };
      const double lx = glm::length(local(c.dx)), ly = glm::length(local(c.dy));
      const double big = std::max(lx, ly);
      const double dmax = std::max(glm::length(c.dx), glm::length(c.dy));
      const double lod = reference::htex_level_of_detail(ml, c.face, c.bary, c.dx, c.dy);
      const double tol = (4.0 * kU * dmax / big + 4.0 * kU) / std::log(2.0) + 4.0 * kU * std::abs(lod);
      const double d = std::abs(double(r.lod.x) - lod);
      worst_lod_ratio = std::max(worst_lod_ratio, d / tol);
      if (d > tol) fail(k, "level of detail off by " + std::to_string(d));
    }
    // Texel points: the same face and kind; weights from (x, y) = ((i + 1/2) / n, ...) by a few
    // roundings (the division, 1 - x, (1 - u - v) / 3 and one addition): within 4 u.
    const htex::TexelPoint tp = htex::texel_point(m, c.edge, c.n, c.i, c.j, c.snap);
    if (r.tp.x != g.first_face[c.mesh] + tp.face) fail(k, "texel_point: another face");
    if ((r.tp.y != 0) != tp.ghost) fail(k, "texel_point: ghost flag differs");
    if ((r.tp.z != 0) != (tp.vertex >= 0)) fail(k, "texel_point: vertex flag differs");
    ghosts += tp.ghost;
    vertices += tp.vertex >= 0;
    for (int a = 0; a < 3; ++a) {
      const double d = std::abs(double(r.tp_bary[a]) - tp.bary[a]);
      worst_tp = std::max(worst_tp, d / kU);
      if (d > 4.0 * kU) fail(k, "texel_point weights off by " + std::to_string(d));
    }
  }
  EXPECT_EQ(failures, 0u);
  EXPECT_GT(footprint_texels, 6000u * 3);
  EXPECT_GT(ghosts, 10u);  // the open quad's boundary texels were exercised
  EXPECT_GT(vertices, 500u);
  std::printf("[ twins ] %zu queries, %zu footprint texels (%zu listed by one side only, all below the weight bound): worst uv %.2g u, "
              "quad xy %.2g u, weight %.2g of bound, lod %.2g of bound, texel point %.2g u; %zu ghost and %zu vertex texels\n",
              cpu.size(), footprint_texels, set_differences, worst_uv, worst_xy, worst_weight_ratio, worst_lod_ratio, worst_tp, ghosts,
              vertices);
}

}  // namespace
}  // namespace prismoid::test
