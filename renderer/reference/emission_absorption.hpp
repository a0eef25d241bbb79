#pragma once
// CPU double-precision reference for emission-absorption with a transfer function: each pixel
// ray's segments in every cell, sorted along the ray (exact per-pixel order), each integrated
// exactly (volume::integrate_segment) and composited front to back.
#include <cstdint>
#include <vector>

#include <glm/vec4.hpp>

#include "renderer/volume/segment_integral.hpp"
#include "renderer/volume/transfer_function.hpp"
#include "scene/camera.hpp"
#include "scene/tet_mesh_fwd.hpp"

namespace prismoid::reference {

struct ColorImage {
  uint32_t width = 0, height = 0;
  std::vector<glm::dvec4> pixels;    // premultiplied (r, g, b) and alpha = 1 - transmittance
  std::vector<uint32_t> segments;    // per pixel: cells the ray crosses with positive length
  // When an InputPerturbation is given: per pixel, a bound on how much any channel can change
  // when every segment's inputs move by that much (each segment's change, by finite
  // differences, summed; what lies behind a segment is only ever attenuated).
  std::vector<double> sensitivity;
};

// How far a renderer's float inputs to a segment may stray, in the model of interval shading's
// float arithmetic (derived in tests/volume/interval_comparison.cpp): each end's depth relative
// to the cell's reference point by `relative` of the cell's depth extent Dz times its depth
// ratio d_max / d_min (and, for a cell the near plane cuts, of the plane's offset from the mesh
// centre plus the mesh's radius), plus `window` of (x + y + 1) pixels times that surface's
// screen gradient (a rasterizer's plane equations in window coordinates); the normalized scalar
// at each end by x_absolute, plus `relative` of the cell's spread of it times d_max / d_min,
// plus `window` of (x + y + 1) pixels times how fast it changes along that surface.
struct InputPerturbation {
  double x_absolute = 0.0;
  double relative = 0.0;
  double window = 0.0;
  double step = 0.0;  // finite differences for the surfaces' gradients, in pixels
};

// The scalar the transfer function reads is mesh.point_scalars (linear in each cell) when
// present, else mesh.cell_scalars (constant per cell); InputError(mesh.name) when neither is.
// With `table`, each segment is looked up in it (volume::lookup) instead of integrated
// exactly: the image the GPU should make with that table, in exact order and double precision.
// With `depth_limit` each ray ends there (trace_cells).
ColorImage emission_absorption_image(const TetMesh& mesh, const volume::TransferFunction& tf, const Camera& camera,
                                     uint32_t width, uint32_t height, double offset_x = 0.0, double offset_y = 0.0,
                                     const volume::PreintegrationTable* table = nullptr,
                                     const InputPerturbation* perturbation = nullptr,
                                     const std::vector<float>* depth_limit = nullptr);

// The longest edge over all cells: no segment inside a cell is longer (a convex polytope's
// diameter is attained at two of its vertices). It bounds the pre-integration table's length axis.
double longest_edge(const TetMesh& mesh);

}  // namespace prismoid::reference
