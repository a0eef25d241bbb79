#include "renderer/reference/tet_ray.hpp"

#include <algorithm>
#include <cmath>
#include <glm/geometric.hpp>
#include <glm/trigonometric.hpp>
#include <glm/vec2.hpp>
#include <functional>
#include <limits>

#include "renderer/reference/row_threads.hpp"
#include "scene/tet_mesh.hpp"

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

namespace {

// One cell as the integrator sees it.
struct Cell {
  std::array<glm::dvec3, 4> v;
  std::array<double, 4> point_sigma{};
  double sigma = 0.0;
  bool linear = false;
};

// The cell's optical depth along the unit ray eye + t dir, counting only the part beyond the
// near plane; `hit` says whether the ray crosses it with a positive length.
// The ray's parameter where it reaches depth `depth` along the viewing axis (+inf for +inf).
double t_at_depth(double depth, const CameraFrame& f, const glm::dvec3& dir) { return depth / glm::dot(dir, f.forward); }

// The pixel's depth limit (+inf without one).
double limit_at(const std::vector<float>* depth_limit, size_t pixel) {
  return depth_limit ? double((*depth_limit)[pixel]) : std::numeric_limits<double>::infinity();
}

double cell_optical_depth(const Cell& cell, const Camera& camera, const CameraFrame& f, const glm::dvec3& dir, bool& hit,
                          double depth_limit = std::numeric_limits<double>::infinity()) {
  const Interval in = ray_tetrahedron(cell.v, camera.eye, dir, t_at_depth(camera.near_distance, f, dir), t_at_depth(depth_limit, f, dir));
  hit = !in.empty();
  if (!hit) return 0.0;
  double mean_sigma = cell.sigma;
  if (cell.linear)
    mean_sigma = 0.5 * (interpolate_linear(cell.v, cell.point_sigma, camera.eye + in.enter * dir) +
                        interpolate_linear(cell.v, cell.point_sigma, camera.eye + in.exit * dir));
  return mean_sigma * in.length();
}

// Calls visit(cell, x0, x1, y0, y1, projected) for every cell c with wanted(c, cell) and some
// part beyond the near plane: [x0, x1] x [y0, y1] are the pixels whose rays (within a pixel
// of their centres) can meet it, `projected` its vertices in continuous pixel coordinates
// (empty when a vertex lies before the near plane; then the rectangle is the whole image).
// Only the rows of `rows` are asked for: y0 is the first of them, and visit steps by rows.step.
template <typename Wanted, typename Visit>
void for_each_cell(const TetMesh& mesh, const Camera& camera, const CameraFrame& f, uint32_t width, uint32_t height,
                   RowPhase rows, Wanted&& wanted, Visit&& visit) {
  std::vector<glm::dvec2> projected;
  for (size_t c = 0; c < mesh.tets.size(); ++c) {
    Cell cell;
    cell.sigma = mesh.cell_extinction[c];
    cell.linear = mesh.linear_extinction();
    for (int i = 0; i < 4; ++i) {
      cell.v[i] = mesh.points[mesh.tets[c][i]];
      if (cell.linear) cell.point_sigma[i] = mesh.point_extinction[mesh.tets[c][i]];
    }
    if (!wanted(c, cell)) continue;
    bool in_front = true, any_in_front = false;
    for (const auto& p : cell.v) {
      const double depth = glm::dot(p - camera.eye, f.forward);
      in_front = in_front && depth > camera.near_distance;
      any_in_front = any_in_front || depth > camera.near_distance;
    }
    if (!any_in_front) continue;  // wholly behind the near plane: nothing to integrate
    double x0 = 0, x1 = width - 1.0, y0 = 0, y1 = height - 1.0;
    projected.clear();
    if (in_front) {
      double px_min = 1e300, px_max = -1e300, py_min = 1e300, py_max = -1e300;
      for (const auto& p : cell.v) {
        const glm::dvec3 rel = p - camera.eye;
        const double depth = glm::dot(rel, f.forward);
        const double nx = glm::dot(rel, f.right) / (depth * f.tan_half_fovy * f.aspect);
        const double ny = -glm::dot(rel, f.up) / (depth * f.tan_half_fovy);
        projected.emplace_back((nx + 1.0) * 0.5 * width, (ny + 1.0) * 0.5 * height);
        const double px = projected.back().x - 0.5, py = projected.back().y - 0.5;
        px_min = std::min(px_min, px); px_max = std::max(px_max, px);
        py_min = std::min(py_min, py); py_max = std::max(py_max, py);
      }
      x0 = std::max(x0, std::floor(px_min) - 1); x1 = std::min(x1, std::ceil(px_max) + 1);
      y0 = std::max(y0, std::floor(py_min) - 1); y1 = std::min(y1, std::ceil(py_max) + 1);
    }
    if (y1 < y0) continue;
    y0 = double(rows.first_from(uint32_t(y0)));
    if (y0 > y1) continue;  // none of this thread's rows
    visit(c, cell, x0, x1, y0, y1, projected);
  }
}

// Cells with no extinction add nothing to the optical depth.
bool absorbs(size_t, const Cell& cell) {
  const auto& ps = cell.point_sigma;
  return cell.linear ? std::max({ps[0], ps[1], ps[2], ps[3]}) != 0.0 : cell.sigma != 0.0;
}

}  // namespace

void trace_cells(const TetMesh& mesh, const Camera& camera, uint32_t width, uint32_t height, double offset_x, double offset_y,
                 const std::function<bool(size_t cell)>& wanted, const CellVisitor& visit, const std::vector<float>* depth_limit) {
  const CameraFrame f = frame_of(camera, width, height);
  for_row_phases(height, [&](RowPhase rows) {
  for_each_cell(mesh, camera, f, width, height, rows, [&](size_t c, const Cell&) { return wanted(c); },
                [&](size_t c, const Cell& cell, double x0, double x1, double y0, double y1, const auto&) {
    for (double yd = y0; yd <= y1; yd += rows.step)
      for (double xd = x0; xd <= x1; ++xd) {
        const auto x = static_cast<uint32_t>(xd), y = static_cast<uint32_t>(yd);
        const glm::dvec3 dir = ray_direction(camera, width, height, x + 0.5 + offset_x, y + 0.5 + offset_y);
        const size_t pixel = size_t(y) * width + x;
        const Interval in = ray_tetrahedron(cell.v, camera.eye, dir, t_at_depth(camera.near_distance, f, dir),
                                            t_at_depth(limit_at(depth_limit, pixel), f, dir));
        if (!in.empty()) visit(pixel, c, in, dir);
      }
  });
  });
}

std::vector<double> optical_depth_image(const TetMesh& mesh, const Camera& camera, uint32_t width, uint32_t height,
                                        double offset_x, double offset_y, std::vector<uint32_t>* cells_hit,
                                        const std::vector<float>* depth_limit) {
  std::vector<double> image(size_t(width) * height, 0.0);
  if (cells_hit) cells_hit->assign(image.size(), 0u);
  const CameraFrame f = frame_of(camera, width, height);
  for_row_phases(height, [&](RowPhase rows) {
  for_each_cell(mesh, camera, f, width, height, rows, absorbs, [&](size_t, const Cell& cell, double x0, double x1, double y0, double y1, const auto&) {
    for (double yd = y0; yd <= y1; yd += rows.step)
      for (double xd = x0; xd <= x1; ++xd) {
        const auto x = static_cast<uint32_t>(xd), y = static_cast<uint32_t>(yd);
        const glm::dvec3 dir = ray_direction(camera, width, height, x + 0.5 + offset_x, y + 0.5 + offset_y);
        bool hit = false;
        const size_t pixel = size_t(y) * width + x;
        image[pixel] += cell_optical_depth(cell, camera, f, dir, hit, limit_at(depth_limit, pixel));
        if (cells_hit && hit) ++(*cells_hit)[pixel];
      }
  });
  });
  return image;
}

std::vector<double> snapping_variation_image(const TetMesh& mesh, const Camera& camera, uint32_t width, uint32_t height,
                                             double radius) {
  std::vector<double> image(size_t(width) * height, 0.0);
  const CameraFrame f = frame_of(camera, width, height);
  const double limit_step = std::ldexp(1.0, -20);
  for_row_phases(height, [&](RowPhase rows) {
  for_each_cell(mesh, camera, f, width, height, rows, absorbs,
                [&](size_t, const Cell& cell, double x0, double x1, double y0, double y1, const std::vector<glm::dvec2>& projected) {
    auto depth_at = [&](double px, double py) {
      bool hit = false;
      return cell_optical_depth(cell, camera, f, ray_direction(camera, width, height, px, py), hit);
    };
    for (double yd = y0; yd <= y1; yd += rows.step)
      for (double xd = x0; xd <= x1; ++xd) {
        const double cx = xd + 0.5, cy = yd + 0.5;
        const double centre = depth_at(cx, cy);
        double variation = 0.0;
        for (int dy = -1; dy <= 1; ++dy)
          for (int dx = -1; dx <= 1; ++dx)
            if (dx || dy) variation = std::max(variation, std::abs(depth_at(cx + dx * radius, cy + dy * radius) - centre));
        // A vertex within reach: the optical depth can jump there (a face through the eye
        // has a chord up to its silhouette), so take its one-sided limits too.
        for (const glm::dvec2& p : projected) {
          if (std::abs(p.x - cx) > radius || std::abs(p.y - cy) > radius) continue;
          for (int dy = -1; dy <= 1; ++dy)
            for (int dx = -1; dx <= 1; ++dx)
              if (dx || dy) variation = std::max(variation, std::abs(depth_at(p.x + dx * limit_step, p.y + dy * limit_step) - centre));
        }
        image[size_t(yd) * width + size_t(xd)] += variation;
      }
  });
  });
  return image;
}

glm::dvec2 surface_depth_gradients(const std::array<glm::dvec3, 4>& v, const Camera& camera, uint32_t width, uint32_t height,
                                   double px, double py, double step) {
  const CameraFrame f = frame_of(camera, width, height);
  auto depths_at = [&](double x, double y, glm::dvec2& depths) {
    const glm::dvec3 dir = ray_direction(camera, width, height, x, y);
    const double cos = glm::dot(dir, f.forward);
    const Interval in = ray_tetrahedron(v, camera.eye, dir, camera.near_distance / cos, std::numeric_limits<double>::infinity());
    depths = glm::dvec2(in.enter, in.exit) * cos;
    return !in.empty();
  };
  glm::dvec2 here;
  if (!depths_at(px, py, here)) return glm::dvec2(0.0);
  glm::dvec2 gradient2(0.0);  // squared, per surface
  for (int axis = 0; axis < 2; ++axis) {
    glm::dvec2 change(0.0);
    for (double sign : {1.0, -1.0}) {
      glm::dvec2 other;
      if (depths_at(px + (axis == 0 ? sign * step : 0.0), py + (axis == 1 ? sign * step : 0.0), other))
        change = glm::max(change, glm::abs(other - here) / step);
    }
    gradient2 += change * change;
  }
  return glm::sqrt(gradient2);
}

std::vector<double> surface_sensitivity_image(const TetMesh& mesh, const Camera& camera, uint32_t width, uint32_t height,
                                              double radius) {
  std::vector<double> image(size_t(width) * height, 0.0);
  const CameraFrame f = frame_of(camera, width, height);
  const double step = 0.25 * radius;  // finite differences within a proxy triangle, mostly
  const double footprint_per_depth = 2.0 * f.tan_half_fovy / height;  // a pixel's world size at depth 1
  for_row_phases(height, [&](RowPhase rows) {
  for_each_cell(mesh, camera, f, width, height, rows, absorbs, [&](size_t, const Cell& cell, double x0, double x1, double y0, double y1, const auto&) {
    // |grad sigma| of the cell's linear field (0 when constant), from its barycentric gradients.
    double field_gradient = 0.0;
    if (cell.linear) {
      const glm::dvec3 e1 = cell.v[1] - cell.v[0], e2 = cell.v[2] - cell.v[0], e3 = cell.v[3] - cell.v[0];
      const double det = glm::dot(e1, glm::cross(e2, e3));
      if (det != 0.0)
        field_gradient = glm::length(((cell.point_sigma[1] - cell.point_sigma[0]) * glm::cross(e2, e3) +
                                      (cell.point_sigma[2] - cell.point_sigma[0]) * glm::cross(e3, e1) +
                                      (cell.point_sigma[3] - cell.point_sigma[0]) * glm::cross(e1, e2)) / det);
    }
    const double sigma_max = cell.linear ? std::max({cell.point_sigma[0], cell.point_sigma[1], cell.point_sigma[2], cell.point_sigma[3]})
                                         : cell.sigma;
    for (double yd = y0; yd <= y1; yd += rows.step)
      for (double xd = x0; xd <= x1; ++xd) {
        // The first of the centre and the 8 points at `radius` around it where the ray meets
        // the cell: a drawn proxy can cover the pixel where the centre's ray just misses.
        static const int kAround[9][2] = {{0, 0}, {-1, -1}, {0, -1}, {1, -1}, {-1, 0}, {1, 0}, {-1, 1}, {0, 1}, {1, 1}};
        for (const auto& k : kAround) {
          const double px = xd + 0.5 + k[0] * radius, py = yd + 0.5 + k[1] * radius;
          const glm::dvec3 dir = ray_direction(camera, width, height, px, py);
          const double cos = glm::dot(dir, f.forward);
          const Interval in = ray_tetrahedron(cell.v, camera.eye, dir, camera.near_distance / cos, std::numeric_limits<double>::infinity());
          if (in.empty()) continue;
          const glm::dvec2 g = surface_depth_gradients(cell.v, camera, width, height, px, py, step);
          const double surface_change = g.x + g.y, length_per_depth = 1.0 / cos;
          const double footprint = footprint_per_depth * in.exit * cos;
          image[size_t(yd) * width + size_t(xd)] += sigma_max * surface_change * length_per_depth +
                                                    field_gradient * in.length() * (0.5 * surface_change * length_per_depth + footprint);
          break;
        }
      }
  });
  });
  return image;
}

}  // namespace prismoid::reference
