// The triangle-ID atlas rasterized in compute (FastAtlas, appendix A, done without the
// rasterizer): a visible triangle covers the texels whose centres, mapped back to the screen by
// its chart's map, lie inside its projection and on the screen. Coverage is tested with the
// triangle's homogeneous 2D edge functions (Olano and Greer, "Triangle Scan Conversion using 2D
// Homogeneous Coordinates"): no division by w, so triangles crossing the eye's plane need no
// clipping, and a point is covered iff its ray meets the triangle in front of the eye. Why
// compute: on the GPU machine graphics work runs on 2 TPCs, and two draws of a 1.2 M-triangle
// atlas took 3.2 ms at 3840 x 2160 (docs/results.md).
//
// Watertight: the edge function of an edge is the dot product of the pixel with the cross
// product of its two corners; the neighbour across the edge computes the same cross product with
// its corners swapped, which IEEE arithmetic negates exactly (`precise` forbids fusing one side
// into an fma and not the other). Both sides test >= 0, so a texel centre on a shared edge is
// covered by both (depth and then the lower triangle decide), never by neither.
//
// Texels whose centres are pixel centres where the visibility pass found a triangle of the chart
// were claimed before (claim.comp): their depth, PRISMOID_FA_CLAIMED, is above every other.
//
// Deterministic: each texel keeps the largest depth (reversed z) under atomicMax, then the
// triangle with exactly that depth under atomicMin; neither depends on invocation order. The
// depth is recomputed by the same function in both passes, so the comparison is bit for bit.
#ifndef PRISMOID_FA_RASTER_GLSL
#define PRISMOID_FA_RASTER_GLSL

#include "fa_triangle.glsl"

layout(set = 0, binding = PRISMOID_FA_BINDING_ID_ATLAS, r32ui) uniform uimage2D fa_id_atlas;
layout(set = 0, binding = PRISMOID_FA_BINDING_DEPTH_ATLAS, r32ui) uniform uimage2D fa_depth_atlas;
layout(std430, set = 0, binding = PRISMOID_FA_BINDING_RASTER_CHUNKS) buffer FaChunkBuffer { uvec2 fa_chunks[]; };

// A visible triangle set up for its chart's texels.
struct FaRasterTriangle {
  vec3 edge[3];    // homogeneous edge functions over (pixel x, pixel y, 1), times the sign of det
  vec3 z, w;       // the corners' clip z and w (depth = dot(E, z) / dot(E, w))
  FaChartMap map;
  ivec2 lo, hi;    // texels to test (inclusive), inside the chart's placed box
};

// False when the triangle covers no texel (degenerate on the screen, nothing of it there, or no
// atlas this frame).
bool fa_raster_setup(uint t, out FaRasterTriangle r) {
  r.edge[0] = r.edge[1] = r.edge[2] = vec3(0.0);
  r.z = r.w = vec3(0.0);
  r.lo = ivec2(0);
  r.hi = ivec2(-1);
  uint root = fa_parent[t];
  if (root == PRISMOID_FA_NONE || fa_state.charts.z == 0u) return false;
  r.map = fa_chart_map(root);
  precise vec3 c[3];
  for (uint k = 0u; k < 3u; ++k) {
    precise vec4 clip = frame.projection * (frame.view * vec4(triangle_corner(t, k), 1.0));
    // (pixel x, pixel y) * w and w: pixels from the top left, as gl_FragCoord counts them.
    c[k] = vec3(0.5 * vec2(fa_push.image.xy) * (clip.xy + clip.w), clip.w);
    r.z[k] = clip.z;
    r.w[k] = clip.w;
  }
  precise vec3 e0 = cross(c[1], c[2]), e1 = cross(c[2], c[0]), e2 = cross(c[0], c[1]);
  precise float det = dot(c[0], e0);
  if (!(abs(det) > 0.0) || isinf(det) || isnan(det)) return false;  // edge-on: no area on the screen
  float s = det > 0.0 ? 1.0 : -1.0;  // two-sided: both windings cover
  r.edge[0] = e0 * s;
  r.edge[1] = e1 * s;
  r.edge[2] = e2 * s;
  vec2 lo_px, hi_px;
  if (!fa_screen_box(t, lo_px, hi_px)) return false;
  vec2 a = fa_to_atlas(r.map, lo_px), b = fa_to_atlas(r.map, hi_px);
  // Texel centres (i + 0.5) within the box, one texel wider for the box's rounding; the test
  // decides coverage, the box only bounds the loop.
  r.lo = ivec2(floor(min(a, b) - 0.5));
  r.hi = ivec2(ceil(max(a, b) - 0.5));
  uvec4 p = fa_placed[root];
  r.lo = max(r.lo, ivec2(p.xy));
  r.hi = min(r.hi, ivec2(p.xy + uvec2(p.z & 0x7fffffffu, p.w)) - 1);
  return r.hi.x >= r.lo.x && r.hi.y >= r.lo.y;
}

// Whether the triangle covers texel `texel`, and its depth there (reversed z, float bits).
bool fa_raster_cover(FaRasterTriangle r, ivec2 texel, out uint depth_bits) {
  depth_bits = 0u;
  vec2 p = fa_to_screen(r.map, vec2(texel) + 0.5);
  if (!(p.x >= 0.0 && p.y >= 0.0 && p.x <= float(fa_push.image.x) && p.y <= float(fa_push.image.y))) return false;  // off the screen
  precise vec3 q = vec3(p, 1.0);
  precise vec3 e = vec3(dot(r.edge[0], q), dot(r.edge[1], q), dot(r.edge[2], q));
  // Inside and in front of the eye: every edge function of det's sign, and not all zero.
  if (!(e.x >= 0.0 && e.y >= 0.0 && e.z >= 0.0 && e.x + e.y + e.z > 0.0)) return false;
  precise float depth = dot(e, r.z) / dot(e, r.w);
  if (!(depth >= 0.0 && depth <= 1.0)) return false;  // nearer than the near plane (or not finite)
  depth_bits = floatBitsToUint(depth);
  return true;
}

// One texel of triangle t: the depth pass keeps the nearest depth, the ID pass the triangle
// whose depth is that one (the lower of two at the same depth).
void fa_raster_texel(FaRasterTriangle r, uint t, ivec2 texel, bool id_pass) {
  uint depth;
  if (!fa_raster_cover(r, texel, depth)) return;
  if (!id_pass) imageAtomicMax(fa_depth_atlas, texel, depth);
  else if (imageLoad(fa_depth_atlas, texel).x == depth) imageAtomicMin(fa_id_atlas, texel, t);
}

#endif
