#pragma once
// CPU double-precision references for marching inside intervals: an analytic field (world
// coordinates) along each pixel ray, over the ray's segments inside the mesh beyond the near
// plane, integrated or searched far more finely than the GPU's step.
#include <cstdint>
#include <vector>

#include "renderer/reference/emission_absorption.hpp"
#include "renderer/volume/analytic_field.hpp"
#include "renderer/volume/transfer_function.hpp"
#include "scene/camera.hpp"
#include "scene/tet_mesh_fwd.hpp"

namespace prismoid::reference {

// Optical depth of sigma = density_scale * max(field, 0) per pixel, by composite 4-point
// Gauss-Legendre on panels of at most `panel` world units in each cell's segment (error of
// order panel^8 times the field's 8th derivative: below 1e-12 for the CLI's fields at the
// default). Row-major, row 0 at the top; rays through pixel centres moved by the offsets.
std::vector<double> field_optical_depth_image(const TetMesh& mesh, const volume::AnalyticField& field, double density_scale,
                                              const Camera& camera, uint32_t width, uint32_t height, double panel = 0.005,
                                              double offset_x = 0.0, double offset_y = 0.0);

// The GPU's march itself in double: per cell segment, ceil(length / step) equal steps, each
// adding density_scale * max(field, 0) at its midpoint times its length. For fields without a
// second-derivative bound (a sampled grid's gradient jumps at voxel faces), comparing with the
// GPU at the same step isolates the sampling from the step error.
std::vector<double> field_march_optical_depth_image(const TetMesh& mesh, const volume::AnalyticField& field,
                                                    double density_scale, const Camera& camera, uint32_t width,
                                                    uint32_t height, double step, double offset_x = 0.0,
                                                    double offset_y = 0.0);

// The first point along each pixel ray inside the mesh where field >= isovalue: marched in
// steps of at most `step`, bisected to double precision inside the first step that reaches it
// (a segment starting at or above the isovalue hits at its start). A crossing pair closer
// together than `step` can be missed (rays grazing the surface).
struct IsosurfaceImage {
  uint32_t width = 0, height = 0;
  std::vector<double> distance;  // from the eye to the hit; 0 where the ray has none
  std::vector<double> shade;     // ambient + (1 - ambient) |cos(normal, ray)|, as the GPU shades it
};
IsosurfaceImage isosurface_image(const TetMesh& mesh, const volume::AnalyticField& field, double isovalue, const Camera& camera,
                                 uint32_t width, uint32_t height, double step = 1e-3);

// Emission-absorption of the transfer function of the field, composited front to back along
// each ray, with the field sampled at the midpoints of steps of at most `step` (constant colour
// and extinction per step, integrated exactly): the GPU's march with a much finer step. Rays
// through pixel centres moved by the offsets.
ColorImage field_color_image(const TetMesh& mesh, const volume::AnalyticField& field, const volume::TransferFunction& tf,
                             const Camera& camera, uint32_t width, uint32_t height, double step = 1e-3, double offset_x = 0.0,
                             double offset_y = 0.0);

}  // namespace prismoid::reference
