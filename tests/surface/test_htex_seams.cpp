// Seams: the Htex image of a smoothly lit sphere and of a cube with averaged (centre) normals
// is continuous across every visible mesh edge, and it is the forward backend's shading
// filtered at texel scale. Directional light + gradient sky, diffuse, no shadows.
//
// Why comparing htex with forward alone cannot see a vertex seam: a lookup is a convex blend of
// texels shaded within ~1.5 texels of the pixel's point, so |htex - forward| is legitimately up
// to (shading gradient) x (texel); a seam from wrong vertex-corner texels has that same size
// (the corner texels' points differ by about a texel). So continuity is measured against the
// seamless lookup itself, whose rounding is 1e-4 or less of the signal:
//
//  1. Edge pairs (the seam statement). Every pair of horizontally or vertically adjacent pixels
//     whose triangles share a mesh edge straddles that edge. H = the GPU image; R = the
//     double-precision reference::htex_lookup at the GPU's stored level and weights over a
//     texture shaded by reference::direct_light_at at every texel's point (vertex-corner texels
//     at their vertex). R is continuous across edges (tests/reference/test_htex.cpp, to 1e-15;
//     checked here too at each pair's crossing point, from both faces at both pixels' levels,
//     within 1e-12). Asserted per pair and channel:
//        |(H(a) - H(b)) - (R(a) - R(b))| <= tol(a) + tol(b),
//     tol(p) = the GPU texel's shading tolerance (its float point's variation + kUlpBudget ulps
//     per term, as tests/surface/test_htex_pass.cpp) + the gather's rounding, max|texel| u
//     (1152 n + 16) (the same derivation). So the image jumps across an edge exactly as a
//     continuous function does, up to rounding. Pairs within 2 px of a projected vertex are
//     included (that is where vertex seams live) and counted apart. Every visible edge (its
//     midpoint's pixel sees one of its faces, both faces turned >= 0.25 towards the eye) must
//     have at least one pair.
//  2. Against forward (same shading code, per-pixel physics): with S the reference shading,
//        |H(p) - F(p)| <= max_k |S(texel k) - S(p)| + tol(p) + tolF(p)
//     because H is a normalized blend of texels (weights >= 0, sum 1); tolF = forward's
//     rounding (kUlpBudget ulps per term) + S's change within the rasterizer's snapping radius
//     2 x 2^-bits px of the pixel's point (probed along the pixel's x and y).
//
// Densities (128 level-0 texels per unit): "pixel scale" (the marking's level of detail picks
// the level; its texel spans 0.5..2 px at > 90% of the pixels, asserted) and "magnified"
// (HtexSettings::lod_bias = 3, clamped to the coarsest level: texels >= 2 px at > 85% (the rest graze), up to ~10 px).
//
// Controls (each must FAIL check 1, asserted):
//  - broken twin mirroring: the GPU's twin of every non-primary halfedge is cleared, so that
//    face reads its edge's quad at (u, v) instead of 1 - (u, v) (the quad is still shaded right:
//    shading reads the primary halfedge's twin) - a seam along every edge; it fails check 2 too.
//  - vertex corners not snapped (HtexSettings::snap_vertex_corners = false): the quads around a
//    vertex hold different corner values; check 1 fails at pairs near vertices (and beyond: the
//    corner texels are read up to a texel and a half from the vertex), magnified and at pixel scale.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <optional>
#include <set>
#include <unordered_map>

#include <glm/geometric.hpp>

#include "renderer/reference/direct_light.hpp"
#include "renderer/reference/htex_reference.hpp"
#include "renderer/reference/tet_ray.hpp"
#include "renderer/surface/forward/forward_pass.hpp"
#include "scene/generators.hpp"
#include "support/gpu_fixture.hpp"
#include "surface/forward_comparison.hpp"
#include "surface/htex_fixture.hpp"
#include "surface/surface_test_scenes.hpp"

namespace prismoid::test {
namespace {

constexpr double kU = 0x1p-24;
constexpr uint32_t kW = 128, kH = 96;

SurfaceScene lit(SurfaceScene s) {
  s.point_lights.clear();
  s.directional_lights = {{{-1.0, -0.3, -0.6}, {1.5, 1.2, 1.0}}};
  s.sky = Sky{glm::dvec3(0.3), glm::dvec3(0.1), {0.0, 1.0, 0.0}};
  return s;
}

SurfaceScene sphere() {
  SphereSceneOptions o;
  o.subdivisions = 2;
  o.lights = Lights::Directional;
  o.sky = true;
  SurfaceScene s = lit(sphere_scene(o));
  s.camera.eye = glm::dvec3(0.4, 0.3, 2.6);
  return s;
}

// A cube of half side 0.7 (2 x 2 squares per side), normals from its centre: shading is
// continuous across its creases, as on the sphere.
SurfaceScene cube() {
  SurfaceScene s = sphere();
  const SurfaceMesh c = make_cube_surface(glm::dvec3(0.0), 0.7, 2);
  SceneMesh m;
  m.name = "cube";
  m.positions = c.points;
  m.triangles = c.triangles;
  for (const auto& p : m.positions) m.normals.push_back(glm::normalize(p));
  s.meshes = {m};
  s.camera.eye = glm::dvec3(1.6, 1.3, 2.2);
  return s;
}

// Pixel coordinates of a world point (the inverse of reference::ray_direction).
struct Projector {
  explicit Projector(const Camera& c) : eye(c.eye) {
    f = reference::ray_direction(c, kW, kH, 0.5 * kW, 0.5 * kH);
    const glm::dvec3 rx = reference::ray_direction(c, kW, kH, kW, 0.5 * kH), ry = reference::ray_direction(c, kW, kH, 0.5 * kW, kH);
    dx = rx / glm::dot(rx, f) - f;
    dy = ry / glm::dot(ry, f) - f;
  }
  glm::dvec2 operator()(const glm::dvec3& x) const {
    const glm::dvec3 v = x - eye;
    const glm::dvec3 w = v / glm::dot(v, f) - f;
    return {(glm::dot(w, dx) / glm::dot(dx, dx) + 1.0) * 0.5 * kW, (glm::dot(w, dy) / glm::dot(dy, dy) + 1.0) * 0.5 * kH};
  }
  glm::dvec3 eye, f, dx, dy;
};

// Barycentric weights where the ray through image point (px, py) meets a triangle's plane.
glm::dvec3 ray_bary(const Camera& c, const glm::dvec3& p0, const glm::dvec3& p1, const glm::dvec3& p2, double px, double py) {
  const glm::dvec3 d = reference::ray_direction(c, kW, kH, px, py);
  const glm::dvec3 e1 = p1 - p0, e2 = p2 - p0, pv = glm::cross(d, e2), tv = c.eye - p0;
  const double det = glm::dot(e1, pv);
  const double b1 = glm::dot(tv, pv) / det, b2 = glm::dot(d, glm::cross(tv, e1)) / det;
  return {1.0 - b1 - b2, b1, b2};
}

double max3(const glm::dvec3& v) { return std::max({std::abs(v.x), std::abs(v.y), std::abs(v.z)}); }

struct SeamStats {
  size_t pixels = 0, forward_compared = 0;
  size_t pairs = 0, vertex_pairs = 0, level_change_pairs = 0, pair_failures = 0, vertex_pair_failures = 0;
  double pair_ratio = 0.0, vertex_pair_ratio = 0.0, pair_excess = 0.0;  // excess: largest |jump error| - tolerance
  double max_tol = 0.0, max_jump = 0.0;
  double continuity = 0.0;  // the reference's largest disagreement across an edge (relative to max|texel|)
  size_t forward_failures = 0;
  double forward_ratio = 0.0, max_forward_error = 0.0;
  size_t visible_edges = 0, edges_without_pairs = 0;
  double texel_px_min = 1e300, texel_px_max = 0.0;  // the level's texel over the pixel (longer axis)
  size_t texel_near_pixel = 0, texel_magnified = 0;  // pixels with texel in [0.5, 2] px; >= 2 px
  std::set<uint32_t> levels;
  uint32_t holes = 0, bias = 0;
};

void print(const char* what, const SeamStats& s) {
  std::printf("[ seams %s ] %zu pixels, levels %u..%u, texel %.2f..%.2f px; %zu edge pairs (%zu within 2 px of a vertex, %zu change level) "
              "over %zu visible edges (%zu without a pair): worst |jump - seamless jump| %.3g of tolerance (near vertices %.3g; "
              "%zu + %zu pairs over, largest excess %.3g, largest tolerance %.3g, largest jump %.3g); reference continuity %.2g; "
              "forward: %zu pixels, worst %.3g of bound (|htex - forward| up to %.3g, %zu over)\n",
              what, s.pixels, s.levels.empty() ? 0u : *s.levels.begin(), s.levels.empty() ? 0u : *s.levels.rbegin(), s.texel_px_min,
              s.texel_px_max, s.pairs, s.vertex_pairs, s.level_change_pairs, s.visible_edges, s.edges_without_pairs, s.pair_ratio,
              s.vertex_pair_ratio, s.pair_failures - s.vertex_pair_failures, s.vertex_pair_failures, s.pair_excess, s.max_tol,
              s.max_jump, s.continuity, s.forward_compared, s.forward_ratio, s.max_forward_error, s.forward_failures);
}

class HtexSeamTest : public GpuTest {
 protected:
  SeamStats measure(const SurfaceScene& scene, float lod_bias, bool snap, bool broken_twin) {
    constexpr double texels_per_unit = 128.0;
    surface::HtexSettings settings;
    settings.pool_pages = 256;
    settings.shadows = false;
    settings.snap_vertex_corners = snap;
    settings.lod_bias = lod_bias;
    htex::LayoutOptions layout_options;
    layout_options.texels_per_unit = texels_per_unit;
    // The control's GPU tables: non-primary halfedges without a twin (declared before the rig,
    // which then holds a pass over it).
    std::optional<surface::HtexGeometry> broken;
    if (broken_twin) {
      broken.emplace(scene, layout_options);
      for (HalfedgeMesh& m : broken->meshes)
        for (size_t h = 0; h < m.twin.size(); ++h)
          if (m.twin[h] > int32_t(h)) m.twin[h] = kNoHalfedge;
    }
    HtexRig rig(device(), scene, layout_options, settings);
    if (broken) rig.pass = std::make_unique<surface::HtexPass>(device(), *broken, settings);
    const Camera& camera = scene.camera;
    const surface::HtexImage img = rig.render(device(), camera, kW, kH);
    surface::ForwardPass forward_pass(device());
    const surface::ForwardImage fwd = surface::render_forward(device(), forward_pass, rig.gpu, camera, {kW, kH});
    const auto& meshes = rig.geometry.meshes;
    const auto& layout = rig.geometry.layout;
    SeamStats s;
    s.holes = img.counters.hole_pixels;
    s.bias = img.counters.bias_levels;

    // The covered pixels' points and footprints; every texel they read, once.
    struct Pixel {
      bool valid = false;
      uint32_t mesh = 0, triangle = 0, face = 0, level = 0;
      glm::dvec3 bary{0.0}, world{0.0};
      reference::HtexFootprint fp;
    };
    const size_t count = size_t(kW) * kH;
    std::vector<Pixel> px(count);
    std::unordered_map<uint64_t, size_t> texel_index;
    std::vector<htex::TexelAddress> texels;
    std::vector<reference::ShadingPointQuery> texel_queries;
    std::vector<reference::ShadingPointQuery> pixel_queries;  // per valid pixel: its point, then 4 probes
    std::vector<size_t> pixel_query(count, 0);
    auto add_footprint = [&](const reference::HtexFootprint& fp) {
      for (uint32_t k = 0; k < fp.count; ++k) {
        const htex::TexelAddress& a = fp.texels[k].texel;
        const uint64_t key = (uint64_t(a.quad) << 32) | (uint64_t(a.level) << 24) | (uint64_t(a.i) << 12) | a.j;
        if (texel_index.emplace(key, texels.size()).second) {
          texels.push_back(a);
          const uint32_t mesh = layout.mesh_of_quad(a.quad);
          const htex::MeshLayout& ml = layout.meshes()[mesh];
          const htex::TexelPoint tp = htex::texel_point(meshes[mesh], a.quad - ml.first_quad, ml.side(a.level), a.i, a.j);
          const reference::ShadingPointQuery q{mesh, meshes[mesh].triangle_of_face[tp.face], tp.bary, camera.eye};
          texel_queries.push_back(q);
          for (int c = 0; c < 3; ++c) {  // the point moved by 2e-6 of the triangle (above a float position's rounding)
            reference::ShadingPointQuery probe = q;
            probe.bary[c] += 2e-6;
            probe.bary[(c + 1) % 3] -= 2e-6;
            texel_queries.push_back(probe);
          }
        }
      }
    };
    const double snap_radius = 2.0 * std::ldexp(1.0, -int(device().capabilities().subpixel_precision_bits));
    for (size_t i = 0; i < count; ++i) {
      const glm::uvec4 v = img.visibility[i];
      if (v.x == 0 || v.y == PRISMOID_HTEX_NONE) continue;
      Pixel& p = px[i];
      p.valid = true;
      std::tie(p.mesh, p.triangle) = rig.local_triangle(v.x - 1);
      p.face = uint32_t(meshes[p.mesh].face_of_triangle[p.triangle]);
      p.level = v.y;
      p.bary = stored_barycentrics(v);
      const auto& sm = scene.meshes[p.mesh];
      const auto& t = sm.triangles[p.triangle];
      p.world = p.bary.x * sm.positions[t[0]] + p.bary.y * sm.positions[t[1]] + p.bary.z * sm.positions[t[2]];
      p.fp = reference::htex_footprint(meshes, layout, p.mesh, p.face, p.bary, p.level);
      add_footprint(p.fp);
      // The pixel's point and the snapping radius along the pixel's x and y.
      const double cx = double(i % kW) + 0.5, cy = double(i / kW) + 0.5;
      const glm::dvec3 p0 = sm.positions[t[0]], p1 = sm.positions[t[1]], p2 = sm.positions[t[2]];
      const glm::dvec3 b = ray_bary(camera, p0, p1, p2, cx, cy);
      const glm::dvec3 bx = ray_bary(camera, p0, p1, p2, cx + 1.0, cy) - b, by = ray_bary(camera, p0, p1, p2, cx, cy + 1.0) - b;
      pixel_query[i] = pixel_queries.size();
      const reference::ShadingPointQuery q{p.mesh, p.triangle, p.bary, camera.eye};
      pixel_queries.push_back(q);
      for (const glm::dvec3& d : {bx, -bx, by, -by}) {
        reference::ShadingPointQuery probe = q;
        probe.bary += snap_radius * d;
        pixel_queries.push_back(probe);
      }
    }
    // Each edge pair: its edge's halfedge in a's face, and the crossing point's weights in both
    // faces (the edge point nearest the midpoint of the pixels' points); their footprints are
    // shaded too, for the reference's continuity check.
    struct Pair {
      size_t a, b;
      int32_t h;
      glm::dvec3 ba, bb;
    };
    std::vector<Pair> pairs;
    for (size_t a = 0; a < count; ++a) {
      if (!px[a].valid) continue;
      for (const size_t b : {a + 1, a + kW}) {
        if (b >= count || (b == a + 1 && b % kW == 0) || !px[b].valid) continue;
        const Pixel &pa = px[a], &pb = px[b];
        if (pa.mesh != pb.mesh || pa.face == pb.face) continue;
        const HalfedgeMesh& m = meshes[pa.mesh];
        int32_t h = kNoHalfedge;
        for (int k = 0; k < 3; ++k) {
          const int32_t t = m.twin[3 * pa.face + uint32_t(k)];
          if (t != kNoHalfedge && uint32_t(HalfedgeMesh::face(t)) == pb.face) h = int32_t(3 * pa.face) + k;
        }
        if (h == kNoHalfedge) continue;  // the faces share a vertex only
        const glm::dvec3 P0 = m.positions[m.vertex(h)], P1 = m.positions[m.target(h)];
        const glm::dvec3 xm = 0.5 * (pa.world + pb.world);
        const double u = std::clamp(glm::dot(xm - P0, P1 - P0) / glm::dot(P1 - P0, P1 - P0), 0.0, 1.0);
        const int32_t th = m.twin[h];
        Pair pr{a, b, h, glm::dvec3(0.0), glm::dvec3(0.0)};
        pr.ba[HalfedgeMesh::corner(h)] = 1.0 - u;
        pr.ba[HalfedgeMesh::corner(HalfedgeMesh::next(h))] = u;
        pr.bb[HalfedgeMesh::corner(th)] = u;  // th starts where h ends
        pr.bb[HalfedgeMesh::corner(HalfedgeMesh::next(th))] = 1.0 - u;
        for (const uint32_t level : {pa.level, pb.level}) {
          add_footprint(reference::htex_footprint(meshes, layout, pa.mesh, pa.face, pr.ba, level));
          add_footprint(reference::htex_footprint(meshes, layout, pa.mesh, pb.face, pr.bb, level));
        }
        pairs.push_back(pr);
      }
    }
    const auto texel_ref = reference::direct_light_at(rig.scene, texel_queries);
    const auto pixel_ref = reference::direct_light_at(rig.scene, pixel_queries);

    // The reference texture and each texel's tolerance.
    reference::HtexTexture texture(layout, 3);
    std::vector<double> texel_tol(texels.size());
    for (size_t k = 0; k < texels.size(); ++k) {
      const auto& r = texel_ref[4 * k];
      double variation = 0.0;
      for (int c = 1; c <= 3; ++c) variation = std::max(variation, max3(texel_ref[4 * k + size_t(c)].radiance - r.radiance));
      texel_tol[k] = variation + kU * (kUlpBudget + r.terms) * r.rounding_scale;
      texture.set(texels[k], glm::dvec4(r.radiance, 0.0));
    }
    auto texel_of = [&](const htex::TexelAddress& a) {
      return texel_index.at((uint64_t(a.quad) << 32) | (uint64_t(a.level) << 24) | (uint64_t(a.i) << 12) | a.j);
    };

    // Per pixel: R, the tolerance, and the forward check.
    std::vector<glm::dvec3> R(count), H(count);
    std::vector<double> tol(count, 0.0), maxv(count, 0.0);
    for (size_t i = 0; i < count; ++i) {
      const Pixel& p = px[i];
      if (!p.valid) continue;
      ++s.pixels;
      s.levels.insert(p.level);
      R[i] = glm::dvec3(reference::htex_lookup(meshes, layout, texture, p.mesh, p.face, p.bary, p.level));
      H[i] = glm::dvec3(img.rgba[4 * i], img.rgba[4 * i + 1], img.rgba[4 * i + 2]);
      const reference::DirectLightSample& S = pixel_ref[pixel_query[i]];
      double shading_tol = 0.0, spread = 0.0;
      for (uint32_t k = 0; k < p.fp.count; ++k) {
        const size_t t = texel_of(p.fp.texels[k].texel);
        shading_tol = std::max(shading_tol, texel_tol[t]);
        maxv[i] = std::max(maxv[i], glm::length(texel_ref[4 * t].radiance));
        spread = std::max(spread, max3(texel_ref[4 * t].radiance - S.radiance));
      }
      const double n = layout.meshes()[p.mesh].side(p.level);
      tol[i] = shading_tol + maxv[i] * kU * (1152.0 * n + 16.0);
      s.max_tol = std::max(s.max_tol, tol[i]);
      // Texel size over pixel size here: the level's texel in world units (the quad's stretch
      // over n) against the pixel's footprint.
      {
        const auto& sm = scene.meshes[p.mesh];
        const auto& t = sm.triangles[p.triangle];
        const double cx = double(i % kW) + 0.5, cy = double(i / kW) + 0.5;
        const glm::dvec3 b = ray_bary(camera, sm.positions[t[0]], sm.positions[t[1]], sm.positions[t[2]], cx, cy);
        const glm::dvec3 bx = ray_bary(camera, sm.positions[t[0]], sm.positions[t[1]], sm.positions[t[2]], cx + 1.0, cy) - b;
        const glm::dvec3 by = ray_bary(camera, sm.positions[t[0]], sm.positions[t[1]], sm.positions[t[2]], cx, cy + 1.0) - b;
        // In the chart's units (quad side 1): n texels per unit; the marking's level of detail.
        const double lod = reference::htex_level_of_detail(layout.meshes()[p.mesh], p.face, p.bary, bx, by);
        const double texels_per_pixel = std::exp2(lod - double(p.level));  // chart texels of level p.level per pixel
        s.texel_px_min = std::min(s.texel_px_min, 1.0 / texels_per_pixel);
        s.texel_px_max = std::max(s.texel_px_max, 1.0 / texels_per_pixel);
        s.texel_near_pixel += texels_per_pixel >= 0.5 && texels_per_pixel <= 2.0;
        s.texel_magnified += texels_per_pixel <= 0.5;
      }
      if (fwd.rgba[4 * i + 3] != 1.0f) continue;
      ++s.forward_compared;
      double probe_variation = 0.0;
      for (size_t c = 1; c <= 4; ++c) probe_variation = std::max(probe_variation, max3(pixel_ref[pixel_query[i] + c].radiance - S.radiance));
      const double tol_f = probe_variation + kU * (kUlpBudget + S.terms) * S.rounding_scale;
      const double bound = spread + tol[i] + tol_f;
      const double e = max3(H[i] - glm::dvec3(fwd.rgba[4 * i], fwd.rgba[4 * i + 1], fwd.rgba[4 * i + 2]));
      s.max_forward_error = std::max(s.max_forward_error, e);
      s.forward_ratio = std::max(s.forward_ratio, e / bound);
      s.forward_failures += e > bound;
    }

    // Edge pairs.
    const Projector project(camera);
    std::set<std::pair<uint32_t, uint32_t>> edges_with_pairs;  // (mesh, edge)
    for (const Pair& pr : pairs) {
      {
        const size_t a = pr.a, b = pr.b;
        const int32_t h = pr.h;
        const Pixel &pa = px[a], &pb = px[b];
        const HalfedgeMesh& m = meshes[pa.mesh];
        ++s.pairs;
        edges_with_pairs.insert({pa.mesh, m.edge_of[h]});
        s.level_change_pairs += pa.level != pb.level;
        const glm::dvec3 P0 = m.positions[m.vertex(h)], P1 = m.positions[m.target(h)];
        const glm::dvec2 mid = 0.5 * glm::dvec2(double(a % kW) + double(b % kW) + 1.0, double(a / kW) + double(b / kW) + 1.0);
        const bool near_vertex = std::min(glm::length(project(P0) - mid), glm::length(project(P1) - mid)) < 2.0;
        s.vertex_pairs += near_vertex;
        // The seamless jump and the GPU's.
        const double jump_error = max3((H[a] - H[b]) - (R[a] - R[b]));
        const double t2 = tol[a] + tol[b];
        s.max_jump = std::max(s.max_jump, max3(H[a] - H[b]));
        s.pair_ratio = std::max(s.pair_ratio, jump_error / t2);
        s.pair_excess = std::max(s.pair_excess, jump_error - t2);
        if (near_vertex) s.vertex_pair_ratio = std::max(s.vertex_pair_ratio, jump_error / t2);
        if (jump_error > t2) {
          ++s.pair_failures;
          s.vertex_pair_failures += near_vertex;
        }
        // The reference is continuous at the crossing point, from both faces, at both levels.
        const glm::dvec3 &ba = pr.ba, &bb = pr.bb;
        for (const uint32_t level : {pa.level, pb.level}) {
          const glm::dvec3 ra(reference::htex_lookup(meshes, layout, texture, pa.mesh, pa.face, ba, level));
          const glm::dvec3 rb(reference::htex_lookup(meshes, layout, texture, pa.mesh, pb.face, bb, level));
          s.continuity = std::max(s.continuity, max3(ra - rb) / std::max(maxv[a], maxv[b]));
        }
      }
    }
    // Visible edges: the midpoint's pixel sees one of the edge's faces, both faces turned
    // towards the eye (cosine >= 0.25), at least 2 px inside the image.
    for (uint32_t mi = 0; mi < meshes.size(); ++mi) {
      const HalfedgeMesh& m = meshes[mi];
      for (uint32_t e = 0; e < m.edge_count(); ++e) {
        const int32_t h = m.edge_halfedge[e], t = m.twin[h];
        if (t == kNoHalfedge) continue;
        bool facing = true;
        for (const int32_t f : {HalfedgeMesh::face(h), HalfedgeMesh::face(t)}) {
          const auto& c = m.faces[f];
          const glm::dvec3 nrm = glm::normalize(glm::cross(m.positions[c[1]] - m.positions[c[0]], m.positions[c[2]] - m.positions[c[0]]));
          const glm::dvec3 centre = (m.positions[c[0]] + m.positions[c[1]] + m.positions[c[2]]) / 3.0;
          facing = facing && glm::dot(nrm, glm::normalize(camera.eye - centre)) >= 0.25;
        }
        const glm::dvec2 q = project(0.5 * (m.positions[m.vertex(h)] + m.positions[m.target(h)]));
        if (!facing || q.x < 2.0 || q.y < 2.0 || q.x > kW - 2.0 || q.y > kH - 2.0) continue;
        const size_t i = size_t(q.y) * kW + size_t(q.x);
        if (!px[i].valid || px[i].mesh != mi ||
            (px[i].face != uint32_t(HalfedgeMesh::face(h)) && px[i].face != uint32_t(HalfedgeMesh::face(t))))
          continue;
        ++s.visible_edges;
        s.edges_without_pairs += !edges_with_pairs.count({mi, e});
      }
    }
    return s;
  }
};

TEST_F(HtexSeamTest, SphereAndCubeAreContinuousAcrossEveryEdge) {
  const std::pair<const char*, SurfaceScene> scenes[] = {{"sphere", sphere()}, {"cube", cube()}};
  for (const auto& [name, scene] : scenes) {
    for (const bool magnified : {false, true}) {
      const SeamStats s = measure(scene, magnified ? 3.0f : 0.0f, true, false);
      print((std::string(name) + (magnified ? ", magnified" : ", pixel scale")).c_str(), s);
      SCOPED_TRACE(std::string(name) + (magnified ? " magnified" : " pixel scale"));
      EXPECT_EQ(s.holes, 0u);
      EXPECT_EQ(s.bias, 0u);
      EXPECT_GT(s.pixels, size_t(kW * kH / 5));
      EXPECT_GT(s.visible_edges, 10u);
      EXPECT_EQ(s.edges_without_pairs, 0u);
      EXPECT_GT(s.vertex_pairs, 10u);
      EXPECT_EQ(s.pair_failures, 0u);
      EXPECT_LE(s.pair_ratio, 1.0);
      EXPECT_LE(s.continuity, 1e-12);
      EXPECT_GT(s.forward_compared, s.pixels * 9 / 10);
      EXPECT_EQ(s.forward_failures, 0u);
      if (magnified)
        EXPECT_GT(s.texel_magnified, s.pixels * 17 / 20);  // the rest: grazing pixels at the coarsest level
      else
        EXPECT_GT(s.texel_near_pixel, s.pixels * 9 / 10);
    }
  }
}

TEST_F(HtexSeamTest, ControlBrokenTwinMirroringIsDetected) {
  const SeamStats s = measure(sphere(), 0.0f, true, true);
  print("sphere, pixel scale, CONTROL twin quads not mirrored", s);
  EXPECT_GT(s.pair_failures, s.pairs / 4) << "a seam along every edge must break the edge-pair check";
  EXPECT_GT(s.forward_failures, 0u);
}

TEST_F(HtexSeamTest, ControlUnsnappedVertexCornersAreDetected) {
  const SeamStats s = measure(sphere(), 3.0f, false, false);
  print("sphere, magnified, CONTROL vertex corners not snapped", s);
  EXPECT_GT(s.vertex_pair_failures, 0u) << "the quads around a vertex disagree: pairs near vertices must break the check";
  EXPECT_GT(s.pair_ratio, 10.0);
  const SeamStats p = measure(sphere(), 0.0f, false, false);
  print("sphere, pixel scale, CONTROL vertex corners not snapped", p);
  EXPECT_GT(p.vertex_pair_failures, 0u);
  EXPECT_GT(p.pair_ratio, 10.0);
}

}  // namespace
}  // namespace prismoid::test
