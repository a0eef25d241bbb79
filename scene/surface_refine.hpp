#pragma once
// Large triangles split for a view (the meshlet shading atlas's paper subdivides its test scenes'
// large triangles "to provide optimal conditions" for block-based atlases: Neff et al. 2022,
// "Meshlets and How to Shade Them", the test scenes of its evaluation): a meshlet's block holds at
// most 256 texels a side, so a flat wall of two triangles, one meshlet, is undersampled wherever
// it spans more pixels than that; split into small triangles it becomes many meshlets, each
// fitting its block.
//
// A triangle is large when the part of it inside the view frustum of `camera` (an image of
// image_width x image_height pixels) spans more than `max_pixels` across or down the image. Each
// round splits every large triangle's longest edge at its midpoint (longest-edge bisection: the
// parts stay shapely), the midpoint shared by the triangles on both sides (no T-junctions); a
// triangle with 1, 2 or 3 split edges becomes 2, 3 or 4 with its winding; rounds repeat until no
// triangle is large. What the camera cannot see is never split. Each new vertex's shading normal
// is the normalized mean of its edge's two, its colour the mean; a triangle's colour passes to
// its parts. Positions are exact midpoints in double. Meshes whose material emits stay as they
// are: their triangles are the area lights every shading point samples, so splitting them would
// multiply the direct light's work (and their look is their constant emission).
#include <cstddef>
#include <cstdint>

#include "scene/camera.hpp"
#include "scene/surface_scene.hpp"

namespace prismoid {

struct RefineStats {
  size_t rounds = 0;
  size_t split_edges = 0;
  size_t triangles_before = 0, triangles_after = 0;
};

// InputError("--max-triangle-pixels", ...) for max_pixels not finite and positive, an empty
// image, or a result above `max_triangles` triangles (with the count it would need at least).
SurfaceScene refine_large_triangles(const SurfaceScene& scene, const Camera& camera, uint32_t image_width, uint32_t image_height,
                                    double max_pixels, RefineStats* stats = nullptr, size_t max_triangles = size_t(1) << 24);

}  // namespace prismoid
