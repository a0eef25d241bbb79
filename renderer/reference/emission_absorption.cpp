#include "renderer/reference/emission_absorption.hpp"

#include <algorithm>
#include <array>
#include <glm/geometric.hpp>

#include "renderer/reference/tet_ray.hpp"
#include "renderer/volume/segment_integral.hpp"
#include "scene/input_error.hpp"

namespace prismoid::reference {

namespace {

struct Segment {
  double enter, exit;
  double x_front, x_back;  // normalized scalar at both ends
};

}  // namespace

ColorImage emission_absorption_image(const TetMesh& mesh, const volume::TransferFunction& tf, const Camera& camera,
                                     uint32_t width, uint32_t height, double offset_x, double offset_y,
                                     const volume::PreintegrationTable* table) {
  const bool linear = !mesh.point_scalars.empty();
  if (!linear && mesh.cell_scalars.empty())
    throw InputError(mesh.name, "has no scalar field for the transfer function (choose one with --array NAME)");
  volume::validate(tf);
  const std::vector<volume::TfSample> samples = volume::breakpoints(tf);
  const size_t pixels = size_t(width) * height;
  std::vector<std::vector<Segment>> along(pixels);
  trace_cells(mesh, camera, width, height, offset_x, offset_y, [](size_t) { return true; },
              [&](size_t pixel, size_t c, const Interval& in, const glm::dvec3& dir) {
                Segment s{in.enter, in.exit, 0.0, 0.0};
                if (linear) {
                  std::array<glm::dvec3, 4> v;
                  std::array<double, 4> values;
                  for (int i = 0; i < 4; ++i) {
                    v[i] = mesh.points[mesh.tets[c][i]];
                    values[i] = mesh.point_scalars[mesh.tets[c][i]];
                  }
                  s.x_front = volume::normalized(tf, interpolate_linear(v, values, camera.eye + in.enter * dir));
                  s.x_back = volume::normalized(tf, interpolate_linear(v, values, camera.eye + in.exit * dir));
                } else {
                  s.x_front = s.x_back = volume::normalized(tf, mesh.cell_scalars[c]);
                }
                along[pixel].push_back(s);
              });
  ColorImage image;
  image.width = width;
  image.height = height;
  image.pixels.assign(pixels, glm::dvec4(0.0));
  image.segments.assign(pixels, 0u);
  for (size_t p = 0; p < pixels; ++p) {
    auto& segs = along[p];
    std::sort(segs.begin(), segs.end(), [](const Segment& a, const Segment& b) { return a.enter < b.enter; });
    volume::SegmentRadiance sum;
    for (const Segment& s : segs)
      sum = volume::composite(sum, table ? volume::lookup(*table, s.x_front, s.x_back, s.exit - s.enter)
                                         : volume::integrate_segment(samples, s.x_front, s.x_back, s.exit - s.enter));
    image.pixels[p] = glm::dvec4(sum.color, sum.alpha);
    image.segments[p] = static_cast<uint32_t>(segs.size());
  }
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
