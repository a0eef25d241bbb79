// The pixels a cell can cover, conservatively: the bounds of its part beyond the near plane
// (its corners there and the points where its edges cross the plane) in pixels, widened by a
// pixel, which covers the float rounding of the projection many times over. The tile raster
// tests every pixel's own ray exactly, so bounds only need to hold every pixel the cell can
// cover. The caller declares `frame`.
#ifndef PRISMOID_CI_CELL_BOUNDS_GLSL
#define PRISMOID_CI_CELL_BOUNDS_GLSL

struct CellBounds {
  bool visible;   // some pixel can see the cell's part beyond the near plane
  uvec2 lo, hi;   // the pixels, inclusive
  float nearest;  // the part's nearest depth minus the mesh origin's
};

vec2 to_pixels(vec3 cam) {
  vec4 clip = frame.projection * vec4(cam, 1.0);
  return (clip.xy / clip.w * 0.5 + 0.5) * frame.viewport.xy;
}

// `position`: the corners, mesh-local.
CellBounds cell_bounds(vec3 position[4]) {
  CellBounds b;
  b.visible = false;
  b.lo = uvec2(0u);
  b.hi = uvec2(0u);
  b.nearest = 0.0;
  // Depth along the viewing axis; a corner counts as beyond the near plane a little before
  // it, so rounding never drops a part the raster keeps.
  float near_lo = frame.ray_scale.z * (1.0 - 1.0 / 65536.0);
  vec3 cam[4];
  bool ahead[4];
  bool any_ahead = false;
  mat3 rotation = mat3(frame.view);
  // The nearest depth, relative to the mesh origin's (mesh-local, so exact to the mesh's size
  // however far the eye is), clamped to the near plane's.
  float nearest = 3.4e38;
  for (int i = 0; i < 4; ++i) {
    cam[i] = (frame.view * vec4(position[i], 1.0)).xyz;
    ahead[i] = -cam[i].z > near_lo;
    any_ahead = any_ahead || ahead[i];
    nearest = min(nearest, -(rotation * position[i]).z);
  }
  if (!any_ahead) return b;
  b.nearest = max(nearest, frame.ray_scale.w);
  vec2 lo = vec2(3.4e38), hi = vec2(-3.4e38);
  for (int i = 0; i < 4; ++i) {
    if (ahead[i]) {
      vec2 p = to_pixels(cam[i]);
      lo = min(lo, p);
      hi = max(hi, p);
      continue;
    }
    for (int j = 0; j < 4; ++j) {
      if (!ahead[j]) continue;
      // The edge from corner j (ahead) to corner i (behind) crosses depth near_lo.
      float dj = -cam[j].z, di = -cam[i].z;
      vec3 crossing = mix(cam[j], cam[i], (dj - near_lo) / (dj - di));
      crossing.z = -near_lo;
      vec2 p = to_pixels(crossing);
      lo = min(lo, p);
      hi = max(hi, p);
    }
  }
  // NaN bounds (cannot happen for finite positions) cover everything rather than nothing.
  vec2 last = frame.viewport.xy - 1.0;
  lo = floor(lo) - 1.0;
  hi = floor(hi) + 1.0;
  if (isnan(lo.x) || isnan(lo.y)) lo = vec2(0.0);
  if (isnan(hi.x) || isnan(hi.y)) hi = last;
  if (any(greaterThan(lo, last)) || any(lessThan(hi, vec2(0.0)))) return b;  // off screen
  lo = clamp(lo, vec2(0.0), last);
  hi = clamp(hi, vec2(0.0), last);
  b.visible = true;
  b.lo = uvec2(lo);
  b.hi = uvec2(hi);
  return b;
}

#endif
