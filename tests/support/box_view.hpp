#pragma once
// The view the tests of time steps share: the box [-1,1]^3 seen from 5 units along +z, in a 9x9
// image whose centre pixel's ray is the z axis through the box (a chord of 2: a constant
// extinction sigma gives an optical depth of 2 sigma there).
#include <cstdint>
#include <string>

#include "scene/camera.hpp"

namespace prismoid::test {

inline constexpr uint32_t kBoxViewSide = 9;  // odd, so that one pixel's ray is the axis

inline Camera box_view() {
  Camera c;
  c.eye = {0.0, 0.0, 5.0};
  c.target = {0.0, 0.0, 0.0};
  c.up = {0.0, 1.0, 0.0};
  c.fovy_degrees = 40.0;
  c.near_distance = 0.5;
  return c;
}

// The same view as `render` options.
inline const std::string kBoxViewArgs = " --eye 0,0,5 --target 0,0,0 --up 0,1,0 --fovy 40 --near 0.5 --size 9x9";

// The centre pixel of an image of that size (row-major floats, one channel).
template <typename Pixels>
double box_view_centre(const Pixels& pixels) {
  return double(pixels[(kBoxViewSide / 2) * kBoxViewSide + kBoxViewSide / 2]);
}

}  // namespace prismoid::test
