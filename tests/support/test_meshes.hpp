#pragma once
// Small surfaces for tests that scene/generators does not make.
#include <cmath>
#include <cstdint>
#include <string>

#include "scene/surface_mesh.hpp"

namespace prismoid::test {

// An open disk of radius 1 in the plane z = bulge (x^2 + y^2) (bulge 0: flat): a centre point
// and `rings` rings of 6 i points at radius i / rings, neighbouring rings zipped into
// triangles by angle (6 rings^2 triangles), all wound counter-clockwise seen from +z.
inline SurfaceMesh make_disk(uint32_t rings, double bulge = 0.0) {
  SurfaceMesh disk;
  disk.name = "disk (" + std::to_string(rings) + " rings)";
  const double two_pi = 6.283185307179586;
  auto add = [&](double r, double angle) {
    disk.points.push_back({r * std::cos(angle), r * std::sin(angle), bulge * r * r});
    return static_cast<uint32_t>(disk.points.size() - 1);
  };
  std::vector<uint32_t> inner = {add(0.0, 0.0)};
  for (uint32_t i = 1; i <= rings; ++i) {
    std::vector<uint32_t> outer;
    const uint32_t n = 6 * i;
    for (uint32_t j = 0; j < n; ++j) outer.push_back(add(double(i) / rings, two_pi * j / n));
    if (inner.size() == 1) {
      for (uint32_t j = 0; j < n; ++j) disk.triangles.push_back({inner[0], outer[j], outer[(j + 1) % n]});
    } else {
      const auto na = static_cast<uint32_t>(inner.size());
      uint32_t a = 0, b = 0;
      while (a < na || b < n) {
        // Advance on the ring whose next point comes first by angle (fractions of a turn).
        const bool step_outer = a == na || (b < n && double(b + 1) / n <= double(a + 1) / na);
        if (step_outer) {
          disk.triangles.push_back({inner[a % na], outer[b % n], outer[(b + 1) % n]});
          ++b;
        } else {
          disk.triangles.push_back({inner[a % na], outer[b % n], inner[(a + 1) % na]});
          ++a;
        }
      }
    }
    inner = std::move(outer);
  }
  return disk;
}

}  // namespace prismoid::test
