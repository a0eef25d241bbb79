// FastAtlas's charts (renderer/surface/fastatlas/charts.hpp): the visible faces' connected
// components against a plain breadth-first search over the same visibility; every visible face in
// exactly one chart, named by its lowest face; charts never share a vertex, so their boundaries
// lie only where visibility changes; each triangle's screen box, including triangles that cross
// the near plane or lie behind the eye.
#include <gtest/gtest.h>

#include <queue>
#include <random>

#include <glm/geometric.hpp>
#include <glm/trigonometric.hpp>
#include <glm/vec4.hpp>

#include "renderer/surface/fastatlas/atlas_map.hpp"
#include "renderer/surface/fastatlas/charts.hpp"
#include "scene/generators.hpp"

namespace prismoid {
namespace {

using fastatlas::kNoChart;

// A camera on the +z axis at `distance`, looking at the origin.
Camera on_z_axis(double distance) {
  Camera camera;
  camera.eye = {0.0, 0.0, distance};
  camera.target = {0.0, 0.0, 0.0};
  camera.near_distance = 0.1;
  return camera;
}

// Per face, whether `keep` holds for its centroid (three times it: the sum of its corners).
template <class Keep>
std::vector<uint8_t> faces_where(const HalfedgeMesh& mesh, Keep keep) {
  std::vector<uint8_t> flags(mesh.face_count());
  for (uint32_t f = 0; f < mesh.face_count(); ++f) {
    const auto& t = mesh.faces[f];
    flags[f] = keep(mesh.positions[t[0]] + mesh.positions[t[1]] + mesh.positions[t[2]]) ? 1 : 0;
  }
  return flags;
}

// Components of the visible faces under sharing a vertex, by breadth-first search: the twin.
std::vector<uint32_t> components_by_search(const HalfedgeMesh& mesh, const std::vector<uint8_t>& visible) {
  std::vector<std::vector<uint32_t>> faces_at(mesh.vertex_count());
  for (uint32_t f = 0; f < mesh.face_count(); ++f)
    if (visible[f])
      for (uint32_t v : mesh.faces[f]) faces_at[v].push_back(f);
  std::vector<uint32_t> label(mesh.face_count(), kNoChart);
  for (uint32_t f = 0; f < mesh.face_count(); ++f) {
    if (!visible[f] || label[f] != kNoChart) continue;
    std::queue<uint32_t> todo;
    todo.push(f);
    label[f] = f;  // the lowest face of its component: faces are visited in increasing order
    while (!todo.empty()) {
      const uint32_t g = todo.front();
      todo.pop();
      for (uint32_t v : mesh.faces[g])
        for (uint32_t h : faces_at[v])
          if (label[h] == kNoChart) {
            label[h] = f;
            todo.push(h);
          }
    }
  }
  return label;
}

void expect_charts_match_search(const HalfedgeMesh& mesh, const std::vector<uint8_t>& visible) {
  const fastatlas::Charts charts = fastatlas::visible_charts(mesh, visible);
  const std::vector<uint32_t> label = components_by_search(mesh, visible);
  for (uint32_t f = 0; f < mesh.face_count(); ++f) {
    if (!visible[f]) {
      EXPECT_EQ(charts.chart_of_face[f], kNoChart);
      continue;
    }
    ASSERT_NE(charts.chart_of_face[f], kNoChart) << "visible face " << f << " in no chart";
    EXPECT_EQ(charts.root[charts.chart_of_face[f]], label[f]) << "face " << f;
    for (uint32_t v : mesh.faces[f]) EXPECT_EQ(charts.chart_of_vertex[v], charts.chart_of_face[f]) << "vertex " << v;
  }
  for (size_t c = 1; c < charts.root.size(); ++c) EXPECT_LT(charts.root[c - 1], charts.root[c]);
}

TEST(FastAtlasCharts, ComponentsOfVisibleFacesMatchASearchAndShareNoVertex) {
  const HalfedgeMesh sphere = build_halfedge_mesh(make_icosphere(glm::dvec3(0.0), 1.0, 4));
  std::mt19937 rng(1);
  for (double p : {0.1, 0.4, 0.7, 0.95}) {
    std::vector<uint8_t> visible(sphere.face_count());
    for (auto& v : visible) v = std::bernoulli_distribution(p)(rng) ? 1 : 0;
    expect_charts_match_search(sphere, visible);
  }
  // Half the sphere seen (z > 0): one chart, rooted at its lowest face.
  const std::vector<uint8_t> front = faces_where(sphere, [](const glm::dvec3& c) { return c.z > 0.0; });
  const fastatlas::Charts half = fastatlas::visible_charts(sphere, front);
  EXPECT_EQ(half.root.size(), 1u);
  expect_charts_match_search(sphere, front);
  // Nothing visible: no charts.
  const fastatlas::Charts none = fastatlas::visible_charts(sphere, std::vector<uint8_t>(sphere.face_count(), 0));
  EXPECT_TRUE(none.root.empty());
  EXPECT_THROW(fastatlas::visible_charts(sphere, {1, 0}), std::invalid_argument);
}

// The renderer's own projection (scene/camera.hpp), the box's independent twin for triangles the
// near plane does not cut.
glm::dvec2 pixel_of(const glm::dvec3& p, const Camera& camera, uint32_t w, uint32_t h) {
  const glm::dvec4 clip = projection_matrix(camera, double(w) / h) * view_matrix(camera, glm::dvec3(0.0)) * glm::dvec4(p, 1.0);
  const glm::dvec2 ndc = glm::dvec2(clip) / clip.w;  // Vulkan: y down
  return {(ndc.x + 1.0) * 0.5 * w, (ndc.y + 1.0) * 0.5 * h};
}

TEST(FastAtlasCharts, TriangleBoxesFollowTheProjectionAndSurviveTheNearPlane) {
  Camera camera;
  camera.eye = {0.0, 0.0, 5.0};
  camera.target = {0.0, 0.0, 0.0};
  camera.fovy_degrees = 40.0;
  camera.near_distance = 0.1;
  const uint32_t w = 640, h = 480;
  // In front of the eye, inside the view: the box of the projected corners.
  const glm::dvec3 a(-0.5, -0.3, 0.0), b(0.7, -0.2, 0.5), c(0.1, 0.6, -1.0);
  const fastatlas::PixelBox box = fastatlas::triangle_box(a, b, c, camera, w, h);
  glm::dvec2 lo(1e30), hi(-1e30);
  for (const glm::dvec3& p : {a, b, c}) {
    lo = glm::min(lo, pixel_of(p, camera, w, h));
    hi = glm::max(hi, pixel_of(p, camera, w, h));
  }
  EXPECT_NEAR(box.x0, lo.x, 1e-9);
  EXPECT_NEAR(box.x1, hi.x, 1e-9);
  EXPECT_NEAR(box.y0, lo.y, 1e-9);
  EXPECT_NEAR(box.y1, hi.y, 1e-9);
  // Behind the eye: nothing.
  EXPECT_TRUE(fastatlas::triangle_box({0, 0, 6}, {1, 0, 7}, {0, 1, 6.5}, camera, w, h).empty());
  // Crossing the near plane, reaching far behind the eye: a finite box inside the viewport (the
  // division by w alone would throw the behind-the-eye corner to the opposite side).
  const fastatlas::PixelBox crossing = fastatlas::triangle_box({-0.2, -0.1, 0.0}, {0.3, 0.0, 0.0}, {0.05, 0.05, 50.0}, camera, w, h);
  EXPECT_FALSE(crossing.empty());
  EXPECT_GE(crossing.x0, 0.0);
  EXPECT_LE(crossing.x1, double(w));
  EXPECT_GE(crossing.y0, 0.0);
  EXPECT_LE(crossing.y1, double(h));
  EXPECT_LT(crossing.x0, pixel_of({-0.2, -0.1, 0.0}, camera, w, h).x + 1e-9);  // it covers the part before the plane
  // A floor under the eye reaching past it on both sides covers the viewport's lower part, not more.
  const fastatlas::PixelBox floor = fastatlas::triangle_box({-100, -1, 10}, {100, -1, 10}, {0, -1, -100}, camera, w, h);
  EXPECT_NEAR(floor.x0, 0.0, 1e-9);
  EXPECT_NEAR(floor.x1, double(w), 1e-9);
  EXPECT_NEAR(floor.y1, double(h), 1e-9);
  EXPECT_GT(floor.y0, 0.5 * h);  // below the horizon
}

TEST(FastAtlasCharts, ChartBoxesAreTheUnionOfTheirFacesInWholePixels) {
  const HalfedgeMesh sphere = build_halfedge_mesh(make_icosphere(glm::dvec3(0.0), 1.0, 3));
  const Camera camera = on_z_axis(4.0);
  const std::vector<uint8_t> front = faces_where(sphere, [](const glm::dvec3& c) { return c.z > 0.0; });
  const fastatlas::Charts charts = fastatlas::visible_charts(sphere, front);
  const fastatlas::ChartScreenBoxes boxes = fastatlas::chart_boxes(sphere, charts, camera, 800, 600);
  ASSERT_EQ(boxes.boxes.size(), 1u);
  // The visible hemisphere's silhouette: a disc of radius r = f / sqrt(d^2 - 1) pixels (f the
  // focal length in pixels), about the centre; its box spans 2 r, the faces' box a little less.
  const double focal = 300.0 / std::tan(glm::radians(camera.fovy_degrees) * 0.5);
  const double r = focal / std::sqrt(16.0 - 1.0);
  EXPECT_NEAR(boxes.boxes[0].x1 - boxes.boxes[0].x0, 2.0 * r, 0.05 * r);
  EXPECT_EQ(boxes.width[0], uint32_t(std::ceil(boxes.boxes[0].x1) - std::floor(boxes.boxes[0].x0)));
  EXPECT_EQ(boxes.height[0], uint32_t(std::ceil(boxes.boxes[0].y1) - std::floor(boxes.boxes[0].y0)));
}

// A frame's whole atlas on the CPU: charts of a seen sphere split by an occluding band, their
// boxes packed into an atlas too small for scale 1. Each chart's map sends its visible vertices
// into its own placed box (so charts never overlap in the atlas: the map is injective), and
// stretches every screen distance by exactly the packer's scale.
TEST(FastAtlasCharts, EachChartMapsIntoItsOwnBoxAtThePackersScale) {
  const HalfedgeMesh sphere = build_halfedge_mesh(make_icosphere(glm::dvec3(0.0), 1.0, 4));
  const Camera camera = on_z_axis(3.0);
  const uint32_t w = 1280, h = 720;
  // The front, less a band across it: two charts.
  const std::vector<uint8_t> seen = faces_where(sphere, [](const glm::dvec3& c) { return c.z > 0.0 && std::abs(c.y) > 0.6; });
  const fastatlas::Charts charts = fastatlas::visible_charts(sphere, seen);
  ASSERT_EQ(charts.root.size(), 2u);
  const fastatlas::ChartScreenBoxes boxes = fastatlas::chart_boxes(sphere, charts, camera, w, h);
  std::vector<fastatlas::ChartBox> packer_boxes;
  for (size_t c = 0; c < charts.root.size(); ++c) packer_boxes.push_back({boxes.width[c], boxes.height[c], charts.root[c]});
  fastatlas::PackingOptions o;
  o.atlas_width = 256;
  o.atlas_height = 256;
  const fastatlas::AtlasPacking packing = fastatlas::pack_atlas(packer_boxes, o);
  ASSERT_TRUE(packing.fits);
  ASSERT_LT(packing.scale, 1.0);  // the test exercises a scale below one texel per pixel
  for (uint32_t f = 0; f < sphere.face_count(); ++f) {
    const uint32_t c = charts.chart_of_face[f];
    if (c == kNoChart) continue;
    const fastatlas::ChartMap map = fastatlas::chart_map(boxes.boxes[c], packing.charts[c], packing.scale, o.border);
    const auto& placed = packing.charts[c];
    glm::dvec2 px[3], tx[3];
    for (int k = 0; k < 3; ++k) {
      px[k] = pixel_of(sphere.positions[sphere.faces[f][k]], camera, w, h);
      tx[k] = fastatlas::to_atlas(map, px[k]);
      EXPECT_GE(tx[k].x, double(placed.x)) << "face " << f;
      EXPECT_LE(tx[k].x, double(placed.x + placed.width)) << "face " << f;
      EXPECT_GE(tx[k].y, double(placed.y)) << "face " << f;
      EXPECT_LE(tx[k].y, double(placed.y + placed.height)) << "face " << f;
    }
    for (int k = 0; k < 3; ++k) {
      const double on_screen = glm::length(px[(k + 1) % 3] - px[k]), in_atlas = glm::length(tx[(k + 1) % 3] - tx[k]);
      EXPECT_NEAR(in_atlas, packing.scale * on_screen, 1e-9 * (1.0 + on_screen)) << "face " << f;
    }
  }
}

}  // namespace
}  // namespace prismoid
