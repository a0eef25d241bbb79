#pragma once
// FastAtlas's charts (Real-Time Compact Atlases for Texture Space Shading, section 5): each
// frame, the connected components of the visible triangles, and each chart's box in pixels, on
// the CPU: the rule the GPU's union-find and box passes follow, and their twin in tests.
//
// Charts are joined across shared edges and, as the paper's vertex-uniqueness merge does, across
// shared vertices too, so every vertex belongs to one chart (the atlas pass looks a chart up by
// vertex). A chart's boundary therefore lies only where visibility changes (silhouettes,
// occlusion boundaries, the screen's edge) or on the mesh's own boundary: it is never seen.
// A chart is named by its root, its lowest face index, the packer's tie-break.
#include <cstdint>
#include <vector>

#include <glm/mat4x4.hpp>

#include "scene/camera.hpp"
#include "scene/halfedge_mesh.hpp"

namespace prismoid::fastatlas {

inline constexpr uint32_t kNoChart = 0xFFFFFFFFu;

struct Charts {
  std::vector<uint32_t> chart_of_face;    // per face: its chart, kNoChart where not visible
  std::vector<uint32_t> chart_of_vertex;  // per vertex: the chart of its visible faces, kNoChart if none
  std::vector<uint32_t> root;             // per chart: its lowest face index; charts numbered by it
};

// `visible`: one flag per face of `mesh` (the visibility pass's buffer).
Charts visible_charts(const HalfedgeMesh& mesh, const std::vector<uint8_t>& visible);

// A box on the screen in pixels, x right and y down from the top-left corner.
struct PixelBox {
  double x0 = 0.0, y0 = 0.0, x1 = 0.0, y1 = 0.0;
  bool empty() const { return !(x1 > x0 && y1 > y0); }
};

// The part of triangle (a, b, c) (world space) beyond the camera's near plane, projected, as a
// box clamped to the viewport. The triangle is clipped against the near plane alone (a triangle
// or a quad remains), so a triangle crossing it gives the box of what the camera sees instead of
// the huge or folded box a division by w near 0 gives (section 5.2). Empty when nothing of it
// lies beyond the near plane or inside the viewport.
PixelBox triangle_box(const glm::dvec3& a, const glm::dvec3& b, const glm::dvec3& c, const Camera& camera, uint32_t width,
                      uint32_t height);

// Per chart, the union of its faces' boxes, and its size in whole pixels (the packer's box:
// from floor(x0) to ceil(x1), at least 1 each way).
struct ChartScreenBoxes {
  std::vector<PixelBox> boxes;
  std::vector<uint32_t> width, height;
};
ChartScreenBoxes chart_boxes(const HalfedgeMesh& mesh, const Charts& charts, const Camera& camera, uint32_t width, uint32_t height);

}  // namespace prismoid::fastatlas
