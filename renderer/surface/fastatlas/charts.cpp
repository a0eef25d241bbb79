#include "renderer/surface/fastatlas/charts.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>

#include <glm/trigonometric.hpp>
#include <glm/vec4.hpp>

#include "scene/disjoint_sets.hpp"

namespace prismoid::fastatlas {

Charts visible_charts(const HalfedgeMesh& mesh, const std::vector<uint8_t>& visible) {
  const size_t faces = mesh.face_count();
  if (visible.size() != faces) throw std::invalid_argument("visible_charts: one visibility flag per face");
  DisjointSets sets(faces);  // rooted at the lowest face, as the GPU's hooking keeps the minimum
  // Across shared edges.
  for (size_t h = 0; h < mesh.halfedge_count(); ++h) {
    const int32_t t = mesh.twin[h];
    if (t == kNoHalfedge) continue;
    const uint32_t f = uint32_t(h / 3), g = uint32_t(t / 3);
    if (visible[f] && visible[g]) sets.unite(f, g);
  }
  // Across shared vertices: the first visible face at each vertex joins every other one there.
  std::vector<uint32_t> first_at(mesh.vertex_count(), kNoChart);
  for (uint32_t f = 0; f < faces; ++f) {
    if (!visible[f]) continue;
    for (uint32_t v : mesh.faces[f]) {
      if (first_at[v] == kNoChart) first_at[v] = f;
      else sets.unite(first_at[v], f);
    }
  }
  Charts charts;
  charts.chart_of_face.assign(faces, kNoChart);
  std::vector<uint32_t> chart_of_root(faces, kNoChart);
  for (uint32_t f = 0; f < faces; ++f) {  // in face order, so charts come numbered by their roots
    if (!visible[f]) continue;
    const uint32_t r = sets.find(f);
    if (chart_of_root[r] == kNoChart) {
      chart_of_root[r] = uint32_t(charts.root.size());
      charts.root.push_back(r);
    }
    charts.chart_of_face[f] = chart_of_root[r];
  }
  charts.chart_of_vertex.assign(mesh.vertex_count(), kNoChart);
  for (uint32_t v = 0; v < mesh.vertex_count(); ++v)
    if (first_at[v] != kNoChart) charts.chart_of_vertex[v] = charts.chart_of_face[first_at[v]];
  return charts;
}

PixelBox triangle_box(const glm::dvec3& a, const glm::dvec3& b, const glm::dvec3& c, const Camera& camera, uint32_t width,
                      uint32_t height) {
  // Camera space relative to the eye (the camera looks along -z); kept in double.
  const glm::dmat4 view = view_matrix(camera, camera.eye);
  const glm::dvec3 v[3] = {glm::dvec3(view * glm::dvec4(a - camera.eye, 1.0)), glm::dvec3(view * glm::dvec4(b - camera.eye, 1.0)),
                           glm::dvec3(view * glm::dvec4(c - camera.eye, 1.0))};
  // Clip against the near plane z = -near: what lies at depth >= near remains (3 or 4 points).
  const double near = camera.near_distance;
  glm::dvec3 kept[4];
  int n = 0;
  for (int i = 0; i < 3; ++i) {
    const glm::dvec3& p = v[i];
    const glm::dvec3& q = v[(i + 1) % 3];
    const double dp = -p.z - near, dq = -q.z - near;  // >= 0: beyond the near plane
    if (dp >= 0.0) kept[n++] = p;
    if ((dp >= 0.0) != (dq >= 0.0)) kept[n++] = p + (q - p) * (dp / (dp - dq));
  }
  PixelBox box;
  if (n == 0) return box;
  const double tan_half = std::tan(glm::radians(camera.fovy_degrees) * 0.5);
  const double aspect = double(width) / double(height);
  double x0 = 1.0, x1 = -1.0, y0 = 1.0, y1 = -1.0;  // normalized device coordinates, y up
  for (int i = 0; i < n; ++i) {
    const double depth = -kept[i].z;  // >= near > 0
    const double x = kept[i].x / (depth * tan_half * aspect), y = kept[i].y / (depth * tan_half);
    x0 = std::min(x0, x);
    x1 = std::max(x1, x);
    y0 = std::min(y0, y);
    y1 = std::max(y1, y);
  }
  x0 = std::max(x0, -1.0);
  x1 = std::min(x1, 1.0);
  y0 = std::max(y0, -1.0);
  y1 = std::min(y1, 1.0);
  if (!(x1 > x0 && y1 > y0)) return box;
  // To pixels, y down from the top.
  box.x0 = (x0 + 1.0) * 0.5 * width;
  box.x1 = (x1 + 1.0) * 0.5 * width;
  box.y0 = (1.0 - y1) * 0.5 * height;
  box.y1 = (1.0 - y0) * 0.5 * height;
  return box;
}

ChartScreenBoxes chart_boxes(const HalfedgeMesh& mesh, const Charts& charts, const Camera& camera, uint32_t width, uint32_t height) {
  ChartScreenBoxes out;
  const size_t n = charts.root.size();
  const double inf = std::numeric_limits<double>::infinity();
  out.boxes.assign(n, PixelBox{inf, inf, -inf, -inf});
  for (size_t f = 0; f < mesh.face_count(); ++f) {
    const uint32_t c = charts.chart_of_face[f];
    if (c == kNoChart) continue;
    const auto& t = mesh.faces[f];
    const PixelBox b = triangle_box(mesh.positions[t[0]], mesh.positions[t[1]], mesh.positions[t[2]], camera, width, height);
    if (b.empty()) continue;
    PixelBox& u = out.boxes[c];
    u.x0 = std::min(u.x0, b.x0);
    u.y0 = std::min(u.y0, b.y0);
    u.x1 = std::max(u.x1, b.x1);
    u.y1 = std::max(u.y1, b.y1);
  }
  out.width.resize(n);
  out.height.resize(n);
  for (size_t c = 0; c < n; ++c) {
    PixelBox& u = out.boxes[c];
    if (u.empty()) u = PixelBox{};  // a chart only touching the viewport's edge: one pixel
    out.width[c] = uint32_t(std::max(1.0, std::ceil(u.x1) - std::floor(u.x0)));
    out.height[c] = uint32_t(std::max(1.0, std::ceil(u.y1) - std::floor(u.y0)));
  }
  return out;
}

}  // namespace prismoid::fastatlas
