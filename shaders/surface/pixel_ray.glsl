// Pixels to surface points for the texture-space backends (Htex, texel shading): the pixel's ray
// (the convention of sky.frag and reference::ray_direction: row 0 at the top) and where it meets
// a triangle's plane. Needs the scene's vertex buffers (PRISMOID_SURFACE_VERTEX_BUFFERS) and the
// frame block.
#ifndef PRISMOID_SURFACE_PIXEL_RAY_GLSL
#define PRISMOID_SURFACE_PIXEL_RAY_GLSL

vec3 pixel_direction(vec2 frag_coord) {
  vec2 ndc = (frag_coord + frame.subpixel.xy) * frame.viewport.zw * 2.0 - 1.0;
  return frame.camera_forward.xyz + ndc.x * frame.camera_right.w * frame.camera_right.xyz - ndc.y * frame.camera_up.w * frame.camera_up.xyz;
}

vec3 triangle_corner(uint triangle, uint k) {
  uint v = triangle_indices[3u * triangle + k];
  return vec3(vertex_positions[3u * v], vertex_positions[3u * v + 1u], vertex_positions[3u * v + 2u]);
}

// Barycentric weights (w0, w1, w2) of the point where the ray through image point `frag_coord`
// meets the triangle's plane (Moeller-Trumbore without the inside test); false when the ray is
// parallel to the plane or the result is not finite.
bool pixel_barycentrics(uint triangle, vec2 frag_coord, out vec3 bary) {
  vec3 d = pixel_direction(frag_coord);
  vec3 p0 = triangle_corner(triangle, 0u);
  vec3 e1 = triangle_corner(triangle, 1u) - p0, e2 = triangle_corner(triangle, 2u) - p0;
  vec3 pv = cross(d, e2);
  float det = dot(e1, pv);
  vec3 tv = frame.eye.xyz - p0;
  float b1 = dot(tv, pv) / det;
  float b2 = dot(d, cross(tv, e1)) / det;
  bary = vec3(1.0 - b1 - b2, b1, b2);
  return !(det == 0.0) && !any(isnan(bary)) && !any(isinf(bary));
}

// The nearest weights inside the triangle (the rasterizer covers pixels whose ray meets the plane
// a rounding error outside): negative weights to 0, renormalized; w0 = 1 - w1 - w2 exactly as the
// gather rebuilds it from the stored w1, w2.
vec3 clamp_to_triangle(vec3 b) {
  b = max(b, vec3(0.0));
  float sum = b.x + b.y + b.z;
  b = sum > 0.0 ? b / sum : vec3(1.0 / 3.0);
  return vec3(1.0 - b.y - b.z, b.y, b.z);
}

// The sky seen through image point `frag_coord` (sky.frag's gradient).
vec3 pixel_sky(vec2 frag_coord) {
  vec3 d = normalize(pixel_direction(frag_coord));
  float t = 0.5 * (1.0 + dot(d, frame.sky_up.xyz));
  return frame.sky_bottom.rgb + (frame.sky_top.rgb - frame.sky_bottom.rgb) * t;
}

#endif
