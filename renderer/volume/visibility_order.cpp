// exact_order: Kahn's topological sort of the 'in front of' relation over shared faces,
// nearest centroid first, with strongly connected sets placed as blocks when it has cycles.
#include "renderer/volume/visibility_order.hpp"

#include <algorithm>
#include <bit>
#include <functional>
#include <glm/geometric.hpp>
#include <stdexcept>
#include <string>
#include <utility>

#include "renderer/volume/orientation.hpp"
#include "scene/tet_mesh.hpp"

namespace prismoid::volume {
namespace {

constexpr uint32_t kNone = ~0u;

// The relation as each cell's outgoing faces, and each cell's count of unplaced predecessors.
struct FrontRelation {
  std::vector<uint8_t> successor_faces;  // bit i: the cell is in front of its neighbour across face i
  std::vector<uint32_t> pending;         // predecessors not yet placed
  std::vector<double> distance2;         // squared distance from the eye to the centroid
};

FrontRelation front_relation(const TetMesh& mesh, const TetAdjacency& adjacency, const glm::dvec3& eye) {
  const size_t cells = mesh.tets.size();
  FrontRelation r{std::vector<uint8_t>(cells, 0), std::vector<uint32_t>(cells, 0), std::vector<double>(cells)};
  for (size_t c = 0; c < cells; ++c) {
    const auto& tet = mesh.tets[c];
    const std::array<glm::dvec3, 4> v = {mesh.points[tet[0]], mesh.points[tet[1]], mesh.points[tet[2]], mesh.points[tet[3]]};
    const glm::dvec3 to_centroid = 0.25 * (v[0] + v[1] + v[2] + v[3]) - eye;
    r.distance2[c] = glm::dot(to_centroid, to_centroid);
    const int side = orient3d_sign(v[0], v[1], v[2], v[3]);
    if (side == 0) continue;
    for (int i = 0; i < 4; ++i) {
      const int32_t across = adjacency.neighbour[c][i];
      if (across < 0) continue;
      const int* f = kFaceVertices[i];
      // The face's normal points away from vertex i when side > 0 (see kFaceVertices), so the eye
      // is on this cell's side exactly when its orientation against the face is -side. Both cells
      // of a face evaluate the same exact predicate, so they never both claim to be in front.
      if (orient3d_sign(v[f[0]], v[f[1]], v[f[2]], eye) == -side) {
        r.successor_faces[c] = uint8_t(r.successor_faces[c] | (1u << i));
        ++r.pending[size_t(across)];
      }
    }
  }
  return r;
}

template <class F>
void for_each_successor(const FrontRelation& r, const TetAdjacency& adjacency, uint32_t c, F&& visit) {
  for (int i = 0; i < 4; ++i)
    if (r.successor_faces[c] & (1u << i)) visit(uint32_t(adjacency.neighbour[c][i]));
}

// Strongly connected sets of the relation among the unplaced cells (Tarjan's algorithm, with an
// explicit stack). Edges from unplaced cells only reach unplaced cells: a placed cell had no
// unplaced predecessor. Returns each cell's set id (kNone for placed cells) and the set count.
std::pair<std::vector<uint32_t>, uint32_t> strongly_connected_sets(const FrontRelation& r, const TetAdjacency& adjacency,
                                                                   const std::vector<bool>& placed) {
  const size_t cells = placed.size();
  std::vector<uint32_t> set_of(cells, kNone), index(cells, kNone), low(cells, 0);
  std::vector<bool> on_stack(cells, false);
  std::vector<uint32_t> stack;
  std::vector<std::pair<uint32_t, int>> calls;  // cell, next local face to look at
  uint32_t next_index = 0, sets = 0;
  for (uint32_t root = 0; root < cells; ++root) {
    if (placed[root] || index[root] != kNone) continue;
    calls.push_back({root, 0});
    index[root] = low[root] = next_index++;
    stack.push_back(root);
    on_stack[root] = true;
    while (!calls.empty()) {
      auto& [c, face] = calls.back();
      if (face < 4) {
        const int i = face++;
        if (!(r.successor_faces[c] & (1u << i))) continue;
        const auto d = uint32_t(adjacency.neighbour[c][i]);
        if (index[d] == kNone) {
          index[d] = low[d] = next_index++;
          stack.push_back(d);
          on_stack[d] = true;
          calls.push_back({d, 0});
        } else if (on_stack[d]) {
          low[c] = std::min(low[c], index[d]);
        }
        continue;
      }
      const uint32_t done = c;
      calls.pop_back();
      if (!calls.empty()) low[calls.back().first] = std::min(low[calls.back().first], low[done]);
      if (low[done] == index[done]) {
        uint32_t member;
        do {
          member = stack.back();
          stack.pop_back();
          on_stack[member] = false;
          set_of[member] = sets;
        } while (member != done);
        ++sets;
      }
    }
  }
  return {set_of, sets};
}

// Kahn's algorithm with a min-heap on centroid distance; after a cycle is found, sets of cells
// in cycles wait in a second heap (keyed by their nearest member) until nothing outside them
// leads into them.
class Sorter {
 public:
  Sorter(const TetAdjacency& adjacency, FrontRelation relation)
      : adjacency_(adjacency), r_(std::move(relation)), placed_(r_.pending.size(), false) {}

  VisibilityOrder run() {
    const size_t cells = placed_.size();
    VisibilityOrder out;
    out.front_to_back.reserve(cells);
    order_ = &out.front_to_back;
    for (uint32_t c = 0; c < cells; ++c)
      if (r_.pending[c] == 0) push(ready_cells_, r_.distance2[c], c);
    while (order_->size() < cells) {
      if (ready_cells_.empty() && ready_sets_.empty()) {
        // After the sets are known a source set is always ready, so this happens once.
        if (!set_of_.empty()) throw std::logic_error("exact_order: no cell ready after grouping the cycles");
        find_cycles();
        out.acyclic = false;
        out.cells_in_cycles = cells_in_cycles_;
        continue;
      }
      const bool take_set = ready_cells_.empty() || (!ready_sets_.empty() && ready_sets_.front() < ready_cells_.front());
      if (take_set) place_set(pop(ready_sets_));
      else place(pop(ready_cells_));
    }
    return out;
  }

 private:
  // A heap entry packs the distance's upper 32 bits (sign, exponent and 20 mantissa bits: a
  // non-negative double's bits order as the double does) above the cell or set index, so the
  // heap compares single integers. Distances within a relative 2^-20 count as ties, broken by
  // index, which keeps the order deterministic; the priority only steers the choice among cells
  // the relation leaves free, so that precision costs nothing.
  using Entry = uint64_t;
  static void push(std::vector<Entry>& heap, double distance2, uint32_t id) {
    heap.push_back((std::bit_cast<uint64_t>(distance2) & ~uint64_t(0xffffffff)) | id);
    std::push_heap(heap.begin(), heap.end(), std::greater<>());
  }
  static uint32_t pop(std::vector<Entry>& heap) {
    std::pop_heap(heap.begin(), heap.end(), std::greater<>());
    const auto id = uint32_t(heap.back());
    heap.pop_back();
    return id;
  }

  void place(uint32_t c) {
    placed_[c] = true;
    order_->push_back(c);
    for_each_successor(r_, adjacency_, c, [&](uint32_t d) {
      --r_.pending[d];
      if (in_cycle(d)) {
        if (set_of_[d] != set_of_[c] && --outside_pending_[set_of_[d]] == 0) push(ready_sets_, set_distance_[set_of_[d]], set_of_[d]);
      } else if (r_.pending[d] == 0) {
        push(ready_cells_, r_.distance2[d], d);
      }
    });
  }

  void place_set(uint32_t set) {
    auto& members = members_[set];
    std::sort(members.begin(), members.end(), [&](uint32_t a, uint32_t b) {
      return std::pair(r_.distance2[a], a) < std::pair(r_.distance2[b], b);
    });
    for (uint32_t c : members) place(c);
  }

  bool in_cycle(uint32_t c) const { return !set_of_.empty() && set_of_[c] != kNone && members_[set_of_[c]].size() > 1; }

  // Every unplaced cell waits on a predecessor, so the relation among them has a cycle. Group
  // the unplaced cells into strongly connected sets once (later cycles are among them too).
  void find_cycles() {
    uint32_t sets = 0;
    std::tie(set_of_, sets) = strongly_connected_sets(r_, adjacency_, placed_);
    members_.assign(sets, {});
    for (uint32_t c = 0; c < placed_.size(); ++c)
      if (set_of_[c] != kNone) members_[set_of_[c]].push_back(c);
    outside_pending_.assign(sets, 0);
    set_distance_.assign(sets, 0.0);
    for (uint32_t s = 0; s < sets; ++s) {
      if (members_[s].size() < 2) continue;
      cells_in_cycles_ += members_[s].size();
      double nearest = r_.distance2[members_[s].front()];
      for (uint32_t c : members_[s]) {
        nearest = std::min(nearest, r_.distance2[c]);
        outside_pending_[s] += r_.pending[c];
        for_each_successor(r_, adjacency_, c, [&](uint32_t d) {
          if (set_of_[d] == s) --outside_pending_[s];  // an edge inside the set
        });
      }
      set_distance_[s] = nearest;
    }
    for (uint32_t s = 0; s < sets; ++s)
      if (members_[s].size() > 1 && outside_pending_[s] == 0) push(ready_sets_, set_distance_[s], s);
  }

  const TetAdjacency& adjacency_;
  FrontRelation r_;
  std::vector<bool> placed_;
  std::vector<uint32_t>* order_ = nullptr;
  std::vector<Entry> ready_cells_, ready_sets_;
  std::vector<uint32_t> set_of_;                // empty until the first cycle
  std::vector<std::vector<uint32_t>> members_;  // per set
  std::vector<uint32_t> outside_pending_;       // per set: unplaced predecessors outside it
  std::vector<double> set_distance_;            // per set: its nearest member's distance
  size_t cells_in_cycles_ = 0;
};

}  // namespace

VisibilityOrder exact_order(const TetMesh& mesh, const TetAdjacency& adjacency, const glm::dvec3& eye) {
  if (adjacency.neighbour.size() != mesh.tets.size())
    throw std::invalid_argument("exact_order: the adjacency has " + std::to_string(adjacency.neighbour.size()) +
                                " cells, the mesh " + std::to_string(mesh.tets.size()));
  for (size_t c = 0; c < mesh.tets.size(); ++c)
    for (int32_t d : adjacency.neighbour[c])
      if (d >= int32_t(mesh.tets.size()) || d == int32_t(c))
        throw std::invalid_argument("exact_order: cell " + std::to_string(c) + " has neighbour " + std::to_string(d) +
                                    ", not another cell of the mesh");
  VisibilityOrder out = Sorter(adjacency, front_relation(mesh, adjacency, eye)).run();
  out.exact = out.acyclic && adjacency.convex_boundary;
  return out;
}

}  // namespace prismoid::volume
