#pragma once
// Several datasets in one scene: the frame renderer draws one TetMesh, so the visible datasets
// are drawn as their union, one mesh whose cells are all of theirs. Sorting and the exact
// visibility order then work across datasets, as they must where volumes overlap.
#include <string>
#include <vector>

#include "scene/tet_mesh_fwd.hpp"

namespace prismoid::app {

// The meshes' points and cells concatenated (each mesh's point indices offset by the points
// before it), with their fields kept exactly:
// - extinction: per cell where every mesh has it per cell; once any mesh has it per point
//   (linear in each cell), the per-cell meshes get each cell its own four points carrying the
//   cell's value, so their extinction stays constant per cell;
// - scalars: only when every mesh has a scalar field (otherwise the union has none, and colour
//   is unavailable); per point once any mesh has them per point, cells' values moved to their own
//   points as above. The transfer function then maps every mesh's values through one range.
// The name joins the meshes' names with " + ".
TetMesh merge_meshes(const std::vector<const TetMesh*>& meshes);

}  // namespace prismoid::app
