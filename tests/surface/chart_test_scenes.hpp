#pragma once
// Small helpers the chart tests share (test_texel_atlas, test_meshlets): 2D orientation of
// chart triangles and scenes assembled from meshes.
#include <array>
#include <string>
#include <utility>
#include <vector>

#include <glm/vec2.hpp>

#include <gtest/gtest.h>

#include "scene/input_error.hpp"
#include "scene/surface_mesh.hpp"
#include "scene/surface_scene.hpp"

namespace prismoid::test {

using Tri2 = std::array<glm::dvec2, 3>;

inline double cross2(const glm::dvec2& a, const glm::dvec2& b) { return a.x * b.y - a.y * b.x; }
// Twice the signed area of (a, b, p): positive when counter-clockwise.
inline double orient(const glm::dvec2& a, const glm::dvec2& b, const glm::dvec2& p) { return cross2(b - a, p - a); }
inline double area2(const Tri2& t) { return orient(t[0], t[1], t[2]); }

inline SceneMesh scene_mesh(const SurfaceMesh& s, const std::string& name) {
  SceneMesh m;
  m.name = name;
  m.positions = s.points;
  m.triangles = s.triangles;
  return m;
}

// A scene of `meshes` with one default material.
inline SurfaceScene scene_of(std::string name, std::vector<SceneMesh> meshes) {
  SurfaceScene scene;
  scene.name = std::move(name);
  scene.meshes = std::move(meshes);
  scene.materials.push_back({});
  return scene;
}

// `build()` throws InputError from `source` with `words` in its message.
template <typename Build>
void expect_input_error(Build&& build, const std::string& source, const std::string& words) {
  try {
    build();
    ADD_FAILURE() << "no error for " << words;
  } catch (const InputError& e) {
    EXPECT_EQ(e.source(), source);
    EXPECT_NE(std::string(e.what()).find(words), std::string::npos) << e.what();
  }
}

}  // namespace prismoid::test
