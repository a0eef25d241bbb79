#include "renderer/reference/analytic_march.hpp"

#include <algorithm>
#include <cmath>
#include <glm/geometric.hpp>

#include "renderer/reference/row_threads.hpp"
#include "renderer/reference/tet_ray.hpp"
#include "shaders/shared/volume.h"

namespace prismoid::reference {

namespace {

struct Segment {
  double enter, exit;
};

// Per pixel, the ray's unit direction and its segments inside cells, sorted along the ray.
struct PixelSegments {
  std::vector<glm::dvec3> direction;
  std::vector<std::vector<Segment>> segments;
};

PixelSegments collect(const TetMesh& mesh, const Camera& camera, uint32_t width, uint32_t height, double offset_x,
                      double offset_y) {
  PixelSegments s;
  const size_t pixels = size_t(width) * height;
  s.direction.resize(pixels);
  s.segments.resize(pixels);
  for (uint32_t y = 0; y < height; ++y)
    for (uint32_t x = 0; x < width; ++x)
      s.direction[size_t(y) * width + x] = ray_direction(camera, width, height, x + 0.5 + offset_x, y + 0.5 + offset_y);
  trace_cells(mesh, camera, width, height, offset_x, offset_y, [](size_t) { return true; },
              [&](size_t pixel, size_t, const Interval& in, const glm::dvec3&) { s.segments[pixel].push_back({in.enter, in.exit}); });
  for_each_pixel_in_parallel(width, height, [&](size_t p) {
    std::sort(s.segments[p].begin(), s.segments[p].end(), [](const Segment& a, const Segment& b) { return a.enter < b.enter; });
  });
  return s;
}

// Equal steps of at most `step` over a segment of length `length`.
uint64_t steps_for(double length, double step) { return std::max<uint64_t>(1, uint64_t(std::ceil(length / step))); }

}  // namespace

std::vector<double> field_optical_depth_image(const TetMesh& mesh, const volume::AnalyticField& field, double density_scale,
                                              const Camera& camera, uint32_t width, uint32_t height, double panel,
                                              double offset_x, double offset_y) {
  // 4-point Gauss-Legendre nodes and weights on [-1, 1] (symmetric pairs).
  static const double kNodes[2] = {0.33998104358485626, 0.86113631159405258};
  static const double kWeights[2] = {0.65214515486254614, 0.34785484513745386};
  const PixelSegments s = collect(mesh, camera, width, height, offset_x, offset_y);
  std::vector<double> image(s.segments.size(), 0.0);
  for_each_pixel_in_parallel(width, height, [&](size_t p) {
    const glm::dvec3 dir = s.direction[p];
    auto sigma = [&](double t) { return density_scale * std::max(volume::evaluate(field, camera.eye + t * dir), 0.0); };
    for (const Segment& seg : s.segments[p]) {
      const uint64_t n = steps_for(seg.exit - seg.enter, panel);
      const double h = (seg.exit - seg.enter) / double(n);
      double sum = 0.0;
      for (uint64_t i = 0; i < n; ++i) {
        const double mid = seg.enter + (double(i) + 0.5) * h;
        for (int k = 0; k < 2; ++k)
          sum += kWeights[k] * (sigma(mid - 0.5 * h * kNodes[k]) + sigma(mid + 0.5 * h * kNodes[k]));
      }
      image[p] += 0.5 * h * sum;
    }
  });
  return image;
}

std::vector<double> field_march_optical_depth_image(const TetMesh& mesh, const volume::AnalyticField& field,
                                                    double density_scale, const Camera& camera, uint32_t width,
                                                    uint32_t height, double step, double offset_x, double offset_y) {
  const PixelSegments s = collect(mesh, camera, width, height, offset_x, offset_y);
  std::vector<double> image(s.segments.size(), 0.0);
  for_each_pixel_in_parallel(width, height, [&](size_t p) {
    for (const Segment& seg : s.segments[p]) {
      const uint64_t n = steps_for(seg.exit - seg.enter, step);
      const double h = (seg.exit - seg.enter) / double(n);
      double sum = 0.0;
      for (uint64_t i = 0; i < n; ++i)
        sum += std::max(volume::evaluate(field, camera.eye + (seg.enter + (double(i) + 0.5) * h) * s.direction[p]), 0.0);
      image[p] += density_scale * sum * h;
    }
  });
  return image;
}

IsosurfaceImage isosurface_image(const TetMesh& mesh, const volume::AnalyticField& field, double isovalue, const Camera& camera,
                                 uint32_t width, uint32_t height, double step) {
  const PixelSegments s = collect(mesh, camera, width, height, 0.0, 0.0);
  IsosurfaceImage image;
  image.width = width;
  image.height = height;
  image.distance.assign(s.segments.size(), 0.0);
  image.shade.assign(s.segments.size(), 0.0);
  for_each_pixel_in_parallel(width, height, [&](size_t p) {
    const glm::dvec3 dir = s.direction[p];
    auto inside = [&](double t) { return volume::evaluate(field, camera.eye + t * dir) >= isovalue; };
    double hit = 0.0;
    for (const Segment& seg : s.segments[p]) {
      if (inside(seg.enter)) { hit = seg.enter; break; }
      const uint64_t n = steps_for(seg.exit - seg.enter, step);
      double lo = seg.enter, hi = seg.enter;
      bool found = false;
      for (uint64_t i = 1; i <= n && !found; ++i) {
        lo = hi;
        hi = i == n ? seg.exit : seg.enter + double(i) * (seg.exit - seg.enter) / double(n);
        found = inside(hi);
      }
      if (!found) continue;
      for (int k = 0; k < 80; ++k) {
        const double mid = 0.5 * (lo + hi);
        if (mid <= lo || mid >= hi) break;
        (inside(mid) ? hi : lo) = mid;
      }
      hit = hi;
      break;
    }
    if (hit <= 0.0) return;
    image.distance[p] = hit;
    const glm::dvec3 g = volume::gradient(field, camera.eye + hit * dir);
    const double g_len = glm::length(g);
    const double lambert = g_len > 0.0 ? std::abs(glm::dot(g / g_len, dir)) : 1.0;
    image.shade[p] = PRISMOID_ISOSURFACE_AMBIENT + (1.0 - PRISMOID_ISOSURFACE_AMBIENT) * lambert;
  });
  return image;
}

ColorImage field_color_image(const TetMesh& mesh, const volume::AnalyticField& field, const volume::TransferFunction& tf,
                             const Camera& camera, uint32_t width, uint32_t height, double step, double offset_x,
                             double offset_y) {
  volume::validate(tf);
  const std::vector<volume::TfSample> samples = volume::breakpoints(tf);
  const PixelSegments s = collect(mesh, camera, width, height, offset_x, offset_y);
  ColorImage image;
  image.width = width;
  image.height = height;
  image.pixels.assign(s.segments.size(), glm::dvec4(0.0));
  image.segments.assign(s.segments.size(), 0u);
  for_each_pixel_in_parallel(width, height, [&](size_t p) {
    const glm::dvec3 dir = s.direction[p];
    glm::dvec4 total(0.0);
    for (const Segment& seg : s.segments[p]) {
      const uint64_t n = steps_for(seg.exit - seg.enter, step);
      const double h = (seg.exit - seg.enter) / double(n);
      for (uint64_t i = 0; i < n; ++i) {
        const double x = volume::normalized(tf, volume::evaluate(field, camera.eye + (seg.enter + (double(i) + 0.5) * h) * dir));
        const volume::TfSample c = volume::evaluate(samples, x);
        const double alpha = 1.0 - std::exp(-c.sigma * h);
        total += (1.0 - total.a) * glm::dvec4(c.rgb * alpha, alpha);
      }
    }
    image.pixels[p] = total;
    image.segments[p] = uint32_t(s.segments[p].size());
  });
  return image;
}

}  // namespace prismoid::reference
