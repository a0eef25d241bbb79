#pragma once
// The opaque surface of the mixed-scene tests: one axis-aligned square, lit by a point light.
#include "scene/camera.hpp"
#include "scene/surface_scene.hpp"

namespace prismoid::test {

// The square z = z, x in [x0, x1], y in [y0, y1], facing +z.
struct Square {
  double z, x0, x1, y0, y1;
};

inline SceneMesh square_mesh(const Square& s) {
  SceneMesh m;
  m.name = "square";
  m.positions = {{s.x0, s.y0, s.z}, {s.x1, s.y0, s.z}, {s.x1, s.y1, s.z}, {s.x0, s.y1, s.z}};
  m.triangles = {{0, 1, 2}, {0, 2, 3}};
  return m;
}

// One square, lit by a point light at (0, 0, 3).
inline SurfaceScene square_scene(const Square& s) {
  SurfaceScene scene;
  scene.name = "square";
  scene.materials.push_back({});
  scene.meshes.push_back(square_mesh(s));
  scene.point_lights.push_back({{0.0, 0.0, 3.0}, {4.0, 4.0, 4.0}});
  return scene;
}

// `scene` with one more square (of the same material).
inline SurfaceScene with_square(SurfaceScene scene, const Square& s) {
  scene.meshes.push_back(square_mesh(s));
  return scene;
}

// A camera at `eye` looking at the origin, +y up, near plane 0.1.
inline Camera view_of_origin(const glm::dvec3& eye, double fovy_degrees) {
  Camera c;
  c.eye = eye;
  c.target = {0.0, 0.0, 0.0};
  c.fovy_degrees = fovy_degrees;
  c.near_distance = 0.1;
  return c;
}

// The view of the mixed scenes' tests: the eye a little off the z axis, 4 units out (the CLI
// tests' --eye 0.3,0.2,4 --target 0,0,0 --up 0,1,0 --fovy 40 --near 0.1).
inline Camera square_view() { return view_of_origin({0.3, 0.2, 4.0}, 40.0); }

}  // namespace prismoid::test
