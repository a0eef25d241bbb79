#pragma once
// CPU double-precision reference for volume rendering: exact ray/tetrahedron intervals by
// plane tests, summed over cells. Every GPU volume mode is tested against these.
#include <array>
#include <cstdint>
#include <functional>
#include <vector>

#include <glm/vec2.hpp>
#include <glm/vec3.hpp>

#include "scene/camera.hpp"
#include "scene/tet_mesh_fwd.hpp"

namespace prismoid::reference {

struct Interval {
  double enter = 0.0;
  double exit = 0.0;
  bool empty() const { return !(exit > enter); }
  double length() const { return empty() ? 0.0 : exit - enter; }
};

// Parameter interval of origin + t * direction inside the tetrahedron, intersected with
// [t_min, t_max]. Exact up to rounding: each face plane clips the interval once.
Interval ray_tetrahedron(const std::array<glm::dvec3, 4>& v, const glm::dvec3& origin, const glm::dvec3& direction,
                         double t_min, double t_max);

// The ray through the image point (px, py) of a width x height image, in continuous pixel
// coordinates (pixel (x, y) has its centre at (x + 0.5, y + 0.5); row 0 at the top), as
// the renderer defines it: unit direction from the eye.
glm::dvec3 ray_direction(const Camera& camera, uint32_t width, uint32_t height, double px, double py);

// sigma at p inside the tetrahedron v with values s at its vertices, by barycentric
// interpolation (signed volumes, double precision). Zero-volume cells give the mean.
double interpolate_linear(const std::array<glm::dvec3, 4>& v, const std::array<double, 4>& s, const glm::dvec3& p);

// Calls `visit` for every pixel ray (through the pixel centre moved by the offsets) and every
// cell with `wanted(cell)` that the ray crosses with a positive length beyond the near plane,
// with the ray's unit direction and parameter interval inside the cell. Row-major pixel
// index, row 0 at the top. Cells are visited in mesh order, not along the ray. Rows are spread
// over threads (row_threads.hpp): `wanted` may be called concurrently, and `visit` concurrently
// for different rows, never for one pixel from two threads, so it may write the pixel's own
// state without locks.
using CellVisitor = std::function<void(size_t pixel, size_t cell, const Interval& interval, const glm::dvec3& direction)>;
// With `depth_limit` (one depth along the viewing axis per pixel, row-major, row 0 at the top;
// +inf: none), each ray ends there: opaque geometry in front of or inside the volume.
void trace_cells(const TetMesh& mesh, const Camera& camera, uint32_t width, uint32_t height, double offset_x, double offset_y,
                 const std::function<bool(size_t cell)>& wanted, const CellVisitor& visit,
                 const std::vector<float>* depth_limit = nullptr);

// Optical depth per pixel: sum over cells of the integral of sigma along the pixel ray inside
// the cell (sigma constant per cell, or linear when the mesh has point extinction: then the
// integral is the length times the mean of sigma at the entry and exit points),
// counting only the part beyond the near plane. Row-major, row 0 at the top. Each pixel's
// ray passes through its centre moved by (offset_x, offset_y) pixels. When `cells_hit` is
// given it receives, per pixel, how many cells the ray crosses with a positive length.
// `depth_limit` as for trace_cells.
std::vector<double> optical_depth_image(const TetMesh& mesh, const Camera& camera, uint32_t width, uint32_t height,
                                        double offset_x = 0.0, double offset_y = 0.0,
                                        std::vector<uint32_t>* cells_hit = nullptr,
                                        const std::vector<float>* depth_limit = nullptr);

// Per pixel, the sum over cells of the largest change of the cell's optical depth when the
// pixel's ray moves to one of the 8 points at `radius` pixels (per axis) around its centre, or
// next to one of the cell's vertices that project within `radius` of the centre (its limits
// from each side, sampled 2^-20 pixel around it). A rasterizer that moves each cell's proxy
// vertices independently by up to `radius` stays within this of the exact image.
std::vector<double> snapping_variation_image(const TetMesh& mesh, const Camera& camera, uint32_t width, uint32_t height,
                                             double radius);

// Per pixel of displacement of the image point (px, py), how fast the depths along the viewing
// axis of the entry (x) and exit (y) surfaces of its ray in the tetrahedron v change (finite
// differences at `step` pixels, forward or backward, whichever stays in the cell; the near
// plane, where it cuts, has constant depth). Zero where the ray misses.
glm::dvec2 surface_depth_gradients(const std::array<glm::dvec3, 4>& v, const Camera& camera, uint32_t width, uint32_t height,
                                   double px, double py, double step);

// Per pixel, the sum over cells of how fast the cell's optical depth changes per pixel of
// displacement of one of its two bounding surfaces alone: sigma_max * (|grad d_entry| +
// |grad d_exit|) * (ray length per unit depth), with d the surfaces' depths along the viewing
// axis as functions of the image point (finite differences), plus the field's change with them
// (|grad sigma| times the segment's length times how far the surface points move). Cells whose
// ray misses at the pixel centre count where one of the 8 points at `radius` around it hits. A
// rasterizer that interpolates each surface's attributes as if at a point displaced by up to
// e pixels (rounding of plane equations evaluated far from the vertices) errs by at most e
// times this.
std::vector<double> surface_sensitivity_image(const TetMesh& mesh, const Camera& camera, uint32_t width, uint32_t height,
                                              double radius);

}  // namespace prismoid::reference
