#pragma once
// The depth along the viewing axis of the nearest opaque surface per pixel, from a surface
// backend's reversed-z depth buffer (every backend draws one: the forward passes' and the
// texture-space backends' pre-pass): what a volume's rays end at (volume::ResolveSettings::depth_limit).
#include <vector>

#include "renderer/vk/device.hpp"
#include "renderer/vk/memory.hpp"

namespace prismoid::surface {

// A reversed-z depth with an infinite far plane holds z = near / d (scene/camera.cpp,
// projection_matrix), d the distance along the viewing axis; 0 where nothing was drawn. Each
// value back to d = near / z in double (+inf for 0): float's z is exact to 2^-24 relative, so d is.
std::vector<float> view_axis_depth(const std::vector<float>& reversed_z, double near_distance);

// The depth attachment of a surface backend (D32, in DEPTH_ATTACHMENT_OPTIMAL after its record),
// read back and turned into depths along the viewing axis.
std::vector<float> read_view_axis_depth(const vk::Device& device, const vk::Image& depth, double near_distance);

}  // namespace prismoid::surface
