#pragma once
// A coarse stand-in for a tetrahedral dataset, drawn while the camera moves where the dataset
// itself is too slow to follow it (app/viewer/interactive_scale.hpp): the data's fields sampled
// at the points of an n^3-cube grid over its bounds (6 Kuhn tetrahedra per cube, as
// make_box_mesh), linear between them. A preview, not a measurement: it is never what a still
// camera, the bench or a comparison draws.
#include <cstdint>

#include "scene/tet_mesh_fwd.hpp"

namespace prismoid {

// Each grid point takes the fields of the cell that holds it (linear fields interpolated,
// per-cell fields that cell's value); its extinction and scalar are point values of the proxy
// (so the proxy is linear in each of its cells). Points outside every cell get extinction 0 and
// the scalar field's smallest value; cubes with no point inside the data are left out.
TetMesh coarse_proxy(const TetMesh& mesh, uint32_t n);

}  // namespace prismoid
