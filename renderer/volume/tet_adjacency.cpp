// build_adjacency: faces matched by a counting sort on their smallest point index, then the
// boundary's convexity from its edges.
#include <algorithm>
#include <glm/geometric.hpp>
#include <limits>
#include <sstream>
#include <string>
#include <unordered_map>

#include "renderer/volume/orientation.hpp"
#include "renderer/volume/visibility_order.hpp"
#include "scene/disjoint_sets.hpp"
#include "scene/input_error.hpp"
#include "scene/tet_mesh.hpp"

namespace prismoid::volume {
namespace {

std::string source_of(const TetMesh& mesh) { return mesh.name.empty() ? std::string("(unnamed mesh)") : mesh.name; }

std::array<uint32_t, 3> sorted_face(const std::array<uint32_t, 4>& tet, int i) {
  std::array<uint32_t, 3> f = {tet[kFaceVertices[i][0]], tet[kFaceVertices[i][1]], tet[kFaceVertices[i][2]]};
  std::sort(f.begin(), f.end());
  return f;
}

// One cell's face, keyed by its two larger point indices inside the bucket of its smallest.
struct BucketedFace {
  uint32_t middle, largest, slot;  // slot = cell * 4 + local face
};

[[noreturn]] void throw_non_manifold(const TetMesh& mesh, const std::array<uint32_t, 3>& face,
                                     const BucketedFace* first, const BucketedFace* last) {
  std::ostringstream s;
  s << "the face with points";
  for (uint32_t p : face) {
    const glm::dvec3& x = mesh.points[p];
    s << " " << p << " (" << x.x << ", " << x.y << ", " << x.z << ")";
  }
  s << " is shared by " << (last - first) << " cells (";
  for (const BucketedFace* f = first; f != last; ++f) s << (f == first ? "" : ", ") << f->slot / 4;
  s << "); a tetrahedral mesh shares a face between at most two cells";
  throw InputError(source_of(mesh), s.str());
}

void check_cells(const TetMesh& mesh) {
  if (mesh.tets.size() > size_t(std::numeric_limits<int32_t>::max()) / 4)
    throw InputError(source_of(mesh), "has " + std::to_string(mesh.tets.size()) +
                                          " cells, more than the visibility order can index");
  for (size_t c = 0; c < mesh.tets.size(); ++c) {
    const auto& t = mesh.tets[c];
    for (int i = 0; i < 4; ++i)
      for (int j = i + 1; j < 4; ++j)
        if (t[i] == t[j])
          throw InputError(source_of(mesh), "cell " + std::to_string(c) + " uses point " + std::to_string(t[i]) + " twice");
  }
}

bool boundary_is_convex(const TetMesh& mesh, const std::vector<uint32_t>& boundary_slots) {
  if (boundary_slots.empty()) return false;
  const Bounds bounds = bounds_of(mesh);
  const double tolerance = 1e-6 * glm::length(bounds.max - bounds.min);  // see TetAdjacency
  // Boundary faces with their points ordered so that the normal points out of the mesh.
  std::vector<std::array<uint32_t, 3>> faces;
  faces.reserve(boundary_slots.size());
  for (uint32_t slot : boundary_slots) {
    const auto& tet = mesh.tets[slot / 4];
    const int side = orient3d_sign(mesh.points[tet[0]], mesh.points[tet[1]], mesh.points[tet[2]], mesh.points[tet[3]]);
    if (side == 0) return false;  // a flat cell has no outside
    const int* local = kFaceVertices[slot % 4];
    std::array<uint32_t, 3> f = {tet[local[0]], tet[local[1]], tet[local[2]]};
    if (side < 0) std::swap(f[1], f[2]);
    faces.push_back(f);
  }
  // Each directed edge u -> v of an outward face must appear once, and its reverse once, in
  // the face across that edge; anything else is an open or pinched boundary.
  std::unordered_map<uint64_t, uint32_t> face_of_edge;
  face_of_edge.reserve(3 * faces.size());
  auto key = [](uint32_t u, uint32_t v) { return (uint64_t(u) << 32) | v; };
  for (uint32_t f = 0; f < faces.size(); ++f)
    for (int e = 0; e < 3; ++e)
      if (!face_of_edge.emplace(key(faces[f][e], faces[f][(e + 1) % 3]), f).second) return false;
  DisjointSets pieces(faces.size());
  size_t piece_count = faces.size();
  for (uint32_t f = 0; f < faces.size(); ++f) {
    const glm::dvec3& p = mesh.points[faces[f][0]];
    const glm::dvec3 normal = glm::cross(mesh.points[faces[f][1]] - p, mesh.points[faces[f][2]] - p);
    const double area2 = glm::length(normal);
    if (!(area2 > 0.0)) return false;
    for (int e = 0; e < 3; ++e) {
      const uint32_t u = faces[f][e], v = faces[f][(e + 1) % 3];
      const auto twin = face_of_edge.find(key(v, u));
      if (twin == face_of_edge.end()) return false;
      const uint32_t g = twin->second;
      if (pieces.unite(f, g)) --piece_count;
      if (u > v) continue;  // each edge once
      const auto& other = faces[g];
      const uint32_t apex = other[0] != u && other[0] != v ? other[0] : (other[1] != u && other[1] != v ? other[1] : other[2]);
      // The neighbour's far point must not rise above this face's plane (on its outer side).
      if (glm::dot(normal, mesh.points[apex] - p) / area2 > tolerance) return false;
    }
  }
  return piece_count == 1;
}

}  // namespace

TetAdjacency build_adjacency(const TetMesh& mesh) {
  check_cells(mesh);
  const size_t cells = mesh.tets.size();
  // Counting sort of the 4 * cells faces by smallest point index; the buckets are small (the
  // faces around one point), so sorting inside them is cheap.
  std::vector<uint32_t> bucket_start(mesh.points.size() + 1, 0);
  for (const auto& tet : mesh.tets)
    for (int i = 0; i < 4; ++i) ++bucket_start[sorted_face(tet, i)[0] + 1];
  std::partial_sum(bucket_start.begin(), bucket_start.end(), bucket_start.begin());
  std::vector<BucketedFace> faces(4 * cells);
  {
    std::vector<uint32_t> cursor(bucket_start.begin(), bucket_start.end() - 1);
    for (size_t c = 0; c < cells; ++c)
      for (int i = 0; i < 4; ++i) {
        const auto f = sorted_face(mesh.tets[c], i);
        faces[cursor[f[0]]++] = {f[1], f[2], uint32_t(c * 4 + size_t(i))};
      }
  }
  TetAdjacency adjacency;
  adjacency.neighbour.assign(cells, {-1, -1, -1, -1});
  std::vector<uint32_t> boundary_slots;
  for (size_t point = 0; point + 1 < bucket_start.size(); ++point) {
    BucketedFace* const first = faces.data() + bucket_start[point];
    BucketedFace* const last = faces.data() + bucket_start[point + 1];
    std::sort(first, last, [](const BucketedFace& a, const BucketedFace& b) {
      return a.middle != b.middle ? a.middle < b.middle : a.largest < b.largest;
    });
    for (BucketedFace* run = first; run != last;) {
      BucketedFace* end = run + 1;
      while (end != last && end->middle == run->middle && end->largest == run->largest) ++end;
      if (end - run == 1) {
        boundary_slots.push_back(run->slot);
      } else if (end - run == 2) {
        adjacency.neighbour[run[0].slot / 4][run[0].slot % 4] = int32_t(run[1].slot / 4);
        adjacency.neighbour[run[1].slot / 4][run[1].slot % 4] = int32_t(run[0].slot / 4);
      } else {
        throw_non_manifold(mesh, {uint32_t(point), run->middle, run->largest}, run, end);
      }
      run = end;
    }
  }
  adjacency.boundary_faces = boundary_slots.size();
  adjacency.convex_boundary = boundary_is_convex(mesh, boundary_slots);
  return adjacency;
}

}  // namespace prismoid::volume
