// The pixels a cell can cover, conservatively: the bounds of its part beyond the near plane
// (its corners there and the points where its edges cross the plane) in pixels, widened by a
// pixel, which covers the float rounding of the projection many times over; and, for a cell
// the near plane does not cut, the edges of its silhouette (the convex hull of its projected
// corners), so a tile of the bounds that the silhouette misses by more than a pixel holds no
// pair. The tile raster tests every pixel's own ray exactly, so bounds only need to hold every
// pixel the cell can cover, and two passes deciding a tile that lies within a pixel of the
// silhouette differently (rounding) lose no covered pixel. The caller declares `frame`.
#ifndef PRISMOID_CI_CELL_BOUNDS_GLSL
#define PRISMOID_CI_CELL_BOUNDS_GLSL

struct CellBounds {
  bool visible;   // some pixel can see the cell's part beyond the near plane
  uvec2 lo, hi;   // the pixels, inclusive
  float nearest;  // the part's nearest depth minus the mesh origin's
  uint edges;     // silhouette edges (0: the near plane cuts the cell, the bounds are all)
  vec3 edge[6];   // per edge: unit outward normal n (xy) and c, n.p + c > 0 outside (pixels)
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
  b.edges = 0u;
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
  if (ahead[0] && ahead[1] && ahead[2] && ahead[3]) {
    // Every line through two projected corners with the other two on one side (or on it) is an
    // edge of the hull; the diagonals of a quadrilateral silhouette have them on both sides.
    vec2 p[4];
    for (int i = 0; i < 4; ++i) p[i] = to_pixels(cam[i]);
    for (int i = 0; i < 3; ++i)
      for (int j = i + 1; j < 4; ++j) {
        vec2 along = p[j] - p[i];
        float len = length(along);
        if (!(len > 0.0)) continue;
        vec2 n = vec2(along.y, -along.x) / len;
        int k = (i + 1 == j) ? ((j + 1) & 3) : (i + 1), l = 6 - i - j - k;
        float sk = dot(n, p[k] - p[i]), sl = dot(n, p[l] - p[i]);
        if (sk <= 0.0 && sl <= 0.0) b.edge[b.edges++] = vec3(n, -dot(n, p[i]));
        else if (sk >= 0.0 && sl >= 0.0) b.edge[b.edges++] = vec3(-n, dot(n, p[i]));
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

// Whether the cell's silhouette comes within a pixel of one of the tile's pixel centres.
bool tile_touched(CellBounds b, uvec2 tile) {
  vec2 centre = vec2(tile * PRISMOID_CI_TILE) + 0.5 * float(PRISMOID_CI_TILE);
  float half_extent = 0.5 * float(PRISMOID_CI_TILE - 1u);  // from the tile's centre to its corner pixels' centres
  for (uint e = 0u; e < b.edges; ++e) {
    vec3 edge = b.edge[e];
    if (dot(edge.xy, centre) + edge.z - half_extent * (abs(edge.x) + abs(edge.y)) > 1.0) return false;
  }
  return true;
}

#endif
