#pragma once
// Edits of a transfer function's opacity points, as the editor's plot makes them: each keeps
// the points sorted by x, inside [0, 1], and at least one point in the list.
#include <cstddef>

#include "renderer/volume/transfer_function.hpp"

namespace prismoid::app {

// Inserts a point where it sorts; returns its index.
size_t add_opacity_point(volume::TransferFunction& tf, double x, double opacity);
// Removes point i unless it is the last one left; returns whether it did.
bool remove_opacity_point(volume::TransferFunction& tf, size_t i);
// Moves point i to (x, opacity), x kept between its neighbours so the order never changes.
void move_opacity_point(volume::TransferFunction& tf, size_t i, double x, double opacity);
// The index of the point nearest to (x, opacity) within `radius` (plot units), or tf.opacity.size().
size_t nearest_opacity_point(const volume::TransferFunction& tf, double x, double opacity, double radius);

}  // namespace prismoid::app
