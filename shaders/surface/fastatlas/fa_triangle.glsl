// A visible triangle's box on the screen, shared by the chart boxes (boxes.comp) and the ID
// atlas raster (fa_raster.glsl). Needs the scene's vertex buffers, the frame block and
// fastatlas.glsl.
#ifndef PRISMOID_FA_TRIANGLE_GLSL
#define PRISMOID_FA_TRIANGLE_GLSL

// The screen box (pixels, y down, not rounded) of the part of triangle t beyond the near plane
// (clipped against that one plane: a triangle or a quad remains), clamped to the viewport;
// false when nothing of it is on the screen. The CPU twin is fastatlas::triangle_box.
bool fa_screen_box(uint t, out vec2 lo_px, out vec2 hi_px) {
  float near = uintBitsToFloat(fa_push.pass.z);
  vec3 v[3];
  for (uint k = 0u; k < 3u; ++k) v[k] = (frame.view * vec4(triangle_corner(t, k), 1.0)).xyz;
  vec3 kept[4];
  int n = 0;
  for (int i = 0; i < 3; ++i) {
    vec3 p = v[i], q = v[(i + 1) % 3];
    float dp = -p.z - near, dq = -q.z - near;  // >= 0: beyond the near plane
    if (dp >= 0.0) kept[n++] = p;
    if ((dp >= 0.0) != (dq >= 0.0)) kept[n++] = p + (q - p) * (dp / (dp - dq));
  }
  lo_px = vec2(0.0);
  hi_px = vec2(0.0);
  if (n == 0) return false;
  vec2 lo = vec2(1.0), hi = vec2(-1.0);  // normalized device coordinates, y up
  for (int i = 0; i < n; ++i) {
    float depth = max(-kept[i].z, near);
    vec2 ndc = vec2(kept[i].x / (depth * frame.camera_right.w), kept[i].y / (depth * frame.camera_up.w));
    lo = min(lo, ndc);
    hi = max(hi, ndc);
  }
  lo = max(lo, vec2(-1.0));
  hi = min(hi, vec2(1.0));
  if (!(hi.x > lo.x && hi.y > lo.y)) return false;
  vec2 size = vec2(fa_push.image.xy);
  lo_px = vec2((lo.x + 1.0) * 0.5 * size.x, (1.0 - hi.y) * 0.5 * size.y);
  hi_px = vec2((hi.x + 1.0) * 0.5 * size.x, (1.0 - lo.y) * 0.5 * size.y);
  return true;
}

#endif
