#pragma once
// The plugin's VTK half of the boundary: what ParaView hands a volume mapper (the grid, the
// coloured array, the volume property, the camera) as Prismoid's plain data. Only ParaView's
// VTK is seen here; Prismoid's side is prismoid_session.hpp.
#include <string>

#include "renderer/volume/transfer_function.hpp"
#include "scene/camera.hpp"
#include "scene/tet_mesh.hpp"

class vtkCamera;
class vtkDataArray;
class vtkUnstructuredGridBase;
class vtkVolumeProperty;

namespace prismoid::paraview {

// The grid's tetrahedra and the scalar array (per point when `per_cell` is false): where it has
// several components, `component` of them (ParaView's "colour by X"), or their magnitude for
// component -1. Cells of lower dimension are left out (counted in
// `skipped`); a 3D cell that is not a tetrahedron, a missing array or non-finite values throw
// std::runtime_error with the reason (ParaView's volume representation tetrahedralizes its
// input before the mapper sees it, so a 3D non-tetrahedron means an unusual pipeline).
TetMesh tet_mesh_from(vtkUnstructuredGridBase* grid, vtkDataArray* scalars, bool per_cell, int component, std::size_t& skipped);

// Which component the volume property's colour function maps (its vector mode): -1 for the
// magnitude, else the component index (ParaView's ColorBy(rep, ("POINTS", "V", "X")) sets it).
int mapped_component(vtkVolumeProperty* property);

// The volume property's colour and scalar opacity functions (component 0) as a transfer
// function over the union of their ranges. VTK's unstructured-grid mappers read the opacity
// function's value divided by the scalar opacity unit distance as the extinction coefficient
// itself; so does this (density_scale = 1 / unit distance). Colours are used as the values VTK
// gives them, as VTK's own mappers do. Functions with non-linear segments (midpoint or
// sharpness other than 0.5 / 0, or a colour space other than RGB) are sampled at 256 points
// between their nodes: piecewise linear, as the renderer's model is.
volume::TransferFunction transfer_function_from(vtkVolumeProperty* property);

// The largest opacity `tf` gives any scalar in [lo, hi] (its opacity is piecewise linear in the
// normalized x: the values at both ends and at every node between). 0: nothing in that range
// can be seen.
double largest_opacity(const volume::TransferFunction& tf, double lo, double hi);

// VTK's perspective camera as Prismoid's (eye, focal point, view up, vertical view angle, the
// near clipping distance). Throws std::runtime_error for a parallel projection.
Camera camera_from(vtkCamera* camera);

}  // namespace prismoid::paraview
