#pragma once
// Closest-hit and any-hit ray queries over triangles in double precision: a bounding volume
// hierarchy built with the surface area heuristic over binned centroids, and the watertight
// ray/triangle test of Woop, Benthin & Wald 2013 ("Watertight ray/triangle intersection",
// JCGT 2(1)): a ray through a shared edge or vertex of a closed mesh hits at least one of the
// triangles around it, never slips between them. Zero-area triangles are skipped when the
// hierarchy is built; no query returns NaN.
#include <array>
#include <cstdint>
#include <limits>
#include <vector>

#include <glm/vec3.hpp>

namespace prismoid::reference {

inline constexpr uint32_t kNoTriangle = std::numeric_limits<uint32_t>::max();

struct TriangleHit {
  double t = std::numeric_limits<double>::infinity();
  uint32_t triangle = kNoTriangle;  // index into the builder's triangle list
  double b1 = 0.0, b2 = 0.0;        // barycentric weights of v1 and v2 (v0 gets 1 - b1 - b2)
  bool hit() const { return triangle != kNoTriangle; }
};

// The ray origin + t * direction (direction need not be unit length) against one triangle,
// for t in (t_min, t_max). Returns false for a miss, an edge-on ray and a degenerate triangle.
bool intersect_triangle(const glm::dvec3& v0, const glm::dvec3& v1, const glm::dvec3& v2, const glm::dvec3& origin,
                        const glm::dvec3& direction, double t_min, double t_max, TriangleHit& hit);

class TriangleBvh {
 public:
  using Triangle = std::array<glm::dvec3, 3>;
  explicit TriangleBvh(std::vector<Triangle> triangles);

  // The nearest hit with t in (t_min, t_max), skipping triangles `skip_a` and `skip_b` (the
  // surface a ray leaves and the one it aims at); !hit() when there is none.
  TriangleHit closest_hit(const glm::dvec3& origin, const glm::dvec3& direction, double t_min, double t_max,
                          uint32_t skip_a = kNoTriangle, uint32_t skip_b = kNoTriangle) const;
  // Whether any triangle other than the skipped ones is hit with t in (t_min, t_max).
  bool occluded(const glm::dvec3& origin, const glm::dvec3& direction, double t_min, double t_max,
                uint32_t skip_a = kNoTriangle, uint32_t skip_b = kNoTriangle) const;

  size_t triangle_count() const { return triangles_.size(); }
  size_t skipped_triangles() const { return skipped_; }  // zero area or non-finite, never hit
  size_t node_count() const { return nodes_.size(); }
  uint32_t depth() const { return depth_; }

 private:
  struct Node {
    glm::dvec3 lo{0.0}, hi{0.0};
    uint32_t first = 0;  // leaf: first entry in order_; inner: index of the right child (left is next)
    uint32_t count = 0;  // triangles in a leaf; 0 for an inner node
  };
  template <bool AnyHit>
  TriangleHit traverse(const glm::dvec3& origin, const glm::dvec3& direction, double t_min, double t_max, uint32_t skip_a,
                       uint32_t skip_b) const;
  uint32_t build(uint32_t begin, uint32_t end, uint32_t level, std::vector<glm::dvec3>& centroids,
                 std::vector<std::array<glm::dvec3, 2>>& boxes);

  std::vector<Triangle> triangles_;
  std::vector<uint32_t> order_;  // triangle indices, leaves' ranges point into it
  std::vector<Node> nodes_;
  size_t skipped_ = 0;
  uint32_t depth_ = 0;
};

}  // namespace prismoid::reference
