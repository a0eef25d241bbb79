#version 460
// Compute interval backend, bin-cells step 1: each cell's conservative screen bounds in
// tiles, the depth key that orders it within a tile, and how many (tile, cell) pairs it needs.
// The bounds are those of the cell's part beyond the near plane (its corners there and the
// points where its edges cross the plane), widened by a pixel, which covers the float rounding
// of the projection many times over: the tile raster tests every pixel's own ray exactly, so
// bounds only need to hold every pixel the cell can cover.
#extension GL_GOOGLE_include_directive : require
#include "../../shared/volume.h"
#include "../../shared/compute_intervals.h"

layout(local_size_x = PRISMOID_CI_WORKGROUP) in;
#include "mesh_input.glsl"
layout(std430, set = 0, binding = PRISMOID_CI_BINDING_BINS) writeonly buffer Bins { uvec4 bins[]; };
layout(std430, set = 0, binding = PRISMOID_CI_BINDING_OFFSETS) writeonly buffer Offsets { uint offsets[]; };

vec2 to_pixels(vec3 cam) {
  vec4 clip = frame.projection * vec4(cam, 1.0);
  return (clip.xy / clip.w * 0.5 + 0.5) * frame.viewport.xy;
}

uvec4 bin_of(CellInput c) {
  if (!c.drawn) return uvec4(0u);
  // Depth along the viewing axis; a corner counts as beyond the near plane a little before
  // it, so rounding never drops a part the raster keeps.
  float near_lo = frame.ray_scale.z * (1.0 - 1.0 / 65536.0);
  vec3 cam[4];
  bool ahead[4];
  bool any_ahead = false;
  mat3 rotation = mat3(frame.view);
  // The nearest depth, relative to the mesh origin's (mesh-local, so exact to the mesh's size
  // however far the eye is), clamped to the near plane's: the key within a tile.
  float nearest = 3.4e38;
  for (int i = 0; i < 4; ++i) {
    cam[i] = (frame.view * vec4(c.position[i], 1.0)).xyz;
    ahead[i] = -cam[i].z > near_lo;
    any_ahead = any_ahead || ahead[i];
    nearest = min(nearest, -(rotation * c.position[i]).z);
  }
  if (!any_ahead) return uvec4(0u);
  nearest = max(nearest, frame.ray_scale.w);
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
  vec2 size = frame.viewport.xy;
  // NaN bounds (cannot happen for finite positions) cover everything rather than nothing.
  lo = clamp(floor(lo) - 1.0, vec2(0.0), size - 1.0);
  hi = clamp(floor(hi) + 1.0, vec2(0.0), size - 1.0);
  if (isnan(lo.x) || isnan(lo.y)) lo = vec2(0.0);
  if (isnan(hi.x) || isnan(hi.y)) hi = size - 1.0;
  if (any(greaterThan(lo, hi))) return uvec4(0u);
  uvec2 t0 = uvec2(lo) / PRISMOID_CI_TILE, t1 = uvec2(hi) / PRISMOID_CI_TILE;
  uint max_key = push.tiles.z >= 32u ? 0xFFFFFFFFu : (1u << push.tiles.z) - 1u;
  float key = clamp((nearest - push.depth.x) * push.depth.y, 0.0, float(max_key));
  uint pairs = (t1.x - t0.x + 1u) * (t1.y - t0.y + 1u);
  return uvec4(t0.x | (t1.x << 16), t0.y | (t1.y << 16), min(uint(key), max_key), pairs);
}

void main() {
  uint count = frame.counts.x;
  for (uint cell = gl_GlobalInvocationID.x; cell < count; cell += gl_NumWorkGroups.x * PRISMOID_CI_WORKGROUP) {
    uvec4 bin = bin_of(load_cell(cell));
    bins[cell] = bin;
    offsets[cell] = bin.w;
  }
}
