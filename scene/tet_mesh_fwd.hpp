#pragma once
// The tetrahedral mesh by name only, for headers that pass it by reference or declare functions
// returning it. scene/tet_mesh.hpp is included by about a hundred objects that use the type; the
// headers that only name it include this instead, so a change to the mesh rebuilds only those.
namespace prismoid {

struct TetMesh;

}  // namespace prismoid
