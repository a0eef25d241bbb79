#include "renderer/surface/charts/planar_charts.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>
#include <map>
#include <numeric>
#include <stdexcept>
#include <string>
#include <utility>

#include <glm/geometric.hpp>

#include "scene/input_error.hpp"

namespace prismoid::charts {

namespace {

double orient(const glm::dvec2& a, const glm::dvec2& b, const glm::dvec2& p) {
  const glm::dvec2 u = b - a, v = p - a;
  return u.x * v.y - u.y * v.x;
}

bool finite(const glm::dvec3& v) { return std::isfinite(v.x) && std::isfinite(v.y) && std::isfinite(v.z); }

struct Box2 {
  glm::dvec2 lo, hi;
};

Box2 box_of(const std::array<glm::dvec2, 3>& t) { return {glm::min(t[0], glm::min(t[1], t[2])), glm::max(t[0], glm::max(t[1], t[2]))}; }

bool boxes_overlap(const Box2& a, const Box2& b) { return a.lo.x < b.hi.x && b.lo.x < a.hi.x && a.lo.y < b.hi.y && b.lo.y < a.hi.y; }

// True when some edge of `a` (counter-clockwise) has all of `b` in its closed outer half-plane.
bool separated_by_edge_of(const std::array<glm::dvec2, 3>& a, const std::array<glm::dvec2, 3>& b) {
  for (int k = 0; k < 3; ++k) {
    const glm::dvec2& p = a[k];
    const glm::dvec2& q = a[(k + 1) % 3];
    if (orient(p, q, b[0]) <= 0.0 && orient(p, q, b[1]) <= 0.0 && orient(p, q, b[2]) <= 0.0) return true;
  }
  return false;
}

// Interiors of two counter-clockwise triangles intersect (separating axis theorem; touching
// along edges or at vertices is not overlap).
bool interiors_overlap(const std::array<glm::dvec2, 3>& a, const std::array<glm::dvec2, 3>& b) {
  return !separated_by_edge_of(a, b) && !separated_by_edge_of(b, a);
}

// Andrew's monotone chain: counter-clockwise hull without collinear points.
std::vector<glm::dvec2> convex_hull(std::vector<glm::dvec2> points) {
  std::sort(points.begin(), points.end(), [](const glm::dvec2& a, const glm::dvec2& b) { return a.x < b.x || (a.x == b.x && a.y < b.y); });
  points.erase(std::unique(points.begin(), points.end()), points.end());
  if (points.size() < 3) return points;
  std::vector<glm::dvec2> hull(2 * points.size());
  size_t k = 0;
  for (size_t i = 0; i < points.size(); ++i) {
    while (k >= 2 && orient(hull[k - 2], hull[k - 1], points[i]) <= 0.0) --k;
    hull[k++] = points[i];
  }
  for (size_t i = points.size() - 1, lower = k + 1; i-- > 0;) {
    while (k >= lower && orient(hull[k - 2], hull[k - 1], points[i]) <= 0.0) --k;
    hull[k++] = points[i];
  }
  hull.resize(k - 1);
  return hull;
}

// Per mesh: the triangles sharing each unordered vertex pair (all of them on a non-manifold edge).
std::vector<std::vector<uint32_t>> edge_neighbours(const SceneMesh& mesh, uint32_t first_id) {
  const size_t n = mesh.triangles.size();
  std::vector<std::pair<uint64_t, uint32_t>> edges;
  edges.reserve(3 * n);
  for (size_t t = 0; t < n; ++t) {
    const auto& tri = mesh.triangles[t];
    for (int k = 0; k < 3; ++k) {
      const uint64_t a = tri[k], b = tri[(k + 1) % 3];
      if (a == b) continue;
      edges.emplace_back(std::min(a, b) << 32 | std::max(a, b), static_cast<uint32_t>(t));
    }
  }
  std::sort(edges.begin(), edges.end());
  std::vector<std::vector<uint32_t>> neighbours(n);
  for (size_t begin = 0; begin < edges.size();) {
    size_t end = begin;
    while (end < edges.size() && edges[end].first == edges[begin].first) ++end;
    for (size_t x = begin; x < end; ++x)
      for (size_t y = begin; y < end; ++y)
        if (edges[x].second != edges[y].second) neighbours[edges[x].second].push_back(first_id + edges[y].second);
    begin = end;
  }
  for (auto& list : neighbours) {
    std::sort(list.begin(), list.end());
    list.erase(std::unique(list.begin(), list.end()), list.end());
  }
  return neighbours;
}

// A chart during construction: its plane frame and its triangles' projections (plane units).
struct ChartBuild {
  uint32_t mesh = 0;
  glm::dvec3 origin{0.0}, e_u{1.0, 0.0, 0.0}, e_v{0.0, 1.0, 0.0}, normal{0.0, 0.0, 1.0};
  std::vector<uint32_t> triangles;
  std::vector<std::array<glm::dvec2, 3>> projected;
  std::vector<Box2> boxes;

  ChartBuild(uint32_t mesh_, const glm::dvec3& origin_, const glm::dvec3& n) : mesh(mesh_), origin(origin_), normal(n) {
    // The axis least aligned with n, made orthogonal to it; (e_u, e_v, n) right-handed.
    const glm::dvec3 a = std::abs(n.x) <= std::abs(n.y) && std::abs(n.x) <= std::abs(n.z) ? glm::dvec3(1, 0, 0)
                         : std::abs(n.y) <= std::abs(n.z)                                 ? glm::dvec3(0, 1, 0)
                                                                                           : glm::dvec3(0, 0, 1);
    e_u = glm::normalize(a - glm::dot(a, n) * n);
    e_v = glm::cross(n, e_u);
  }

  glm::dvec2 project(const glm::dvec3& p) const { return {glm::dot(p - origin, e_u), glm::dot(p - origin, e_v)}; }
  std::array<glm::dvec2, 3> project(const TriangleGeometry& g) const { return {project(g.p[0]), project(g.p[1]), project(g.p[2])}; }

  // Adds triangle t with projection `proj` when it keeps enough area with positive orientation
  // and overlaps no triangle already in the chart.
  bool try_add(uint32_t t, const TriangleGeometry& g, const std::array<glm::dvec2, 3>& proj) {
    const double area2 = orient(proj[0], proj[1], proj[2]);
    if (!(area2 > kMinProjectedArea * 2.0 * g.area)) return false;
    const Box2 box = box_of(proj);
    for (size_t k = 0; k < projected.size(); ++k)
      if (boxes_overlap(box, boxes[k]) && interiors_overlap(proj, projected[k])) return false;
    triangles.push_back(t);
    projected.push_back(proj);
    boxes.push_back(box);
    return true;
  }
};

// Solves the symmetric positive definite n x n system a x = b (a row-major, overwritten by its
// Cholesky factor; b by x). False when a pivot is not positive (a singular system).
bool solve_spd(std::vector<double>& a, std::vector<double>& b, size_t n) {
  for (size_t j = 0; j < n; ++j) {
    double d = a[j * n + j];
    for (size_t k = 0; k < j; ++k) d -= a[j * n + k] * a[j * n + k];
    if (!(d > 0.0) || !std::isfinite(d)) return false;
    d = std::sqrt(d);
    a[j * n + j] = d;
    for (size_t i = j + 1; i < n; ++i) {
      double sum = a[i * n + j];
      for (size_t k = 0; k < j; ++k) sum -= a[i * n + k] * a[j * n + k];
      a[i * n + j] = sum / d;
    }
  }
  for (size_t i = 0; i < n; ++i) {
    double sum = b[i];
    for (size_t k = 0; k < i; ++k) sum -= a[i * n + k] * b[k];
    b[i] = sum / a[i * n + i];
  }
  for (size_t i = n; i-- > 0;) {
    double sum = b[i];
    for (size_t k = i + 1; k < n; ++k) sum -= a[k * n + i] * b[k];
    b[i] = sum / a[i * n + i];
  }
  return true;
}

PlanarChart point_chart(uint32_t mesh, uint32_t triangle) {
  PlanarChart chart;
  chart.mesh = mesh;
  chart.triangles = {triangle};
  chart.corners = {{glm::dvec2(0.0), glm::dvec2(0.0), glm::dvec2(0.0)}};
  return chart;
}

// Ascending ids; the minimum-area bounding rectangle of the hull, axis-aligned, landscape, its
// lower corner at 0.
PlanarChart finish(const ChartBuild& build) {
  const size_t n = build.triangles.size();
  std::vector<uint32_t> by_id(n);
  std::iota(by_id.begin(), by_id.end(), 0u);
  std::sort(by_id.begin(), by_id.end(), [&](uint32_t a, uint32_t b) { return build.triangles[a] < build.triangles[b]; });

  std::vector<glm::dvec2> points;
  points.reserve(3 * n);
  for (uint32_t k : by_id) points.insert(points.end(), build.projected[k].begin(), build.projected[k].end());
  const std::vector<glm::dvec2> hull = convex_hull(points);
  glm::dvec2 axis(1.0, 0.0);
  double best = std::numeric_limits<double>::infinity();
  glm::dvec2 best_extent(0.0);
  for (size_t k = 0; k < hull.size(); ++k) {
    const glm::dvec2 edge = hull[(k + 1) % hull.size()] - hull[k];
    const double len = glm::length(edge);
    if (!(len > 0.0)) continue;
    const glm::dvec2 d = edge / len, perp(-d.y, d.x);
    glm::dvec2 lo(std::numeric_limits<double>::infinity()), hi(-std::numeric_limits<double>::infinity());
    for (const glm::dvec2& p : hull) {
      const glm::dvec2 q(glm::dot(p, d), glm::dot(p, perp));
      lo = glm::min(lo, q);
      hi = glm::max(hi, q);
    }
    const glm::dvec2 extent = hi - lo;
    if (extent.x * extent.y < best) {
      best = extent.x * extent.y;
      axis = d;
      best_extent = extent;
    }
  }
  // Landscape: turn a quarter (a rotation, so orientation is kept) when taller than wide.
  if (best_extent.y > best_extent.x) axis = glm::dvec2(-axis.y, axis.x);
  const glm::dvec2 perp(-axis.y, axis.x);
  glm::dvec2 lo(std::numeric_limits<double>::infinity());
  glm::dvec2 hi(-std::numeric_limits<double>::infinity());
  for (const glm::dvec2& p : points) {
    const glm::dvec2 q(glm::dot(p, axis), glm::dot(p, perp));
    lo = glm::min(lo, q);
    hi = glm::max(hi, q);
  }

  PlanarChart chart;
  chart.mesh = build.mesh;
  chart.normal = build.normal;
  chart.extent = hi - lo;
  chart.triangles.resize(n);
  chart.corners.resize(n);
  for (size_t k = 0; k < n; ++k) {
    chart.triangles[k] = build.triangles[by_id[k]];
    for (int v = 0; v < 3; ++v) {
      const glm::dvec2& p = build.projected[by_id[k]][v];
      chart.corners[k][v] = glm::dvec2(glm::dot(p, axis), glm::dot(p, perp)) - lo;
    }
  }
  return chart;
}

std::string fmt(double v) {
  char buffer[64];
  std::snprintf(buffer, sizeof buffer, "%.6g", v);
  return buffer;
}

}  // namespace

std::vector<TriangleGeometry> triangle_geometry(const SurfaceScene& scene) {
  size_t count = 0;
  for (const SceneMesh& mesh : scene.meshes) count += mesh.triangles.size();
  if (count > size_t(std::numeric_limits<uint32_t>::max()))
    throw InputError(scene.name, "too many triangles for 32-bit triangle ids (" + std::to_string(count) + ")");
  std::vector<TriangleGeometry> tris;
  tris.reserve(count);
  for (uint32_t m = 0; m < scene.meshes.size(); ++m) {
    const SceneMesh& mesh = scene.meshes[m];
    for (const auto& tri : mesh.triangles) {
      TriangleGeometry g;
      g.mesh = m;
      for (int k = 0; k < 3; ++k) {
        if (tri[k] >= mesh.positions.size())
          throw InputError(scene.name, "mesh " + std::to_string(m) + " (" + mesh.name + ") has a vertex index out of range (" +
                                           std::to_string(tri[k]) + " of " + std::to_string(mesh.positions.size()) + " points)");
        g.p[k] = mesh.positions[tri[k]];
      }
      const glm::dvec3 c = glm::cross(g.p[1] - g.p[0], g.p[2] - g.p[0]);
      const double len = glm::length(c);
      const double longest = std::max({glm::dot(g.p[1] - g.p[0], g.p[1] - g.p[0]), glm::dot(g.p[2] - g.p[1], g.p[2] - g.p[1]),
                                       glm::dot(g.p[0] - g.p[2], g.p[0] - g.p[2])});
      g.degenerate = !(std::isfinite(len) && finite(g.p[0]) && finite(g.p[1]) && finite(g.p[2]) && len > kDegenerateTriangle * longest);
      if (!g.degenerate) {
        g.normal = c / len;
        g.degenerate = !finite(g.normal);
      }
      if (!g.degenerate)
        g.area = 0.5 * len;
      else
        g.normal = glm::dvec3(0.0);
      tris.push_back(g);
    }
  }
  return tris;
}

std::vector<PlanarChart> grow_planar_charts(const SurfaceScene& scene, const std::vector<TriangleGeometry>& tris, uint32_t max_triangles,
                                            double max_normal_angle_deg) {
  if (max_triangles == 0) throw InputError(scene.name, "planar charts: a chart must be allowed at least one triangle");
  if (!(max_normal_angle_deg > 0.0 && max_normal_angle_deg < 90.0))
    throw InputError(scene.name, "planar charts: the normal angle must lie in (0, 90) degrees, not " + fmt(max_normal_angle_deg));
  std::vector<std::vector<uint32_t>> neighbours;
  neighbours.reserve(tris.size());
  for (uint32_t m = 0; m < scene.meshes.size(); ++m) {
    auto local = edge_neighbours(scene.meshes[m], static_cast<uint32_t>(neighbours.size()));
    for (auto& list : local) neighbours.push_back(std::move(list));
  }
  if (neighbours.size() != tris.size()) throw std::invalid_argument("grow_planar_charts: the geometry is not the scene's");
  const uint32_t triangle_count = static_cast<uint32_t>(tris.size());

  // Grow from the lowest unassigned triangle over shared edges, breadth first.
  const double cos_max = std::cos(max_normal_angle_deg * (3.14159265358979323846 / 180.0));
  constexpr uint32_t kUnassigned = std::numeric_limits<uint32_t>::max();
  std::vector<uint32_t> chart_of(triangle_count, kUnassigned);
  std::vector<uint32_t> tried(triangle_count, kUnassigned);  // the chart that last tested the triangle
  std::vector<PlanarChart> charts;
  std::vector<uint32_t> queue;
  for (uint32_t seed = 0; seed < triangle_count; ++seed) {
    if (chart_of[seed] != kUnassigned) continue;
    const uint32_t id = static_cast<uint32_t>(charts.size());
    chart_of[seed] = id;
    tried[seed] = id;
    const TriangleGeometry& s = tris[seed];
    if (s.degenerate) {
      charts.push_back(point_chart(s.mesh, seed));
      continue;
    }
    ChartBuild chart(s.mesh, s.p[0], s.normal);
    chart.triangles.push_back(seed);
    chart.projected.push_back(chart.project(s));
    chart.boxes.push_back(box_of(chart.projected.back()));
    queue.assign(1, seed);
    for (size_t head = 0; head < queue.size() && chart.triangles.size() < max_triangles; ++head) {
      for (uint32_t t : neighbours[queue[head]]) {
        if (chart.triangles.size() >= max_triangles) break;
        if (chart_of[t] != kUnassigned || tried[t] == id) continue;
        tried[t] = id;
        const TriangleGeometry& g = tris[t];
        if (g.degenerate || glm::dot(g.normal, chart.normal) < cos_max) continue;
        if (!chart.try_add(t, g, chart.project(g))) continue;
        chart_of[t] = id;
        queue.push_back(t);
      }
    }
    charts.push_back(finish(chart));
  }
  return charts;
}

std::optional<PlanarChart> chart_triangles(const std::vector<TriangleGeometry>& tris, std::vector<uint32_t> triangles) {
  if (triangles.empty()) return std::nullopt;
  for (uint32_t t : triangles)
    if (t >= tris.size()) return std::nullopt;
  std::vector<uint32_t> sorted = triangles;
  std::sort(sorted.begin(), sorted.end());
  if (std::adjacent_find(sorted.begin(), sorted.end()) != sorted.end()) return std::nullopt;
  const TriangleGeometry& first = tris[triangles[0]];
  if (triangles.size() == 1 && first.degenerate) return point_chart(first.mesh, triangles[0]);
  glm::dvec3 sum(0.0);
  for (uint32_t t : triangles) {
    if (tris[t].degenerate || tris[t].mesh != first.mesh) return std::nullopt;
    sum += tris[t].area * tris[t].normal;
  }
  const double len = glm::length(sum);
  glm::dvec3 normal = sum / len;
  if (!(len > 0.0) || !finite(normal) || !(glm::length(normal) > 0.5)) normal = first.normal;
  ChartBuild chart(first.mesh, first.p[0], normal);
  for (uint32_t t : triangles)
    if (!chart.try_add(t, tris[t], chart.project(tris[t]))) return std::nullopt;
  return finish(chart);
}

std::optional<PlanarChart> conformal_chart(const std::vector<TriangleGeometry>& tris, const PlanarChart& chart) {
  if (chart.point_like() || chart.triangles.size() < 2) return chart;
  // The chart's vertices: corners that coincide exactly (a mesh's shared vertices).
  std::map<std::array<double, 3>, uint32_t> vertex_of;
  std::vector<glm::dvec2> planar;  // each vertex where `chart` has it
  std::vector<std::array<uint32_t, 3>> corner_vertex(chart.triangles.size());
  for (size_t k = 0; k < chart.triangles.size(); ++k) {
    const uint32_t t = chart.triangles[k];
    if (t >= tris.size() || tris[t].degenerate) return std::nullopt;
    for (int v = 0; v < 3; ++v) {
      const glm::dvec3& p = tris[t].p[v];
      const auto [it, added] = vertex_of.try_emplace({p.x, p.y, p.z}, static_cast<uint32_t>(planar.size()));
      if (added) planar.push_back(chart.corners[k][v]);
      corner_vertex[k][v] = it->second;
    }
  }
  const size_t nv = planar.size();
  // Pins: the two vertices farthest apart in the projection, kept where it has them.
  uint32_t pin_a = 0, pin_b = 1;
  double farthest = -1.0;
  for (uint32_t i = 0; i < nv; ++i)
    for (uint32_t j = i + 1; j < nv; ++j) {
      const glm::dvec2 d = planar[j] - planar[i];
      if (glm::dot(d, d) > farthest) farthest = glm::dot(d, d), pin_a = i, pin_b = j;
    }
  std::vector<int64_t> unknown(nv, -1);  // vertex -> index of its U among the unknowns (V follows)
  size_t n = 0;
  for (uint32_t i = 0; i < nv; ++i)
    if (i != pin_a && i != pin_b) unknown[i] = static_cast<int64_t>(n), n += 2;
  std::vector<double> normal_matrix(n * n, 0.0), rhs(n, 0.0);
  double surface_area = 0.0;
  for (size_t k = 0; k < chart.triangles.size(); ++k) {
    const TriangleGeometry& g = tris[chart.triangles[k]];
    surface_area += g.area;
    // The triangle in its own plane, counter-clockwise seen from its normal: z0 = 0, z1 on +x.
    const glm::dvec3 e1 = g.p[1] - g.p[0], e2 = g.p[2] - g.p[0];
    const glm::dvec3 x = glm::normalize(e1), y = glm::cross(g.normal, x);
    const glm::dvec2 z[3] = {glm::dvec2(0.0), glm::dvec2(glm::length(e1), 0.0), glm::dvec2(glm::dot(e2, x), glm::dot(e2, y))};
    const double weight = 1.0 / std::sqrt(2.0 * g.area);
    // sum_j W_j u_j = 0 (complex; W_j = z_{j+1} - z_{j+2}) holds exactly for similarities: its
    // real and imaginary parts are the two rows, each over (U_j, V_j).
    for (int part = 0; part < 2; ++part) {
      double coef[6];  // (U_j, V_j) for j = 0, 1, 2
      for (int j = 0; j < 3; ++j) {
        const glm::dvec2 w = (z[(j + 1) % 3] - z[(j + 2) % 3]) * weight;
        coef[2 * j] = part == 0 ? w.x : w.y;
        coef[2 * j + 1] = part == 0 ? -w.y : w.x;
      }
      double pinned = 0.0;  // the row's value from the pinned vertices
      for (int j = 0; j < 3; ++j) {
        const uint32_t vtx = corner_vertex[k][j];
        if (unknown[vtx] < 0) pinned += coef[2 * j] * planar[vtx].x + coef[2 * j + 1] * planar[vtx].y;
      }
      for (int j = 0; j < 3; ++j) {
        const int64_t r = unknown[corner_vertex[k][j]];
        if (r < 0) continue;
        for (int d = 0; d < 2; ++d) {
          const size_t row = static_cast<size_t>(r) + d;
          rhs[row] -= coef[2 * j + d] * pinned;
          for (int i = 0; i < 3; ++i) {
            const int64_t c = unknown[corner_vertex[k][i]];
            if (c < 0) continue;
            for (int e = 0; e < 2; ++e) normal_matrix[row * n + static_cast<size_t>(c) + e] += coef[2 * j + d] * coef[2 * i + e];
          }
        }
      }
    }
  }
  if (n > 0 && !solve_spd(normal_matrix, rhs, n)) return std::nullopt;
  std::vector<glm::dvec2> uv(nv);
  for (uint32_t i = 0; i < nv; ++i)
    uv[i] = unknown[i] < 0 ? planar[i] : glm::dvec2(rhs[static_cast<size_t>(unknown[i])], rhs[static_cast<size_t>(unknown[i]) + 1]);
  double chart_area = 0.0;
  for (const auto& cv : corner_vertex) chart_area += 0.5 * orient(uv[cv[0]], uv[cv[1]], uv[cv[2]]);
  if (!(chart_area > 0.0) || !std::isfinite(chart_area)) return std::nullopt;
  const double scale = std::sqrt(surface_area / chart_area);
  // Kept only where it samples its worst triangle at least as well as the projection does (to
  // rounding: on a flat meshlet the two are the same map).
  auto worst_sampling = [&](auto corner) {
    double worst = std::numeric_limits<double>::infinity();
    for (size_t k = 0; k < chart.triangles.size(); ++k)
      worst = std::min(worst, std::sqrt(0.5 * std::abs(orient(corner(k, 0), corner(k, 1), corner(k, 2))) / tris[chart.triangles[k]].area));
    return worst;
  };
  const double projected = worst_sampling([&](size_t k, int v) { return chart.corners[k][v]; });
  const double conformal = worst_sampling([&](size_t k, int v) { return uv[corner_vertex[k][v]] * scale; });
  if (!(conformal >= projected * (1.0 - 1e-9))) return std::nullopt;
  ChartBuild build(chart.mesh, tris[chart.triangles[0]].p[0], chart.normal);
  for (size_t k = 0; k < chart.triangles.size(); ++k) {
    const std::array<glm::dvec2, 3> corners{uv[corner_vertex[k][0]] * scale, uv[corner_vertex[k][1]] * scale, uv[corner_vertex[k][2]] * scale};
    if (!std::isfinite(corners[0].x + corners[0].y + corners[1].x + corners[1].y + corners[2].x + corners[2].y)) return std::nullopt;
    if (!build.try_add(chart.triangles[k], tris[chart.triangles[k]], corners)) return std::nullopt;  // flipped, shrunk or overlapping
  }
  return finish(build);
}

}  // namespace prismoid::charts
