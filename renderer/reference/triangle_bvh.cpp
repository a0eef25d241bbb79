#include "renderer/reference/triangle_bvh.hpp"

#include <algorithm>
#include <cmath>
#include <utility>

#include <glm/geometric.hpp>

namespace prismoid::reference {

namespace {

constexpr uint32_t kBins = 16;
constexpr uint32_t kLeafSize = 4;        // always a leaf at or below this many triangles
constexpr uint32_t kMaxLeafSize = 16;    // a leaf may hold this many when splitting costs more
constexpr uint32_t kSahLevels = 48;      // deeper than this, split at the median (bounded depth)
constexpr uint32_t kStackSize = 128;     // > kSahLevels + log2(2^32)
// Slab distances are rounded; widening the exit distance by 2 gamma_3 (Ize 2013, "Robust BVH
// ray traversal") keeps a box that the exact ray touches from being missed.
constexpr double kExitWiden = 1.0 + 2.0 * (3.0 * 0x1p-53) / (1.0 - 3.0 * 0x1p-53);

bool finite(const glm::dvec3& v) { return std::isfinite(v.x) && std::isfinite(v.y) && std::isfinite(v.z); }

double half_area(const glm::dvec3& lo, const glm::dvec3& hi) {
  const glm::dvec3 e = hi - lo;
  return e.x * e.y + e.y * e.z + e.z * e.x;
}

// The ray's entry distance into the box, or +infinity for a miss within [t_min, t_max].
double slab_entry(const glm::dvec3& lo, const glm::dvec3& hi, const glm::dvec3& origin, const glm::dvec3& direction,
                  const glm::dvec3& inverse, double t_min, double t_max) {
  double t0 = t_min, t1 = t_max;
  for (int i = 0; i < 3; ++i) {
    if (direction[i] == 0.0) {
      if (origin[i] < lo[i] || origin[i] > hi[i]) return std::numeric_limits<double>::infinity();
      continue;
    }
    double ta = (lo[i] - origin[i]) * inverse[i];
    double tb = (hi[i] - origin[i]) * inverse[i];
    if (ta > tb) std::swap(ta, tb);
    t0 = std::max(t0, ta);
    t1 = std::min(t1, tb * kExitWiden);
    if (t0 > t1) return std::numeric_limits<double>::infinity();
  }
  return t0;
}

// The edge function p x q of the sheared 2D vertices, recomputed in extended precision when it
// comes out exactly zero, so that the side of a ray passing (almost) through an edge is decided
// right. Each edge is computed from its two endpoints alone, so two triangles sharing an edge
// get exactly opposite values: the test stays watertight.
double edge_function(double px, double py, double qx, double qy) {
  const double e = px * qy - py * qx;
  if (e != 0.0) return e;
  using L = long double;
  return static_cast<double>(L(px) * L(qy) - L(py) * L(qx));
}

}  // namespace

bool intersect_triangle(const glm::dvec3& v0, const glm::dvec3& v1, const glm::dvec3& v2, const glm::dvec3& origin,
                        const glm::dvec3& direction, double t_min, double t_max, TriangleHit& hit) {
  // Woop et al. 2013: permute axes so that z is the direction's largest component (swapping x
  // and y keeps the winding when it is negative), shear so that the ray runs along +z through
  // the origin, then decide by the signs of the 2D edge functions of the sheared triangle.
  const glm::dvec3 ad = glm::abs(direction);
  const int kz = ad.x > ad.y ? (ad.x > ad.z ? 0 : 2) : (ad.y > ad.z ? 1 : 2);
  if (direction[kz] == 0.0) return false;  // zero (or NaN) direction
  int kx = (kz + 1) % 3, ky = (kx + 1) % 3;
  if (direction[kz] < 0.0) std::swap(kx, ky);
  const double sz = 1.0 / direction[kz];
  const double sx = direction[kx] * sz, sy = direction[ky] * sz;
  const glm::dvec3 a = v0 - origin, b = v1 - origin, c = v2 - origin;
  const double ax = a[kx] - sx * a[kz], ay = a[ky] - sy * a[kz];
  const double bx = b[kx] - sx * b[kz], by = b[ky] - sy * b[kz];
  const double cx = c[kx] - sx * c[kz], cy = c[ky] - sy * c[kz];
  const double u = edge_function(cx, cy, bx, by);  // weight of v0
  const double v = edge_function(ax, ay, cx, cy);  // weight of v1
  const double w = edge_function(bx, by, ax, ay);  // weight of v2
  if ((u < 0.0 || v < 0.0 || w < 0.0) && (u > 0.0 || v > 0.0 || w > 0.0)) return false;
  const double det = u + v + w;
  if (det == 0.0 || !std::isfinite(det)) return false;  // edge-on ray or zero-area triangle
  const double t_scaled = (u * a[kz] + v * b[kz] + w * c[kz]) * sz;
  const double t = t_scaled / det;
  if (!(t > t_min && t < t_max)) return false;  // also rejects NaN and infinite t
  hit.t = t;
  hit.b1 = v / det;
  hit.b2 = w / det;
  return true;
}

TriangleBvh::TriangleBvh(std::vector<Triangle> triangles) : triangles_(std::move(triangles)) {
  std::vector<glm::dvec3> centroids(triangles_.size());
  std::vector<std::array<glm::dvec3, 2>> boxes(triangles_.size());
  for (uint32_t i = 0; i < triangles_.size(); ++i) {
    const auto& t = triangles_[i];
    const glm::dvec3 n = glm::cross(t[1] - t[0], t[2] - t[0]);
    if (!finite(t[0]) || !finite(t[1]) || !finite(t[2]) || !finite(n) || glm::length(n) == 0.0) {
      ++skipped_;
      continue;
    }
    order_.push_back(i);
    centroids[i] = (t[0] + t[1] + t[2]) / 3.0;
    boxes[i] = {glm::min(t[0], glm::min(t[1], t[2])), glm::max(t[0], glm::max(t[1], t[2]))};
  }
  if (!order_.empty()) build(0, static_cast<uint32_t>(order_.size()), 1, centroids, boxes);
}

uint32_t TriangleBvh::build(uint32_t begin, uint32_t end, uint32_t level, std::vector<glm::dvec3>& centroids,
                            std::vector<std::array<glm::dvec3, 2>>& boxes) {
  depth_ = std::max(depth_, level);
  const auto index = static_cast<uint32_t>(nodes_.size());
  nodes_.emplace_back();
  glm::dvec3 lo(std::numeric_limits<double>::infinity()), hi(-std::numeric_limits<double>::infinity());
  glm::dvec3 clo = lo, chi = hi;
  for (uint32_t i = begin; i < end; ++i) {
    const uint32_t t = order_[i];
    lo = glm::min(lo, boxes[t][0]);
    hi = glm::max(hi, boxes[t][1]);
    clo = glm::min(clo, centroids[t]);
    chi = glm::max(chi, centroids[t]);
  }
  nodes_[index].lo = lo;
  nodes_[index].hi = hi;
  const uint32_t n = end - begin;
  const glm::dvec3 extent = chi - clo;
  const int axis = extent.x > extent.y ? (extent.x > extent.z ? 0 : 2) : (extent.y > extent.z ? 1 : 2);
  auto make_leaf = [&] {
    nodes_[index].first = begin;
    nodes_[index].count = n;
    return index;
  };
  if (n <= kLeafSize || !(extent[axis] > 0.0)) return make_leaf();  // small, or all centroids coincide

  uint32_t mid = begin;
  if (level < kSahLevels) {
    // Binned SAH: bin the centroids along the widest axis, cost each of the kBins - 1 planes.
    struct Bin {
      glm::dvec3 lo{std::numeric_limits<double>::infinity()}, hi{-std::numeric_limits<double>::infinity()};
      uint32_t count = 0;
    };
    std::array<Bin, kBins> bins{};
    const double scale = kBins / extent[axis];
    auto bin_of = [&](uint32_t t) {
      return std::min(kBins - 1, static_cast<uint32_t>((centroids[t][axis] - clo[axis]) * scale));
    };
    for (uint32_t i = begin; i < end; ++i) {
      Bin& b = bins[bin_of(order_[i])];
      b.lo = glm::min(b.lo, boxes[order_[i]][0]);
      b.hi = glm::max(b.hi, boxes[order_[i]][1]);
      ++b.count;
    }
    std::array<double, kBins> right_cost{};
    Bin acc;
    for (uint32_t k = kBins - 1; k > 0; --k) {
      acc.lo = glm::min(acc.lo, bins[k].lo);
      acc.hi = glm::max(acc.hi, bins[k].hi);
      acc.count += bins[k].count;
      right_cost[k] = acc.count ? acc.count * half_area(acc.lo, acc.hi) : 0.0;
    }
    acc = Bin{};
    double best = std::numeric_limits<double>::infinity();
    uint32_t best_split = 0;
    for (uint32_t k = 1; k < kBins; ++k) {
      acc.lo = glm::min(acc.lo, bins[k - 1].lo);
      acc.hi = glm::max(acc.hi, bins[k - 1].hi);
      acc.count += bins[k - 1].count;
      const double cost = (acc.count ? acc.count * half_area(acc.lo, acc.hi) : 0.0) + right_cost[k];
      if (acc.count > 0 && acc.count < n && cost < best) {
        best = cost;
        best_split = k;
      }
    }
    const double leaf_cost = n * half_area(lo, hi);
    if (best_split == 0 || (best >= leaf_cost && n <= kMaxLeafSize)) {
      if (n <= kMaxLeafSize) return make_leaf();
    } else {
      mid = static_cast<uint32_t>(
          std::partition(order_.begin() + begin, order_.begin() + end, [&](uint32_t t) { return bin_of(t) < best_split; }) -
          order_.begin());
    }
  }
  if (mid <= begin || mid >= end) {  // median split: SAH found nothing or the hierarchy is deep
    mid = begin + n / 2;
    std::nth_element(order_.begin() + begin, order_.begin() + mid, order_.begin() + end,
                     [&](uint32_t a, uint32_t b) { return centroids[a][axis] < centroids[b][axis]; });
  }
  build(begin, mid, level + 1, centroids, boxes);
  const uint32_t right = build(mid, end, level + 1, centroids, boxes);
  nodes_[index].first = right;
  nodes_[index].count = 0;
  return index;
}

template <bool AnyHit>
TriangleHit TriangleBvh::traverse(const glm::dvec3& origin, const glm::dvec3& direction, double t_min, double t_max,
                                  uint32_t skip_a, uint32_t skip_b) const {
  TriangleHit best;
  best.t = t_max;
  if (nodes_.empty() || !finite(origin) || !finite(direction)) return TriangleHit{};
  const glm::dvec3 inverse(1.0 / direction.x, 1.0 / direction.y, 1.0 / direction.z);
  constexpr double kMiss = std::numeric_limits<double>::infinity();
  std::array<std::pair<uint32_t, double>, kStackSize> stack{};  // node, its entry distance
  uint32_t top = 0;
  const double root_entry = slab_entry(nodes_[0].lo, nodes_[0].hi, origin, direction, inverse, t_min, best.t);
  if (root_entry == kMiss) return TriangleHit{};
  stack[top++] = {0, root_entry};
  while (top > 0) {
    const auto [node_index, entry] = stack[--top];
    if (entry > best.t) continue;  // a nearer hit was found since this node was pushed
    const Node& node = nodes_[node_index];
    if (node.count > 0) {
      for (uint32_t i = node.first; i < node.first + node.count; ++i) {
        const uint32_t t = order_[i];
        if (t == skip_a || t == skip_b) continue;
        TriangleHit h;
        const auto& tri = triangles_[t];
        if (intersect_triangle(tri[0], tri[1], tri[2], origin, direction, t_min, best.t, h)) {
          h.triangle = t;
          best = h;
          if constexpr (AnyHit) return best;
        }
      }
      continue;
    }
    const uint32_t left = node_index + 1, right = node.first;
    const double tl = slab_entry(nodes_[left].lo, nodes_[left].hi, origin, direction, inverse, t_min, best.t);
    const double tr = slab_entry(nodes_[right].lo, nodes_[right].hi, origin, direction, inverse, t_min, best.t);
    // Push the farther child first so the nearer one is visited first.
    if (tl <= tr) {
      if (tr != kMiss) stack[top++] = {right, tr};
      if (tl != kMiss) stack[top++] = {left, tl};
    } else {
      if (tl != kMiss) stack[top++] = {left, tl};
      if (tr != kMiss) stack[top++] = {right, tr};
    }
  }
  if (!best.hit()) return TriangleHit{};
  return best;
}

TriangleHit TriangleBvh::closest_hit(const glm::dvec3& origin, const glm::dvec3& direction, double t_min, double t_max,
                                     uint32_t skip_a, uint32_t skip_b) const {
  return traverse<false>(origin, direction, t_min, t_max, skip_a, skip_b);
}

bool TriangleBvh::occluded(const glm::dvec3& origin, const glm::dvec3& direction, double t_min, double t_max, uint32_t skip_a,
                           uint32_t skip_b) const {
  return traverse<true>(origin, direction, t_min, t_max, skip_a, skip_b).hit();
}

}  // namespace prismoid::reference
