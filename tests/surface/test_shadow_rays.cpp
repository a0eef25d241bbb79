// The CPU twin of the GPU's shadow rays (renderer/reference/shadow_rays.hpp) on geometry whose
// answers are known: the shared sample table, segments into and past an occluder, the ratio
// for an emitter partly hidden, the Cornell box's ceiling light from the open floor and from
// under the tall block, ambiguity exactly at an occluder's edge, and direct_light with shadows.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>

#include <glm/geometric.hpp>

#include "renderer/reference/direct_light.hpp"
#include "renderer/reference/shadow_rays.hpp"
#include "scene/surface_generators.hpp"
#include "shaders/shared/surface.h"
#include "surface/surface_test_scenes.hpp"

namespace prismoid::test {
namespace {

// The four points are the centroids of the midpoint subdivision's triangles: corner triangles
// (corner k and the midpoints of its two edges) and the middle one (the three midpoints).
TEST(ShadowRays, SampleTableIsTheMidpointSubdivisionsCentroids) {
  const glm::dvec3 c[3] = {{1, 0, 0}, {0, 1, 0}, {0, 0, 1}};
  const glm::dvec3 m01 = 0.5 * (c[0] + c[1]), m12 = 0.5 * (c[1] + c[2]), m02 = 0.5 * (c[0] + c[2]);
  const glm::dvec3 expected[4] = {(c[0] + m01 + m02) / 3.0, (c[1] + m01 + m12) / 3.0, (c[2] + m02 + m12) / 3.0, (m01 + m12 + m02) / 3.0};
  ASSERT_EQ(PRISMOID_EMITTER_SHADOW_SAMPLES, 4u);
  for (uint32_t k = 0; k < 4; ++k) {
    const glm::dvec3 b = reference::emitter_shadow_sample(k);
    for (int i = 0; i < 3; ++i) EXPECT_NEAR(b[i], expected[k][i], 1e-15) << k;
  }
}

TEST(ShadowRays, PointAndDirectionalSegmentsThroughAnOccluder) {
  const SurfaceScene scene = occluder_scene(ShadowLight::Point);
  const reference::ShadowRays rays(scene);
  const glm::dvec3 up(0.0, 1.0, 0.0);
  // The floor is global triangles 0 and 1; under the occluder's middle (umbra), far outside it.
  const glm::dvec3 below = (3.0 * glm::dvec3(kOccluderX, kOccluderY, kOccluderZ) - kShadowPointLight) / 2.0;  // projects to its centre
  ASSERT_NEAR(below.y, 0.0, 1e-15);
  reference::ShadowVisibility v = rays.point_light(below, up, 0, kShadowPointLight);
  EXPECT_EQ(v.value, 0.0);
  EXPECT_FALSE(v.ambiguous);
  EXPECT_EQ(v.rays, 1u);
  v = rays.point_light({-1.8, 0.0, -1.8}, up, 0, kShadowPointLight);
  EXPECT_EQ(v.value, 1.0);
  EXPECT_FALSE(v.ambiguous);
  // Exactly on the umbra's edge: the segment from the moved origin (offset above the floor)
  // passes through the occluder's edge x = 0.8.
  const double off = rays.offset(below), s = (kOccluderY - off) / (kShadowPointLight.y - off);
  const glm::dvec3 edge(((kOccluderX + 0.5 * kOccluderSize) - s * kShadowPointLight.x) / (1.0 - s), 0.0, below.z);
  v = rays.point_light(edge, up, 0, kShadowPointLight);
  EXPECT_TRUE(v.ambiguous);
  // A hair further out (1e-3 of the occluder) is not ambiguous any more.
  v = rays.point_light(edge + glm::dvec3(1.5e-3, 0.0, 0.0), up, 0, kShadowPointLight);
  EXPECT_FALSE(v.ambiguous);
  EXPECT_EQ(v.value, 1.0);
  // Directional: straight up from below the occluder, and from a floor corner.
  EXPECT_EQ(rays.directional_light({kOccluderX, 0.0, kOccluderZ}, up, 0, up).value, 0.0);
  EXPECT_EQ(rays.directional_light({-1.9, 0.0, 1.9}, up, 0, up).value, 1.0);
  // A light grazing the floor (1e-4 rad above it) from a floor point: the offset keeps the
  // segment off the floor's own and neighbouring (coplanar) triangles.
  const glm::dvec3 grazing = glm::normalize(glm::dvec3(1.0, 1e-4, 0.0));
  v = rays.directional_light({-1.9, 0.0, -1.5}, up, 0, grazing);
  EXPECT_EQ(v.value, 1.0);
  EXPECT_FALSE(v.ambiguous);
  // The offset and ambiguity distance follow the scene's scale (half the floor's side, 2).
  EXPECT_DOUBLE_EQ(rays.scale(), 2.0);
  EXPECT_DOUBLE_EQ(rays.offset({0.0, 0.0, 0.0}), 2.0 * 0x1p-16);
  EXPECT_DOUBLE_EQ(rays.ambiguity_distance(), 2.0 * 0x1p-19);
}

// One emitter triangle above a floor point and a thin bar that hides exactly its sample 0's
// segment: the ratio is the other samples' weight over all four weights, computed here
// independently from the stated formula.
TEST(ShadowRays, EmitterRatioWeighsTheVisibleSamples) {
  SurfaceScene scene;
  scene.materials = {{"floor", glm::dvec3(0.5), glm::dvec3(0.0), 1.0, glm::dvec3(0.0)},
                     {"light", glm::dvec3(0.0), glm::dvec3(0.0), 1.0, glm::dvec3(5.0)}};
  scene.meshes.push_back(horizontal_quad("floor", 0.0, 0.0, 0.0, 4.0, 0));
  SceneMesh light;
  light.name = "light";
  light.material = 1;
  light.positions = {{-0.6, 2.0, -0.3}, {0.7, 2.0, -0.4}, {0.1, 2.0, 0.8}};
  light.triangles = {{0, 1, 2}};
  if (glm::cross(light.positions[1] - light.positions[0], light.positions[2] - light.positions[0]).y > 0.0) light.triangles = {{0, 2, 1}};
  scene.meshes.push_back(light);
  const auto& c = scene.meshes[1].positions;
  const auto& t = scene.meshes[1].triangles[0];
  const std::array<glm::dvec3, 3> corners = {c[t[0]], c[t[1]], c[t[2]]};
  const glm::dvec3 normal = glm::normalize(glm::cross(corners[1] - corners[0], corners[2] - corners[0]));
  ASSERT_LT(normal.y, 0.0);
  const glm::dvec3 p(0.2, 0.0, 0.1), up(0.0, 1.0, 0.0);
  // A small square occluder around the point halfway to sample 0.
  const glm::dvec3 b0 = reference::emitter_shadow_sample(0);
  const glm::dvec3 q0 = b0.x * corners[0] + b0.y * corners[1] + b0.z * corners[2];
  const glm::dvec3 mid = 0.5 * (p + q0);
  scene.meshes.push_back(horizontal_quad("blocker", mid.x, mid.y, mid.z, 0.05, 0));
  const reference::ShadowRays rays(scene);
  double total = 0.0, seen = 0.0;
  for (uint32_t k = 0; k < 4; ++k) {
    const glm::dvec3 b = reference::emitter_shadow_sample(k);
    const glm::dvec3 q = b.x * corners[0] + b.y * corners[1] + b.z * corners[2];
    const double d2 = glm::dot(q - p, q - p);
    const glm::dvec3 w = (q - p) / std::sqrt(d2);
    const double weight = std::max(glm::dot(w, up), 0.0) * std::max(-glm::dot(w, normal), 0.0) / d2;
    total += weight;
    if (k != 0) seen += weight;
  }
  const reference::ShadowVisibility v = rays.emitter(p, up, up, 0, corners, normal, 2);
  EXPECT_NEAR(v.value, seen / total, 1e-14);
  EXPECT_GT(v.value, 0.5);
  EXPECT_LT(v.value, 0.95);
  EXPECT_EQ(v.rays, 4u);
  EXPECT_FALSE(v.ambiguous);
  // Seen from behind the emitter's plane every weight is 0: the ratio is 1 by definition.
  const reference::ShadowVisibility behind = rays.emitter({0.0, 3.0, 0.0}, up, up, reference::kNoTriangle, corners, normal, 2);
  EXPECT_EQ(behind.value, 1.0);
  EXPECT_EQ(behind.rays, 0u);
}

// The Cornell box's ceiling light (two emitter triangles) from a floor point in full view of it
// (ratio 1 for both) and from the floor under the tall block (0: its top is in the way).
TEST(ShadowRays, CornellCeilingLightFromTheOpenFloorAndUnderTheTallBlock) {
  const SurfaceScene scene = make_cornell_box();
  const reference::ShadowRays rays(scene);
  uint32_t first = 0, light_mesh = 0;
  for (uint32_t m = 0; m < scene.meshes.size(); ++m) {
    if (scene.meshes[m].name == "light") break;
    first += static_cast<uint32_t>(scene.meshes[m].triangles.size());
    light_mesh = m + 1;
  }
  ASSERT_EQ(scene.meshes[light_mesh].name, "light");
  const SceneMesh& light = scene.meshes[light_mesh];
  const glm::dvec3 up(0.0, 1.0, 0.0);
  for (uint32_t j = 0; j < light.triangles.size(); ++j) {
    const auto& t = light.triangles[j];
    const std::array<glm::dvec3, 3> corners = {light.positions[t[0]], light.positions[t[1]], light.positions[t[2]]};
    const glm::dvec3 normal = glm::normalize(glm::cross(corners[1] - corners[0], corners[2] - corners[0]));
    ASSERT_LT(normal.y, 0.0);
    const reference::ShadowVisibility open = rays.emitter({150.0, 0.0, 450.0}, up, up, 0, corners, normal, first + j);
    EXPECT_EQ(open.value, 1.0) << j;
    EXPECT_EQ(open.rays, 4u);
    EXPECT_FALSE(open.ambiguous);
    const reference::ShadowVisibility under = rays.emitter({368.0, 0.0, 351.0}, up, up, 0, corners, normal, first + j);
    EXPECT_EQ(under.value, 0.0) << j;
    EXPECT_EQ(under.rays, 4u);
    EXPECT_FALSE(under.ambiguous);
  }
}

// direct_light with shadows: never brighter than without, darker in the blocks' shadows, equal
// where nothing is in the way; few ambiguous pixels (printed).
TEST(ShadowRays, DirectLightWithShadowsOnTheCornellBox) {
  const SurfaceScene scene = make_cornell_box();
  reference::DirectLightOptions shadowed;
  shadowed.shadows = true;
  const auto a = reference::direct_light_image(scene, scene.camera, 48, 36);
  const auto b = reference::direct_light_image(scene, scene.camera, 48, 36, 0.0, 0.0, shadowed);
  size_t darker = 0, ambiguous = 0, rays = 0;
  for (size_t i = 0; i < a.pixels.size(); ++i) {
    for (int c = 0; c < 3; ++c) EXPECT_LE(b.pixels[i].radiance[c], a.pixels[i].radiance[c] * (1.0 + 1e-12)) << i;
    darker += b.pixels[i].radiance.x < a.pixels[i].radiance.x * (1.0 - 1e-9);
    ambiguous += b.pixels[i].shadow_ambiguous;
    rays += b.pixels[i].shadow_rays;
    EXPECT_EQ(a.pixels[i].shadow_rays, 0u);
  }
  EXPECT_GT(darker, a.pixels.size() / 20);
  EXPECT_LT(double(ambiguous), 0.02 * double(a.pixels.size()));
  std::printf("[ twin ] %zu of %zu pixels darkened by shadows, %zu ambiguous, %zu shadow segments\n", darker, a.pixels.size(), ambiguous, rays);
}

}  // namespace
}  // namespace prismoid::test
