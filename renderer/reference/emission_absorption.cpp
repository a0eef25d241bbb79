#include "renderer/reference/emission_absorption.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <glm/geometric.hpp>
#include <glm/trigonometric.hpp>

#include "renderer/reference/row_threads.hpp"
#include "renderer/reference/tet_ray.hpp"
#include "renderer/volume/segment_integral.hpp"
#include "scene/input_error.hpp"
#include "scene/setting_names.hpp"
#include "scene/tet_mesh.hpp"

namespace prismoid::reference {

namespace {

struct Segment {
  double enter, exit;
  double x_front, x_back;  // normalized scalar at both ends
  double x_slack = 0.0;    // how far the renderer's x may stray at either end
  double length_slack = 0.0;
};

// sqrt of the sum of squares of the gradient of the linear interpolant of `values` over v.
double gradient_length(const std::array<glm::dvec3, 4>& v, const std::array<double, 4>& values) {
  const glm::dvec3 e1 = v[1] - v[0], e2 = v[2] - v[0], e3 = v[3] - v[0];
  const double det = glm::dot(e1, glm::cross(e2, e3));
  if (det == 0.0) return 0.0;
  const glm::dvec3 g = ((values[1] - values[0]) * glm::cross(e2, e3) + (values[2] - values[0]) * glm::cross(e3, e1) +
                        (values[3] - values[0]) * glm::cross(e1, e2)) / det;
  return glm::length(g);
}

}  // namespace

ColorImage emission_absorption_image(const TetMesh& mesh, const volume::TransferFunction& tf, const Camera& camera,
                                     uint32_t width, uint32_t height, double offset_x, double offset_y,
                                     const volume::PreintegrationTable* table, const InputPerturbation* perturbation,
                                     const std::vector<float>* depth_limit) {
  const bool linear = !mesh.point_scalars.empty();
  if (!linear && mesh.cell_scalars.empty())
    throw InputError(mesh.name, "has no scalar field for the transfer function (choose one with " + setting("array", "NAME") + ")");
  volume::validate(tf);
  const std::vector<volume::TfSample> samples = volume::breakpoints(tf);
  const size_t pixels = size_t(width) * height;
  std::vector<std::vector<Segment>> along(pixels);
  const glm::dvec3 forward = glm::normalize(camera.target - camera.eye);
  const glm::dvec3 origin = bounds_of(mesh).center();
  double mesh_radius = 0.0;
  if (perturbation)
    for (const auto& p : mesh.points) mesh_radius = std::max(mesh_radius, glm::length(p - origin));
  const double near_from_origin = std::abs(camera.near_distance - glm::dot(origin - camera.eye, forward));
  const double footprint_per_depth = 2.0 * std::tan(glm::radians(camera.fovy_degrees) * 0.5) / height;
  trace_cells(mesh, camera, width, height, offset_x, offset_y, [](size_t) { return true; },
              [&](size_t pixel, size_t c, const Interval& in, const glm::dvec3& dir) {
                Segment s{in.enter, in.exit, 0.0, 0.0};
                std::array<glm::dvec3, 4> v;
                std::array<double, 4> x{};
                for (int i = 0; i < 4; ++i) {
                  v[i] = mesh.points[mesh.tets[c][i]];
                  x[i] = volume::normalized(tf, linear ? mesh.point_scalars[mesh.tets[c][i]] : mesh.cell_scalars[c]);
                }
                if (linear) {
                  std::array<double, 4> values;
                  for (int i = 0; i < 4; ++i) values[i] = mesh.point_scalars[mesh.tets[c][i]];
                  s.x_front = volume::normalized(tf, interpolate_linear(v, values, camera.eye + in.enter * dir));
                  s.x_back = volume::normalized(tf, interpolate_linear(v, values, camera.eye + in.exit * dir));
                } else {
                  s.x_front = s.x_back = x[0];
                }
                if (perturbation) {
                  double d_lo = 1e300, d_hi = -1e300;
                  for (const auto& p : v) {
                    d_lo = std::min(d_lo, glm::dot(p - camera.eye, forward));
                    d_hi = std::max(d_hi, glm::dot(p - camera.eye, forward));
                  }
                  const double ratio = d_hi / std::max(d_lo, camera.near_distance);
                  const double length_per_depth = 1.0 / glm::dot(dir, forward);
                  const double px = double(pixel % width) + 0.5 + offset_x, py = double(pixel / width) + 0.5 + offset_y;
                  const glm::dvec2 g = surface_depth_gradients(v, camera, width, height, px, py, perturbation->step);
                  const double window = perturbation->window * (double(pixel % width) + double(pixel / width) + 1.0);
                  s.length_slack = (perturbation->relative * 2.0 * (d_hi - d_lo) * ratio + window * (g.x + g.y)) * length_per_depth;
                  if (d_lo < camera.near_distance)
                    s.length_slack = 3.0 * (s.length_slack + perturbation->relative * 2.0 * (near_from_origin + mesh_radius) * length_per_depth);
                  const double x_spread = *std::max_element(x.begin(), x.end()) - *std::min_element(x.begin(), x.end());
                  const double x_gradient = linear ? gradient_length(v, x) : 0.0;
                  s.x_slack = perturbation->x_absolute + perturbation->relative * ratio * x_spread +
                              window * x_gradient * (0.5 * (g.x + g.y) * length_per_depth + footprint_per_depth * in.exit);
                }
                along[pixel].push_back(s);
              }, depth_limit);
  ColorImage image;
  image.width = width;
  image.height = height;
  image.pixels.assign(pixels, glm::dvec4(0.0));
  image.segments.assign(pixels, 0u);
  if (perturbation) image.sensitivity.assign(pixels, 0.0);
  auto segment = [&](double xf, double xb, double length) {
    return table ? volume::lookup(*table, xf, xb, length) : volume::integrate_segment(samples, xf, xb, length);
  };
  auto largest_change = [](const volume::SegmentRadiance& a, const volume::SegmentRadiance& b) {
    return std::max({std::abs(a.color.r - b.color.r), std::abs(a.color.g - b.color.g), std::abs(a.color.b - b.color.b),
                     std::abs(a.alpha - b.alpha)});
  };
  for_each_pixel_in_parallel(width, height, [&](size_t p) {
    auto& segs = along[p];
    std::sort(segs.begin(), segs.end(), [](const Segment& a, const Segment& b) { return a.enter < b.enter; });
    volume::SegmentRadiance sum;
    for (const Segment& s : segs) {
      const double length = s.exit - s.enter;
      const volume::SegmentRadiance r = segment(s.x_front, s.x_back, length);
      sum = volume::composite(sum, r);
      if (perturbation) {
        // Each input moved both ways by its slack; the changes add (first order).
        double change = 0.0;
        for (double sign : {-1.0, 1.0}) {
          change = std::max(change, largest_change(r, segment(s.x_front + sign * s.x_slack, s.x_back, length)) +
                                        largest_change(r, segment(s.x_front, s.x_back + sign * s.x_slack, length)) +
                                        largest_change(r, segment(s.x_front, s.x_back, std::max(length + sign * s.length_slack, 0.0))));
        }
        image.sensitivity[p] += change;
      }
    }
    image.pixels[p] = glm::dvec4(sum.color, sum.alpha);
    image.segments[p] = static_cast<uint32_t>(segs.size());
  });
  return image;
}

double longest_edge(const TetMesh& mesh) {
  double longest = 0.0;
  for (const auto& t : mesh.tets)
    for (int i = 0; i < 4; ++i)
      for (int j = i + 1; j < 4; ++j) longest = std::max(longest, glm::distance(mesh.points[t[i]], mesh.points[t[j]]));
  return longest;
}

}  // namespace prismoid::reference
