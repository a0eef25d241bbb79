#include "renderer/surface/view_depth.hpp"

#include <limits>

#include "renderer/vk/depth_readback.hpp"

namespace prismoid::surface {

std::vector<float> view_axis_depth(const std::vector<float>& reversed_z, double near_distance) {
  std::vector<float> d(reversed_z.size());
  for (size_t i = 0; i < d.size(); ++i)
    d[i] = reversed_z[i] > 0.0f ? float(near_distance / double(reversed_z[i])) : std::numeric_limits<float>::infinity();
  return d;
}

std::vector<float> read_view_axis_depth(const vk::Device& device, const vk::Image& depth, double near_distance) {
  return view_axis_depth(vk::read_depth(device, depth), near_distance);
}

}  // namespace prismoid::surface
