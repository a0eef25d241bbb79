// A surface point rebuilt from a global triangle index and barycentric weights, for passes
// that shade away from the rasterizer (texel and shadel shading, ray hits): the same inputs
// forward.frag gets from interpolated vertex attributes, read from the scene's vertex and
// index buffers instead. Include after defining PRISMOID_SURFACE_VERTEX_BUFFERS (so
// scene_bindings.glsl declares those buffers) and before or after shading.glsl.
#ifndef PRISMOID_SURFACE_POINT_GLSL
#define PRISMOID_SURFACE_POINT_GLSL

#ifndef PRISMOID_SURFACE_VERTEX_BUFFERS
#error "define PRISMOID_SURFACE_VERTEX_BUFFERS before including surface_point.glsl"
#endif
#include "shading.glsl"

vec3 vertex_position(uint v) { return vec3(vertex_positions[3u * v], vertex_positions[3u * v + 1u], vertex_positions[3u * v + 2u]); }
vec3 vertex_normal(uint v) { return vec3(vertex_attributes[6u * v], vertex_attributes[6u * v + 1u], vertex_attributes[6u * v + 2u]); }
vec3 vertex_color(uint v) { return vec3(vertex_attributes[6u * v + 3u], vertex_attributes[6u * v + 4u], vertex_attributes[6u * v + 5u]); }
uvec3 triangle_vertices(uint triangle) {
  return uvec3(triangle_indices[3u * triangle], triangle_indices[3u * triangle + 1u], triangle_indices[3u * triangle + 2u]);
}

// The global triangle index of a ray hit: mesh = gl_InstanceCustomIndexEXT, primitive =
// gl_PrimitiveID (renderer/rt builds one instance per mesh).
uint global_triangle(uint mesh, uint primitive) { return scene_meshes[mesh].info.x + primitive; }

// Scene-local position at barycentric weights (w0, w1, w2) of the triangle's corners.
vec3 triangle_point(uint triangle, vec3 bary) {
  uvec3 v = triangle_vertices(triangle);
  return bary.x * vertex_position(v.x) + bary.y * vertex_position(v.y) + bary.z * vertex_position(v.z);
}

// Everything shade_surface_point needs at a point of a triangle seen from `eye` (both
// scene-local): as forward.frag computes it from rasterized attributes.
struct ShadingInput {
  SurfacePoint point;
  ShadingMaterial material;
  vec3 emission;
};
ShadingInput shading_input_at(uint triangle, vec3 bary, vec3 position, vec3 eye) {
  uvec3 v = triangle_vertices(triangle);
  SurfaceTriangleGpu tri = triangles[triangle];
  vec3 normal = bary.x * vertex_normal(v.x) + bary.y * vertex_normal(v.y) + bary.z * vertex_normal(v.z);
  vec3 color = bary.x * vertex_color(v.x) + bary.y * vertex_color(v.y) + bary.z * vertex_color(v.z);
  ShadingInput s;
  s.point = make_surface_point(position, tri.normal.xyz, normal, eye, triangle);
  SurfaceMaterialGpu material = materials[tri.info.x];
  s.material = shading_material(material, color * tri.color.rgb);
  s.emission = material.emission.rgb;
  return s;
}
ShadingInput shading_input(uint triangle, vec3 bary, vec3 eye) {
  return shading_input_at(triangle, bary, triangle_point(triangle, bary), eye);
}

#endif
