#include "renderer/reference/tet_ray.hpp"

#include <algorithm>
#include <cmath>
#include <glm/geometric.hpp>
#include <glm/trigonometric.hpp>
#include <limits>
#include <functional>

namespace prismoid::reference {

Interval ray_tetrahedron(const std::array<glm::dvec3, 4>& v, const glm::dvec3& origin, const glm::dvec3& direction,
                         double t_min, double t_max) {
  static const int kFaces[4][3] = {{1, 2, 3}, {0, 3, 2}, {0, 1, 3}, {0, 2, 1}};
  // No component zero and no simple ratios between them, so no face normal of a real mesh
  // is orthogonal to it.
  static const glm::dvec3 kTieBreak(0.5773502691896258, 0.2113248654051871, 0.7886751345948129);
  Interval r{t_min, t_max};
  for (int f = 0; f < 4; ++f) {
    const glm::dvec3& a = v[kFaces[f][0]];
    glm::dvec3 n = glm::cross(v[kFaces[f][1]] - a, v[kFaces[f][2]] - a);
    // Orient n away from the opposite vertex, whatever the tetrahedron's orientation.
    if (glm::dot(n, v[f] - a) > 0.0) n = -n;
    const double dist = glm::dot(n, origin - a);  // > 0 outside the face's half-space
    const double rate = glm::dot(n, direction);
    if (rate == 0.0) {
      // The ray runs parallel to the face. When it lies exactly in the face's plane (a pixel
      // ray along a grid line of an axis-aligned mesh), both cells sharing the face would
      // claim it; decide as if the ray were moved by an infinitesimal step along a fixed
      // generic direction, so exactly one of them does (simulation of simplicity).
      if (dist > 0.0 || (dist == 0.0 && glm::dot(n, kTieBreak) >= 0.0)) return {0.0, 0.0};
      continue;
    }
    const double t = -dist / rate;
    if (rate > 0.0) r.exit = std::min(r.exit, t);   // leaving through this face
    else r.enter = std::max(r.enter, t);            // entering through this face
    if (r.empty()) return {0.0, 0.0};
  }
  return r;
}

double interpolate_linear(const std::array<glm::dvec3, 4>& v, const std::array<double, 4>& s, const glm::dvec3& p) {
  const double volume = signed_volume(v[0], v[1], v[2], v[3]);
  if (volume == 0.0) return 0.25 * (s[0] + s[1] + s[2] + s[3]);
  double value = 0.0;
  for (int i = 0; i < 4; ++i) {
    std::array<glm::dvec3, 4> w = v;
    w[i] = p;
    value += s[i] * signed_volume(w[0], w[1], w[2], w[3]) / volume;
  }
  return value;
}

namespace {

struct CameraFrame {
  glm::dvec3 right, up, forward;
  double tan_half_fovy, aspect;
};

CameraFrame frame_of(const Camera& camera, uint32_t width, uint32_t height) {
  CameraFrame f;
  f.forward = glm::normalize(camera.target - camera.eye);
  f.right = glm::normalize(glm::cross(f.forward, camera.up));
  f.up = glm::cross(f.right, f.forward);
  f.tan_half_fovy = std::tan(glm::radians(camera.fovy_degrees) * 0.5);
  f.aspect = double(width) / double(height);
  return f;
}

}  // namespace

glm::dvec3 ray_direction(const Camera& camera, uint32_t width, uint32_t height, double px, double py) {
  const CameraFrame f = frame_of(camera, width, height);
  const double ndc_x = 2.0 * px / width - 1.0;
  const double ndc_y = 2.0 * py / height - 1.0;  // grows downwards, as Vulkan's
  const glm::dvec3 d = f.forward + ndc_x * f.tan_half_fovy * f.aspect * f.right - ndc_y * f.tan_half_fovy * f.up;
  return glm::normalize(d);
}

void trace_cells(const TetMesh& mesh, const Camera& camera, uint32_t width, uint32_t height, double offset_x, double offset_y,
                 const std::function<bool(size_t cell)>& wanted, const CellVisitor& visit) {
  const CameraFrame f = frame_of(camera, width, height);
  for (size_t c = 0; c < mesh.tets.size(); ++c) {
    if (!wanted(c)) continue;
    std::array<glm::dvec3, 4> v;
    for (int i = 0; i < 4; ++i) v[i] = mesh.points[mesh.tets[c][i]];
    // Pixel bounds of the projection when the cell lies in front of the eye; all pixels
    // otherwise (the plane tests decide).
    double x0 = 0, x1 = width - 1.0, y0 = 0, y1 = height - 1.0;
    bool in_front = true, any_in_front = false;
    for (const auto& p : v) {
      const double depth = glm::dot(p - camera.eye, f.forward);
      in_front = in_front && depth > camera.near_distance;
      any_in_front = any_in_front || depth > camera.near_distance;
    }
    if (!any_in_front) continue;  // wholly behind the near plane: nothing to integrate
    double px_min = 1e300, px_max = -1e300, py_min = 1e300, py_max = -1e300;
    for (const auto& p : v) {
      if (!in_front) break;
      const glm::dvec3 rel = p - camera.eye;
      const double depth = glm::dot(rel, f.forward);
      const double nx = glm::dot(rel, f.right) / (depth * f.tan_half_fovy * f.aspect);
      const double ny = -glm::dot(rel, f.up) / (depth * f.tan_half_fovy);
      const double px = (nx + 1.0) * 0.5 * width - 0.5, py = (ny + 1.0) * 0.5 * height - 0.5;
      px_min = std::min(px_min, px); px_max = std::max(px_max, px);
      py_min = std::min(py_min, py); py_max = std::max(py_max, py);
    }
    if (in_front) {
      x0 = std::max(x0, std::floor(px_min) - 1); x1 = std::min(x1, std::ceil(px_max) + 1);
      y0 = std::max(y0, std::floor(py_min) - 1); y1 = std::min(y1, std::ceil(py_max) + 1);
    }
    for (double yd = y0; yd <= y1; ++yd)
      for (double xd = x0; xd <= x1; ++xd) {
        const auto x = static_cast<uint32_t>(xd), y = static_cast<uint32_t>(yd);
        const glm::dvec3 dir = ray_direction(camera, width, height, x + 0.5 + offset_x, y + 0.5 + offset_y);
        const double t_near = camera.near_distance / glm::dot(dir, f.forward);
        const Interval in = ray_tetrahedron(v, camera.eye, dir, t_near, std::numeric_limits<double>::infinity());
        if (!in.empty()) visit(size_t(y) * width + x, c, in, dir);
      }
  }
}

std::vector<double> optical_depth_image(const TetMesh& mesh, const Camera& camera, uint32_t width, uint32_t height,
                                        double offset_x, double offset_y, std::vector<uint32_t>* cells_hit) {
  std::vector<double> image(size_t(width) * height, 0.0);
  if (cells_hit) cells_hit->assign(image.size(), 0u);
  const bool linear = mesh.linear_extinction();
  auto corners = [&](size_t c) {
    std::array<glm::dvec3, 4> v;
    for (int i = 0; i < 4; ++i) v[i] = mesh.points[mesh.tets[c][i]];
    return v;
  };
  auto point_sigma = [&](size_t c) {
    std::array<double, 4> s{};
    for (int i = 0; i < 4; ++i) s[i] = mesh.point_extinction[mesh.tets[c][i]];
    return s;
  };
  auto wanted = [&](size_t c) {
    if (!linear) return mesh.cell_extinction[c] != 0.0;
    const auto s = point_sigma(c);
    return std::max({s[0], s[1], s[2], s[3]}) != 0.0;
  };
  trace_cells(mesh, camera, width, height, offset_x, offset_y, wanted,
              [&](size_t pixel, size_t c, const Interval& in, const glm::dvec3& dir) {
                double mean_sigma = mesh.cell_extinction[c];
                if (linear) {
                  const auto v = corners(c);
                  const auto s = point_sigma(c);
                  mean_sigma = 0.5 * (interpolate_linear(v, s, camera.eye + in.enter * dir) +
                                      interpolate_linear(v, s, camera.eye + in.exit * dir));
                }
                image[pixel] += mean_sigma * in.length();
                if (cells_hit) ++(*cells_hit)[pixel];
              });
  return image;
}

}  // namespace prismoid::reference
