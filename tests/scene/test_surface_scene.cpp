#include <gtest/gtest.h>

#include <cmath>
#include <numbers>

#include <glm/geometric.hpp>
#include <glm/trigonometric.hpp>

#include "scene/generators.hpp"
#include "scene/input_error.hpp"
#include "scene/surface_generators.hpp"
#include "scene/surface_scene.hpp"

namespace prismoid {
namespace {

// One unlit white quad in the z = 0 plane.
SurfaceScene unlit_quad() {
  SurfaceScene s;
  s.name = "quad";
  s.materials = {{"white", glm::dvec3(1.0), glm::dvec3(0.0), 1.0, glm::dvec3(0.0)}};
  SceneMesh m;
  m.positions = {{-1, -1, 0}, {1, -1, 0}, {1, 1, 0}, {-1, 1, 0}};
  m.triangles = {{0, 1, 2}, {0, 2, 3}};
  s.meshes.push_back(m);
  s.camera.eye = {0, 0, 3};
  s.camera.target = {0, 0, 0};
  return s;
}

glm::dvec3 winding_normal(const SceneMesh& m, size_t t) {
  const auto& p = m.positions;
  const auto& i = m.triangles[t];
  return glm::normalize(glm::cross(p[i[1]] - p[i[0]], p[i[2]] - p[i[0]]));
}

TEST(SurfaceScene, SceneWithoutLightGetsAKeyLightAndASky) {
  const SurfaceScene dark = unlit_quad();
  EXPECT_FALSE(has_light(dark));
  const SurfaceScene lit = with_default_lighting(dark, dark.camera);
  EXPECT_TRUE(has_light(lit));
  ASSERT_EQ(lit.directional_lights.size(), 1u);
  EXPECT_TRUE(lit.point_lights.empty());
  // The key light arrives from above the camera and to its left, about 40 degrees off the view
  // axis, with irradiance pi * kHeadlightScale.
  const glm::dvec3 forward = glm::normalize(dark.camera.target - dark.camera.eye);
  const glm::dvec3 right = glm::normalize(glm::cross(forward, dark.camera.up));
  const glm::dvec3 up = glm::cross(right, forward);
  const glm::dvec3 travel = glm::normalize(lit.directional_lights[0].direction);
  EXPECT_NEAR(glm::degrees(std::acos(glm::dot(travel, forward))), 39.8, 0.5);
  EXPECT_LT(glm::dot(travel, up), -0.5);   // travelling down: it comes from above
  EXPECT_GT(glm::dot(travel, right), 0.3);  // travelling right: it comes from the left
  EXPECT_DOUBLE_EQ(lit.directional_lights[0].irradiance.x, std::numbers::pi * kHeadlightScale);
  // The sky is brighter above than below, and nowhere black.
  EXPECT_GT(lit.sky.radiance({0, 1, 0}).x, lit.sky.radiance({0, -1, 0}).x);
  EXPECT_DOUBLE_EQ(lit.sky.radiance({0, 1, 0}).y, kDefaultSkyTop);
  EXPECT_DOUBLE_EQ(lit.sky.radiance({0, -1, 0}).z, kDefaultSkyBottom);
  EXPECT_NO_THROW(validate(lit));
}

TEST(SurfaceScene, SceneWithAnyLightIsLeftAsItIs) {
  SurfaceScene point = unlit_quad();
  point.point_lights.push_back({{0, 0, 1}, glm::dvec3(1.0)});
  SurfaceScene directional = unlit_quad();
  directional.directional_lights.push_back({{0, 0, -1}, {0.0, 0.5, 0.0}});
  SurfaceScene sky = unlit_quad();
  sky.sky.bottom = {0.0, 0.0, 0.1};
  SurfaceScene emissive = unlit_quad();
  emissive.materials[0].emission = {0.0, 2.0, 0.0};
  for (const SurfaceScene* s : {&point, &directional, &sky, &emissive}) {
    EXPECT_TRUE(has_light(*s));
    const SurfaceScene after = with_default_lighting(*s, s->camera);
    EXPECT_EQ(after.directional_lights.size(), s->directional_lights.size());
    EXPECT_EQ(after.sky.top, s->sky.top);
    EXPECT_EQ(after.sky.bottom, s->sky.bottom);
  }
}

TEST(SurfaceScene, LightsWithoutPowerDoNotCount) {
  // Zero-power lights, an emissive material no triangle uses, and an emissive triangle of zero
  // area give no light: the rule must still apply.
  SurfaceScene s = unlit_quad();
  s.point_lights.push_back({{0, 0, 1}, glm::dvec3(0.0)});
  s.directional_lights.push_back({{0, 0, -1}, glm::dvec3(0.0)});
  s.materials.push_back({"unused glow", glm::dvec3(0.5), glm::dvec3(0.0), 1.0, glm::dvec3(3.0)});
  SceneMesh needle;
  needle.positions = {{0, 0, 0}, {1, 1, 1}, {2, 2, 2}};  // collinear
  needle.triangles = {{0, 1, 2}};
  needle.material = 1;
  s.meshes.push_back(needle);
  EXPECT_NO_THROW(validate(s));
  EXPECT_FALSE(has_light(s));
  EXPECT_EQ(with_default_lighting(s, s.camera).directional_lights.size(), 2u);
}

TEST(SurfaceScene, ValidateNamesTheProblem) {
  auto expect_error = [](SurfaceScene s, const std::string& words) {
    try {
      validate(s);
      ADD_FAILURE() << "no error for: " << words;
    } catch (const InputError& e) {
      EXPECT_NE(std::string(e.what()).find(words), std::string::npos) << e.what();
      EXPECT_EQ(e.source(), "quad");
    }
  };
  SurfaceScene s = unlit_quad();
  s.meshes[0].triangles.push_back({0, 1, 7});
  expect_error(s, "triangle index 7 out of range");
  s = unlit_quad();
  s.meshes[0].material = 3;
  expect_error(s, "material index 3 out of range");
  s = unlit_quad();
  s.materials[0].albedo.y = 1.5;
  expect_error(s, "albedo must lie in [0, 1]");
  s = unlit_quad();
  s.materials[0].roughness = std::nan("");
  expect_error(s, "roughness");
  s = unlit_quad();
  s.materials[0].emission.z = -1.0;
  expect_error(s, "emission");
  s = unlit_quad();
  s.meshes[0].positions[2].x = std::numeric_limits<double>::infinity();
  expect_error(s, "position is not finite");
  s = unlit_quad();
  s.meshes[0].normals = {{0, 0, 1}};
  expect_error(s, "one normal per position");
  s = unlit_quad();
  s.meshes[0].color_binding = ColorBinding::PerTriangle;
  s.meshes[0].colors = {glm::dvec3(1.0)};
  expect_error(s, "has 1 colours where its binding needs 2");
  s = unlit_quad();
  s.directional_lights.push_back({glm::dvec3(0.0), glm::dvec3(1.0)});
  expect_error(s, "non-zero direction");
  s = unlit_quad();
  s.materials.clear();
  expect_error(s, "no material");
}

// Radiometric values beyond float32's largest value over 2^32 (the headroom for what shading
// multiplies them by) are refused before anything is shaded, each named with its size and the
// limit; the limit itself is accepted.
TEST(SurfaceScene, RadiometricValuesBeyondFloatsHeadroomAreRefused) {
  auto expect_error = [](const SurfaceScene& s, const std::string& words) {
    try {
      validate_float_range(s);
      ADD_FAILURE() << "no error for: " << words;
    } catch (const InputError& e) {
      EXPECT_NE(std::string(e.what()).find(words), std::string::npos) << e.what();
      EXPECT_NE(std::string(e.what()).find("is beyond 7.92e+28"), std::string::npos) << e.what();
    }
  };
  expect_error(make_furnace(0.5, 1e300, 1), "material 0 (furnace): emission 1e+300");
  EXPECT_NO_THROW(validate_float_range(make_furnace(0.5, kMaxRadiometricValue, 1)));
  SurfaceScene s = unlit_quad();
  s.point_lights.push_back({glm::dvec3(0.0, 0.0, 1.0), glm::dvec3(1.0, 2e29, 1.0)});
  expect_error(s, "point light 0: intensity 2e+29");
  s = unlit_quad();
  s.directional_lights.push_back({glm::dvec3(0.0, 0.0, -1.0), glm::dvec3(1e35)});
  expect_error(s, "directional light 0: irradiance 1e+35");
  s = unlit_quad();
  s.sky.bottom = glm::dvec3(1e30);
  expect_error(s, "the sky: radiance 1e+30");
}

TEST(SurfaceGenerators, CornellBoxMatchesThePublishedData) {
  const SurfaceScene s = make_cornell_box();
  EXPECT_NO_THROW(validate(s));
  ASSERT_EQ(s.meshes.size(), 8u);
  size_t triangles = 0;
  for (const auto& m : s.meshes) triangles += m.triangles.size();
  EXPECT_EQ(triangles, 2u * (5 + 5 + 5 + 1));  // floor, ceiling, 3 walls, 2 blocks of 5 quads, light
  // The camera: 35 mm lens on 25 mm film.
  EXPECT_NEAR(s.camera.fovy_degrees, 39.3077, 1e-4);
  EXPECT_EQ(s.camera.eye, glm::dvec3(278.0, 273.0, -800.0));
  // The light: 130 x 105 mm, hanging just below the ceiling, wound to face down, and the only
  // emitter.
  const SceneMesh& light = s.meshes.back();
  EXPECT_EQ(s.materials[light.material].emission, glm::dvec3(17.0, 12.0, 4.0));
  double area = 0.0;
  for (size_t t = 0; t < light.triangles.size(); ++t) {
    EXPECT_NEAR(winding_normal(light, t).y, -1.0, 1e-15);
    const auto& p = light.positions;
    const auto& i = light.triangles[t];
    area += 0.5 * glm::length(glm::cross(p[i[1]] - p[i[0]], p[i[2]] - p[i[0]]));
    for (uint32_t v : i) EXPECT_DOUBLE_EQ(p[v].y, 548.8 - kCornellLightDrop);
  }
  EXPECT_NEAR(area, 130.0 * 105.0, 1e-9);
  for (size_t m = 0; m + 1 < s.meshes.size(); ++m) EXPECT_EQ(s.materials[s.meshes[m].material].emission, glm::dvec3(0.0));
  EXPECT_EQ(s.materials[1].albedo, glm::dvec3(0.63, 0.065, 0.05));  // red
  EXPECT_EQ(s.meshes[4].name, "left wall");
  EXPECT_EQ(s.meshes[4].material, 1u);
}

TEST(SurfaceGenerators, FurnaceIsClosedAndFacesItsCentre) {
  const SurfaceScene s = make_furnace(0.5, 2.0, 2);
  EXPECT_NO_THROW(validate(s));
  ASSERT_EQ(s.meshes.size(), 1u);
  const SceneMesh& m = s.meshes[0];
  EXPECT_EQ(m.triangles.size(), 20u * 16u);
  for (size_t t = 0; t < m.triangles.size(); ++t) {
    const auto& i = m.triangles[t];
    const glm::dvec3 centroid = (m.positions[i[0]] + m.positions[i[1]] + m.positions[i[2]]) / 3.0;
    EXPECT_LT(glm::dot(winding_normal(m, t), centroid), 0.0) << "triangle " << t << " faces outwards";
  }
  // Closed: every edge is used by exactly two triangles, once in each direction (consistent winding).
  std::map<std::pair<uint32_t, uint32_t>, int> directed;
  for (const auto& i : m.triangles)
    for (int k = 0; k < 3; ++k) ++directed[{i[size_t(k)], i[size_t((k + 1) % 3)]}];
  for (const auto& [edge, count] : directed) {
    EXPECT_EQ(count, 1);
    EXPECT_EQ(directed.count({edge.second, edge.first}), 1u);
  }
  EXPECT_EQ(s.materials[0].albedo, glm::dvec3(0.5));
  EXPECT_EQ(s.materials[0].emission, glm::dvec3(2.0));
  EXPECT_DOUBLE_EQ(furnace_radiance(0.5, 2.0), 4.0);
  EXPECT_EQ(s.camera.eye, glm::dvec3(0.0));
}

TEST(SurfaceGenerators, NamedScenesParseAndRejectMalformedNames) {
  EXPECT_TRUE(is_named_surface_scene("cornell-box"));
  EXPECT_TRUE(is_named_surface_scene("furnace:0.5"));
  EXPECT_FALSE(is_named_surface_scene("bunny.off"));
  EXPECT_EQ(make_named_surface_scene("cornell-box").meshes.size(), 8u);
  const SurfaceScene f = make_named_surface_scene("furnace:0.25:3");
  EXPECT_EQ(f.materials[0].albedo, glm::dvec3(0.25));
  EXPECT_EQ(f.materials[0].emission, glm::dvec3(3.0));
  EXPECT_EQ(make_named_surface_scene("furnace:0.9").materials[0].emission, glm::dvec3(1.0));
  for (const char* bad : {"furnace:", "furnace:1", "furnace:-0.1", "furnace:abc", "furnace:0.5:0", "furnace:0.5:x", "cornell"})
    EXPECT_THROW(make_named_surface_scene(bad), InputError) << bad;
}

TEST(SurfaceGenerators, SurfaceFromAFileGetsTheDefaultMaterialAndNoLight) {
  const SurfaceMesh sphere = make_icosphere(glm::dvec3(10.0, 0.0, 0.0), 2.0, 1);
  EXPECT_EQ(sphere.triangles.size(), 80u);
  const SurfaceScene s = make_surface_scene(sphere);
  EXPECT_NO_THROW(validate(s));
  EXPECT_EQ(s.materials.size(), 1u);
  EXPECT_EQ(s.materials[0].albedo, default_surface_material().albedo);
  EXPECT_FALSE(has_light(s));
  EXPECT_NEAR(glm::length(s.camera.target - glm::dvec3(10.0, 0.0, 0.0)), 0.0, 1e-12);
  EXPECT_TRUE(s.meshes[0].normals.empty());
}

}  // namespace
}  // namespace prismoid
