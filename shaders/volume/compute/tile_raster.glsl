// Compute interval backend, tile-raster: one 8x8 workgroup per 8x8-pixel tile. The tile's
// cells, in the order of their depth keys, are set up a batch at a time in shared memory
// (one invocation per cell), and every pixel finds each cell's interval on its own ray:
// exactly, by the cell's four face planes, like the CPU reference (reference/tet_ray.cpp),
// then clipped at the near plane, which covers cells the plane cuts and an eye inside the
// mesh. The interval is then integrated by the very functions the mesh shader's fragment
// stages call (segment_emission.glsl, march_interval.glsl, isosurface_hit.glsl). Each pixel's
// sum is formed in one invocation in a fixed order: images are deterministic.
//
// Precision. Everything is measured from the cell's first corner c, as the mesh shader does:
// depths along the ray relative to c's depth ("rel", exact to the cell's size however far the
// eye is), the field from its value at c. A face plane is set up from its three points in the
// order of their point indices, so the two cells sharing a face compute the same plane, up to
// its sign: a ray crossing the face leaves one cell exactly where it enters the other, and a
// ray lying in the plane is given to exactly one of them, by the reference's tie-break.
//
// Order. Colour composites each pixel's intervals in their own order of entry depth through a
// k-buffer of PRISMOID_CI_KBUFFER entries: the nearest is composited when it is full. An
// interval arriving nearer than one already composited is composited behind it and the pixel
// counted as inexact (PRISMOID_CI_STAT_INEXACT).
//
// Long lists. A tile holding more than a chunk of pairs (push.chunks.z) is split (tile_chunks.comp):
// its own workgroup rasters the first chunk and workgroups of a second dispatch the others,
// each into its slot of partial results (ChunkPartial), which tile_merge.comp combines in chunk
// order. Colour stays exact per pixel across chunks as long as no chunk composited an interval
// nearer than one an earlier chunk composited; a tile where one did is rastered again whole
// (PRISMOID_CI_LAUNCH_REDO).
//
// What each interval gives (PRISMOID_CI_*) is fixed per pipeline: the file including this body
// (tile_raster_*.comp) defines PRISMOID_CI_RASTER_MODE, so each variant carries only its own
// integration code (the others' loops and arrays cost registers and compile time).
#ifndef PRISMOID_CI_RASTER_MODE
#error "define PRISMOID_CI_RASTER_MODE (a PRISMOID_CI_* value) before including tile_raster.glsl"
#endif
#include "../../shared/volume.h"
#include "../../shared/compute_intervals.h"

layout(local_size_x = PRISMOID_CI_TILE, local_size_y = PRISMOID_CI_TILE) in;
#include "mesh_input.glsl"
layout(std430, set = 0, binding = PRISMOID_CI_BINDING_BINS) readonly buffer Bins { uvec4 bins[]; };
layout(std430, set = 0, binding = PRISMOID_BINDING_PREINTEGRATED) readonly buffer Table { vec4 texels[]; };
layout(std430, set = 0, binding = PRISMOID_BINDING_TRANSFER) readonly buffer Transfer { vec4 tf_samples[]; };
layout(std430, set = 0, binding = PRISMOID_CI_BINDING_VALUES) readonly buffer Values { uint values[]; };
layout(std430, set = 0, binding = PRISMOID_CI_BINDING_TILE_RANGES) readonly buffer TileRanges { uvec2 ranges[]; };
layout(std430, set = 0, binding = PRISMOID_CI_BINDING_STATS) buffer Stats { uint stats[]; };
layout(std430, set = 0, binding = PRISMOID_CI_BINDING_CHUNK_BASE) readonly buffer ChunkBase { uint chunk_base[]; };
layout(std430, set = 0, binding = PRISMOID_CI_BINDING_CHUNK_WORK) readonly buffer ChunkWork { uvec2 chunk_work[]; };
layout(std430, set = 0, binding = PRISMOID_CI_BINDING_SPLIT_TILES) readonly buffer SplitTiles { uint split_tiles[]; };
layout(std430, set = 0, binding = PRISMOID_CI_BINDING_PARTIALS) writeonly buffer Partials { ChunkPartial partials[]; };
layout(set = 0, binding = PRISMOID_CI_BINDING_OPTICAL_DEPTH, r32f) uniform writeonly image2D optical_depth_image;
layout(set = 0, binding = PRISMOID_CI_BINDING_EMISSION, rgba32f) uniform writeonly image2D emission_image;
layout(std430, set = 0, binding = PRISMOID_CI_BINDING_DEPTH_LIMIT) readonly buffer DepthLimit { float depth_limit[]; };

#define PRISMOID_INTERVAL_RAY_COMPUTE
#include "../analytic_field.glsl"
#include "../interval_ray.glsl"
#include "../segment_emission.glsl"
#include "../march_interval.glsl"
#include "../isosurface_hit.glsl"

// Faces listed opposite each corner (as tet_projection.glsl and the reference list them).
const uvec3 kFaces[4] = uvec3[4](uvec3(1, 2, 3), uvec3(0, 3, 2), uvec3(0, 1, 3), uvec3(0, 2, 1));

// One batch of set-up cells. Per face: the outward normal n (camera orientation) and the
// depth d0 of its first point p0 (first by point index); then n.xy . p0.xy (camera space) and
// p0's depth minus c's.
shared vec4 s_plane[PRISMOID_CI_BATCH][4];
shared vec2 s_plane_offset[PRISMOID_CI_BATCH][4];
shared vec4 s_origin[PRISMOID_CI_BATCH];    // c in camera space (xy), c's depth, the near plane's depth minus c's (+inf: not drawn)
shared vec4 s_gradient[PRISMOID_CI_BATCH];  // the field's gradient (camera orientation), the field at c
shared vec4 s_reference[PRISMOID_CI_BATCH]; // c mesh-local, c's depth minus the mesh origin's
shared vec2 s_range[PRISMOID_CI_BATCH];     // the field's least and greatest value in the cell
shared uvec2 s_pixels[PRISMOID_CI_BATCH];   // the pixels it can cover (cell_bounds.glsl): x0 | x1 << 16, y0 | y1 << 16

void set_up_cell(uint slot, uint cell) {
  CellInput c = load_cell(cell);
  mat3 rotation = mat3(frame.view);
  vec3 cam[4], offset[4];
  for (int i = 0; i < 4; ++i) {
    cam[i] = (frame.view * vec4(c.position[i], 1.0)).xyz;
    offset[i] = rotation * (c.position[i] - c.position[0]);
  }
  // The cell's orientation, once, in mesh-local coordinates: differences of nearby stored
  // positions, without the rotation's rounding, which for a needle's long faces is larger
  // than its volume. A flat cell has no inside.
  vec3 d1 = c.position[1] - c.position[0], d2 = c.position[2] - c.position[0], d3 = c.position[3] - c.position[0];
  float volume6 = dot(d1, cross(d2, d3));
  bool drawn = c.drawn && volume6 != 0.0;
  for (uint f = 0u; f < 4u; ++f) {
    // kFaces winds every face outward on a positively oriented cell. Its corners are taken in
    // the order of their point indices, so both cells sharing the face compute the same plane
    // from the same numbers, and the swaps' parity restores the winding.
    uvec3 k = kFaces[f];
    uint a = k.x, b = k.y, d = k.z, t;
    float outward = volume6 > 0.0 ? 1.0 : -1.0;
    if (c.points[b] < c.points[a]) { t = a; a = b; b = t; outward = -outward; }
    if (c.points[d] < c.points[b]) { t = b; b = d; d = t; outward = -outward; }
    if (c.points[b] < c.points[a]) { t = a; a = b; b = t; outward = -outward; }
    // The normal from mesh-local edges, then rotated: rotating a vector is well conditioned,
    // a cross product of two rotated long edges of a thin face is not.
    vec3 n = outward * (rotation * cross(c.position[b] - c.position[a], c.position[d] - c.position[a]));
    s_plane[slot][f] = vec4(n, -cam[a].z);
    s_plane_offset[slot][f] = vec2(dot(n.xy, cam[a].xy), -offset[a].z);
  }
  // The field's gradient (zero for a constant field), from the same mesh-local edges, rotated.
  vec3 gradient = vec3(0.0);
  float df1 = c.field[1] - c.field[0], df2 = c.field[2] - c.field[0], df3 = c.field[3] - c.field[0];
  if (drawn && (df1 != 0.0 || df2 != 0.0 || df3 != 0.0))
    gradient = rotation * ((df1 * cross(d2, d3) + df2 * cross(d3, d1) + df3 * cross(d1, d2)) / volume6);
  float near_c = frame.ray_scale.w + (rotation * c.position[0]).z;
  s_origin[slot] = vec4(cam[0].xy, -cam[0].z, drawn ? near_c : uintBitsToFloat(0x7F800000u));
  s_gradient[slot] = vec4(gradient, c.field[0]);
  s_reference[slot] = vec4(c.position[0], -(rotation * c.position[0]).z);
  s_range[slot] = vec2(min(min(c.field[0], c.field[1]), min(c.field[2], c.field[3])),
                       max(max(c.field[0], c.field[1]), max(c.field[2], c.field[3])));
  // Most cells cover a few of the tile's pixels: the others skip them before any plane test.
  // Their bounds are bin-cells' (a cell in a tile list is visible).
  s_pixels[slot] = bins[cell].xy;
}

bool may_cover(uint slot, uvec2 pixel) {
  uvec2 b = s_pixels[slot];
  return pixel.x >= (b.x & 0xFFFFu) && pixel.x <= (b.x >> 16) && pixel.y >= (b.y & 0xFFFFu) && pixel.y <= (b.y >> 16);
}

// The interval of the ray d * ray (d: depth along the viewing axis) inside set-up cell `slot`
// and beyond the near plane, as depths relative to c's.
bool cell_interval(uint slot, vec3 ray, out float enter, out float exit) {
  enter = s_origin[slot].w;
  exit = uintBitsToFloat(0x7F800000u);
  for (uint f = 0u; f < 4u; ++f) {
    vec4 plane = s_plane[slot][f];
    vec2 offset = s_plane_offset[slot][f];
    // The ray's signed distance from the plane at p0's depth (> 0 outside) and its rate per
    // unit of depth: the ray point d * ray minus p0 has no z at d = d0.
    float along = plane.x * ray.x + plane.y * ray.y;
    float rate = along - plane.z;
    float dist = along * plane.w - offset.x;
    if (rate == 0.0) {
      // The ray runs parallel to the face. When it lies exactly in the face's plane (a pixel ray
      // along a grid line of an axis-aligned mesh), both cells sharing the face would take it;
      // decide, as the reference does, as if the ray were moved by an infinitesimal step along a
      // fixed generic direction: exactly one of them keeps it, since the other computed the
      // same numbers with the opposite sign. Near that case, the two cells compute the same
      // crossing, so the ray leaves one where it enters the other.
      if (dist > 0.0 || (dist == 0.0 && dot(plane.xyz, push.tie_break.xyz) >= 0.0)) return false;
      continue;
    }
    float t = -dist / rate + offset.y;
    if (rate > 0.0) exit = min(exit, t);
    else enter = max(enter, t);
  }
  return exit > enter;
}

// The cell's linear field at relative depth `rel` on the ray, held to its range in the cell
// (where a nearly flat cell's gradient rounds large, the true value still lies in it).
float field_on_ray(uint slot, vec3 ray, float rel) {
  vec4 o = s_origin[slot], g = s_gradient[slot];
  vec2 lateral = o.z * ray.xy - o.xy;  // the ray's offset from c at c's depth (camera orientation)
  float value = g.w + dot(g.xy, lateral) + rel * dot(g.xyz, ray);
  return clamp(value, s_range[slot].x, s_range[slot].y);
}

// The k-buffer: entries sorted by key (entry depth relative to the mesh origin's), nearest first.
float kb_key[PRISMOID_CI_KBUFFER];
vec4 kb_value[PRISMOID_CI_KBUFFER];
uint kb_count;
vec4 composited;
float composited_key;  // the farthest key composited so far
float composited_min;  // the nearest
bool inexact;

void composite_next(float key, vec4 value) {
  composited = composite_under(composited, value);
  composited_key = max(composited_key, key);
  composited_min = min(composited_min, key);
}

void kb_insert(float key, vec4 value) {
  if (key < composited_key) inexact = true;
  if (kb_count == PRISMOID_CI_KBUFFER) {
    if (key <= kb_key[0]) {
      composite_next(key, value);
      return;
    }
    composite_next(kb_key[0], kb_value[0]);
    for (uint i = 1u; i < PRISMOID_CI_KBUFFER; ++i) {
      kb_key[i - 1u] = kb_key[i];
      kb_value[i - 1u] = kb_value[i];
    }
    kb_count = PRISMOID_CI_KBUFFER - 1u;
  }
  uint i = kb_count;
  for (; i > 0u && kb_key[i - 1u] > key; --i) {
    kb_key[i] = kb_key[i - 1u];
    kb_value[i] = kb_value[i - 1u];
  }
  kb_key[i] = key;
  kb_value[i] = value;
  ++kb_count;
}

// Pairs [first, end) of `tile`, to the image (slot PRISMOID_CI_UNSPLIT) or to a slot of partial
// results. Called in workgroup-uniform control flow: it synchronizes the workgroup.
void raster(uint tile, uint first_pair, uint end_pair, uint slot_out) {
  const float inf = uintBitsToFloat(0x7F800000u);
  kb_count = 0u;
  composited = vec4(0.0);
  composited_key = -inf;
  composited_min = inf;
  inexact = false;
  uvec2 pixel = uvec2(tile % push.tiles.x, tile / push.tiles.x) * PRISMOID_CI_TILE + gl_LocalInvocationID.xy;
  bool inside = pixel.x < push.options.y && pixel.y < push.options.z;
  // The pixel centre's ray, as interval_ray.glsl forms it from gl_FragCoord.
  vec2 ndc = (vec2(pixel) + 0.5) * frame.viewport.zw * 2.0 - 1.0;
  vec3 ray = vec3(ndc * frame.ray_scale.xy, -1.0);
  float length_per_depth = length(ray);
  // Opaque geometry ends the ray at this depth along the viewing axis (+inf: nowhere).
  float limit = inf;
  if (push.options.w == 1u && inside) limit = depth_limit[pixel.y * push.options.y + pixel.x];
  const uint mode = PRISMOID_CI_RASTER_MODE;
  float optical_depth = 0.0;
  float nearest_hit = inf;
  vec4 hit_value = vec4(0.0);

  for (uint first = first_pair; first < end_pair; first += PRISMOID_CI_BATCH) {
    barrier();  // the previous batch is no longer read
    uint local = gl_LocalInvocationIndex;
    if (first + local < end_pair) set_up_cell(local, values[first + local]);
    barrier();
    uint batch = min(uint(PRISMOID_CI_BATCH), end_pair - first);
    if (!inside) continue;
    for (uint slot = 0u; slot < batch; ++slot) {
      float enter, exit;
      if (!may_cover(slot, pixel) || !cell_interval(slot, ray, enter, exit)) continue;
      vec4 origin = s_origin[slot];
      // Up to the opaque geometry, as the interval is clipped at the near plane; relative to
      // c's depth like the interval's own ends.
      exit = min(exit, limit - origin.z);
      if (!(exit > enter)) continue;
      IntervalRay r;
      r.rel_front = enter;
      r.rel_back = exit;
      r.front = origin.z + enter;
      r.back = origin.z + exit;
      r.field_front = field_on_ray(slot, ray, enter);
      r.field_back = field_on_ray(slot, ray, exit);
      r.length_per_depth = length_per_depth;
      r.ray = ray;
      float len = interval_length(r);
      vec4 reference = vec4(s_reference[slot].xyz, s_gradient[slot].w);
      if (mode == PRISMOID_CI_ISOSURFACE) {
        float shade, hit_depth;
        if (isosurface_hit(r, reference, shade, hit_depth) && hit_depth < nearest_hit) {
          nearest_hit = hit_depth;
          hit_value = vec4(vec3(shade), hit_depth * length_per_depth);
        }
        continue;
      }
      // A non-finite interval adds nothing (as in the fragment shaders).
      if (!(len > 0.0) || isinf(len)) continue;
      if (mode == PRISMOID_CI_OPTICAL_DEPTH) {
        // sigma is linear along the segment: its integral is the length times its mean.
        optical_depth += max(0.5 * (r.field_front + r.field_back), 0.0) * len;
      } else if (mode == PRISMOID_CI_MARCH_DEPTH) {
        optical_depth += march_optical_depth(r, reference);
      } else {
        vec4 segment = mode == PRISMOID_CI_EMISSION ? segment_emission(r.field_front, r.field_back, len) : march_color(r, reference);
        kb_insert(s_reference[slot].w + enter, segment);
      }
    }
  }
  if (!inside) return;
  ChunkPartial partial;
  partial.keys = vec4(inf, -inf, 0.0, 0.0);
  if (mode == PRISMOID_CI_OPTICAL_DEPTH || mode == PRISMOID_CI_MARCH_DEPTH) {
    partial.value = vec4(optical_depth, 0.0, 0.0, 0.0);
  } else if (mode == PRISMOID_CI_ISOSURFACE) {
    partial.value = hit_value;
    partial.keys.x = nearest_hit;
  } else {
    for (uint i = 0u; i < kb_count; ++i) composite_next(kb_key[i], kb_value[i]);
    partial.value = composited;
    partial.keys = vec4(composited_min, composited_key, inexact ? 1.0 : 0.0, 0.0);
  }
  if (slot_out != PRISMOID_CI_UNSPLIT) {
    partials[slot_out * PRISMOID_CI_TILE_PIXELS + gl_LocalInvocationIndex] = partial;
    return;
  }
  ivec2 p = ivec2(pixel);
  if (mode == PRISMOID_CI_OPTICAL_DEPTH || mode == PRISMOID_CI_MARCH_DEPTH) {
    imageStore(optical_depth_image, p, partial.value);
  } else {
    imageStore(emission_image, p, partial.value);
    if (inexact) atomicAdd(stats[PRISMOID_CI_STAT_INEXACT], 1u);
  }
}

void main() {
  if (push.chunks.y == PRISMOID_CI_LAUNCH_TILES) {
    // A tile's own workgroup: its whole list, or its first chunk if it was split.
    uint tile = gl_WorkGroupID.y * push.tiles.x + gl_WorkGroupID.x;
    uvec2 range = ranges[tile];
    uint base = chunk_base[tile];
    raster(tile, range.x, base == PRISMOID_CI_UNSPLIT ? range.y : min(range.y, range.x + push.chunks.z), base);
    return;
  }
  if (push.chunks.y == PRISMOID_CI_LAUNCH_REDO) {
    // Split tiles whose colour the merge could not put in each pixel's order: whole, as unsplit.
    uint count = stats[PRISMOID_CI_STAT_SPLIT_TILES];
    for (uint item = gl_WorkGroupID.x; item < count; item += gl_NumWorkGroups.x) {
      uint marked = split_tiles[item];
      if ((marked & PRISMOID_CI_REDO_BIT) == 0u) continue;
      uint tile = marked & ~PRISMOID_CI_REDO_BIT;
      uvec2 range = ranges[tile];
      raster(tile, range.x, range.y, PRISMOID_CI_UNSPLIT);
    }
    return;
  }
  // The split tiles' other chunks.
  uint count = stats[PRISMOID_CI_STAT_EXTRA_CHUNKS];
  for (uint item = gl_WorkGroupID.x; item < count; item += gl_NumWorkGroups.x) {
    uvec2 work = chunk_work[item];
    uvec2 range = ranges[work.x];
    uint first = range.x + work.y * push.chunks.z;
    raster(work.x, first, min(range.y, first + push.chunks.z), chunk_base[work.x] + work.y);
  }
}
