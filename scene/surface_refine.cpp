#include "scene/surface_refine.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <map>
#include <string>
#include <utility>

#include <glm/geometric.hpp>
#include <glm/trigonometric.hpp>

#include "scene/input_error.hpp"

namespace prismoid {

namespace {

struct View {
  glm::dvec3 eye, right, up, forward;
  double near = 0.0, tan_x = 0.0, tan_y = 0.0;
  double width = 0.0, height = 0.0, max_pixels = 0.0;

  // Whether the part of triangle (a, b, c) inside the view frustum spans more than max_pixels
  // across or down the image: the triangle clipped against the near plane and the four side
  // planes (Sutherland-Hodgman, in camera space), its corners projected.
  bool large(const glm::dvec3& a, const glm::dvec3& b, const glm::dvec3& c) const {
    std::array<glm::dvec3, 8> poly{}, next{};
    size_t n = 0;
    for (const glm::dvec3& p : {a, b, c}) {
      const glm::dvec3 d = p - eye;
      poly[n++] = {glm::dot(d, right), glm::dot(d, up), glm::dot(d, forward)};
    }
    auto plane = [&](int k, const glm::dvec3& q) {
      switch (k) {
        case 0: return q.z - near;
        case 1: return q.z * tan_x - q.x;
        case 2: return q.z * tan_x + q.x;
        case 3: return q.z * tan_y - q.y;
        default: return q.z * tan_y + q.y;
      }
    };
    for (int k = 0; k < 5 && n > 0; ++k) {
      size_t m = 0;
      for (size_t i = 0; i < n; ++i) {
        const glm::dvec3 &p = poly[i], &q = poly[(i + 1) % n];
        const double dp = plane(k, p), dq = plane(k, q);
        if (dp >= 0.0) next[m++] = p;
        if ((dp >= 0.0) != (dq >= 0.0) && m < next.size()) next[m++] = p + (q - p) * (dp / (dp - dq));
      }
      poly = next;
      n = m;
    }
    if (n < 3) return false;  // nothing of it on the screen
    glm::dvec2 lo(INFINITY), hi(-INFINITY);
    for (size_t i = 0; i < n; ++i) {
      const double z = std::max(poly[i].z, near);
      const glm::dvec2 px(poly[i].x / (z * tan_x) * 0.5 * width, poly[i].y / (z * tan_y) * 0.5 * height);
      lo = glm::min(lo, px);
      hi = glm::max(hi, px);
    }
    return std::max(hi.x - lo.x, hi.y - lo.y) > max_pixels;
  }
};

// One round over a mesh; false when no edge was long. `grow(n)` hears of the n triangles the
// round adds before they are made (and may throw).
template <typename Grow>
bool refine_round(SceneMesh& mesh, const View& view, size_t& split_edges, Grow&& grow) {
  using Edge = std::pair<uint32_t, uint32_t>;
  auto key = [](uint32_t a, uint32_t b) { return a < b ? Edge{a, b} : Edge{b, a}; };
  std::map<Edge, uint32_t> midpoint;
  const bool normals = !mesh.normals.empty();
  const bool vertex_colors = mesh.color_binding == ColorBinding::PerVertex;
  // Each large triangle's longest edge is split (longest-edge bisection, so the parts stay
  // shapely), and so, to keep the mesh conforming, is that edge in the triangle across it.
  for (const auto& t : mesh.triangles) {
    const auto& p = mesh.positions;
    if (!view.large(p[t[0]], p[t[1]], p[t[2]])) continue;
    int longest = 0;
    for (int k = 1; k < 3; ++k)
      if (glm::length(p[t[(k + 1) % 3]] - p[t[k]]) > glm::length(p[t[(longest + 1) % 3]] - p[t[longest]])) longest = k;
    const Edge e = key(t[longest], t[(longest + 1) % 3]);
    if (midpoint.count(e)) continue;
    midpoint[e] = uint32_t(mesh.positions.size());
    mesh.positions.push_back(0.5 * (mesh.positions[e.first] + mesh.positions[e.second]));
    if (normals) {
      const glm::dvec3 sum = mesh.normals[e.first] + mesh.normals[e.second];
      const double len = glm::length(sum);
      mesh.normals.push_back(len > 0.0 && std::isfinite(len) ? sum / len : mesh.normals[e.first]);
    }
    if (vertex_colors) mesh.colors.push_back(0.5 * (mesh.colors[e.first] + mesh.colors[e.second]));
  }
  if (midpoint.empty()) return false;
  split_edges += midpoint.size();
  size_t added = 0;  // a triangle with n split edges becomes n + 1
  for (const auto& t : mesh.triangles)
    for (int k = 0; k < 3; ++k) added += midpoint.count(key(t[k], t[(k + 1) % 3]));
  grow(added);
  std::vector<std::array<uint32_t, 3>> out;
  std::vector<glm::dvec3> triangle_colors;
  const bool per_triangle = mesh.color_binding == ColorBinding::PerTriangle;
  for (size_t i = 0; i < mesh.triangles.size(); ++i) {
    const auto& t = mesh.triangles[i];
    std::array<uint32_t, 3> m{};
    int splits = 0;
    for (int k = 0; k < 3; ++k) {
      const auto it = midpoint.find(key(t[k], t[(k + 1) % 3]));
      m[k] = it == midpoint.end() ? UINT32_MAX : it->second;  // m[k]: the midpoint of edge t[k] -> t[k + 1]
      splits += it != midpoint.end();
    }
    const size_t before = out.size();
    if (splits == 0) {
      out.push_back(t);
    } else if (splits == 3) {
      out.push_back({t[0], m[0], m[2]});
      out.push_back({m[0], t[1], m[1]});
      out.push_back({m[2], m[1], t[2]});
      out.push_back({m[0], m[1], m[2]});
    } else {
      // Rotate so that the split edges come first: one split: edge 0; two: edges 0 and 1.
      int r = 0;
      if (splits == 1) {
        while (m[r] == UINT32_MAX) ++r;
      } else {
        while (!(m[r] != UINT32_MAX && m[(r + 1) % 3] != UINT32_MAX)) ++r;
      }
      const uint32_t a = t[r], b = t[(r + 1) % 3], c = t[(r + 2) % 3], mab = m[r], mbc = m[(r + 1) % 3];
      if (splits == 1) {
        out.push_back({a, mab, c});
        out.push_back({mab, b, c});
      } else {
        out.push_back({mab, b, mbc});
        // The quad a, mab, mbc, c along its shorter diagonal.
        const auto& p = mesh.positions;
        if (glm::length(p[mbc] - p[a]) <= glm::length(p[c] - p[mab])) {
          out.push_back({a, mab, mbc});
          out.push_back({a, mbc, c});
        } else {
          out.push_back({a, mab, c});
          out.push_back({mab, mbc, c});
        }
      }
    }
    if (per_triangle)
      for (size_t k = before; k < out.size(); ++k) triangle_colors.push_back(mesh.colors[i]);
  }
  mesh.triangles = std::move(out);
  if (per_triangle) mesh.colors = std::move(triangle_colors);
  return true;
}

}  // namespace

SurfaceScene refine_large_triangles(const SurfaceScene& scene, const Camera& camera, uint32_t image_width, uint32_t image_height,
                                   double max_pixels, RefineStats* stats, size_t max_triangles) {
  if (!(max_pixels > 0.0) || !std::isfinite(max_pixels))
    throw InputError("--max-triangle-pixels", "the largest extent must be a finite, positive number of pixels (got " + std::to_string(max_pixels) + ")");
  if (image_width == 0 || image_height == 0) throw InputError("--max-triangle-pixels", "needs an image of at least one pixel");
  validate(camera);
  View view;
  view.eye = camera.eye;
  view.forward = glm::normalize(camera.target - camera.eye);
  view.right = glm::normalize(glm::cross(view.forward, camera.up));
  view.up = glm::cross(view.right, view.forward);
  view.near = camera.near_distance;
  view.tan_y = std::tan(glm::radians(camera.fovy_degrees) * 0.5);
  view.tan_x = view.tan_y * double(image_width) / double(image_height);
  view.width = image_width;
  view.height = image_height;
  view.max_pixels = max_pixels;
  SurfaceScene out = scene;
  RefineStats s;
  auto count = [&] {
    size_t n = 0;
    for (const SceneMesh& m : out.meshes) n += m.triangles.size();
    return n;
  };
  s.triangles_before = count();
  size_t triangles = s.triangles_before;
  auto grow = [&](size_t added) {
    triangles += added;
    if (triangles > max_triangles)
      throw InputError("--max-triangle-pixels", std::to_string(max_pixels) + " pixels would split " + scene.name + " into more than " +
                                                std::to_string(triangles) + " triangles (at most " + std::to_string(max_triangles) +
                                                "): give a larger size, or move the camera's near plane out");
  };
  for (bool any = true; any;) {
    any = false;
    for (SceneMesh& mesh : out.meshes) {
      const glm::dvec3 e = mesh.material < out.materials.size() ? out.materials[mesh.material].emission : glm::dvec3(0.0);
      if (e.x > 0.0 || e.y > 0.0 || e.z > 0.0) continue;  // an emitter: see the header
      any = refine_round(mesh, view, s.split_edges, grow) || any;
    }
    s.rounds += any;
  }
  s.triangles_after = count();
  if (stats) *stats = s;
  return out;
}

}  // namespace prismoid
