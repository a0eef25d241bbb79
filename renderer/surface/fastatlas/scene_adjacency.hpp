#pragma once
// What FastAtlas needs of a scene's connectivity, built once at load: one halfedge mesh over all
// of the scene's meshes in the GPU's global triangle order, with each mesh's vertices welded by
// position (a mesh split at its normal or colour seams would otherwise have chart boundaries
// there, visible in the image), and per triangle its edge neighbours, which of them meet it at
// under the hard-edge filter's angle, and its welded vertices. Meshes are not welded to each
// other: they are charted apart where they only touch.
#include <array>
#include <cstdint>
#include <vector>

#include "scene/halfedge_mesh.hpp"
#include "scene/surface_scene.hpp"

namespace prismoid::fastatlas {

inline constexpr uint32_t kNoTriangle = 0xFFFFFFFFu;

struct SceneAdjacency {
  HalfedgeMesh mesh;  // face f is global triangle mesh.triangle_of_face[f]
  std::vector<std::array<uint32_t, 3>> neighbours;  // per global triangle: across edge k (corner k to k + 1), or kNoTriangle
  std::vector<uint8_t> smooth;                       // per global triangle: bit k when neighbour k turns by less than the angle
  std::vector<std::array<uint32_t, 3>> vertices;     // per global triangle: its welded vertices
};

// `max_degrees`: the hard-edge filter's threshold (75 in the paper).
SceneAdjacency scene_adjacency(const SurfaceScene& scene, double max_degrees = 75.0);

// Per global triangle of `adjacency`, the visibility flags of its halfedge mesh's faces.
std::vector<uint8_t> face_visibility(const SceneAdjacency& adjacency, const std::vector<uint8_t>& triangle_visible);

}  // namespace prismoid::fastatlas
