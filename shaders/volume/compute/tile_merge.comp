#version 460
// Compute interval backend, after the split tiles' chunks were rastered (tile_raster.glsl): each
// pixel of a split tile combines its chunks' partial results in chunk order, which is the
// tile's depth-key order: optical depths summed, colours composited front to back (the
// operator is associative, so this is the sequential result up to rounding), the nearest
// isosurface hit kept (the earlier chunk's on a tie). A colour is in the pixel's own order
// unless some chunk composited an interval nearer than one an earlier chunk composited: a tile
// with such a pixel is left to a last raster dispatch (PRISMOID_CI_LAUNCH_REDO), which walks its
// whole list in one workgroup as an unsplit tile is walked, so splitting costs no exactness.
// One invocation forms each pixel's result in a fixed order: deterministic.
#extension GL_GOOGLE_include_directive : require
#include "../../shared/volume.h"
#include "../../shared/compute_intervals.h"

layout(local_size_x = PRISMOID_CI_TILE, local_size_y = PRISMOID_CI_TILE) in;
layout(std430, set = 0, binding = PRISMOID_CI_BINDING_TILE_RANGES) readonly buffer TileRanges { uvec2 ranges[]; };
layout(std430, set = 0, binding = PRISMOID_CI_BINDING_STATS) buffer Stats { uint stats[]; };
layout(std430, set = 0, binding = PRISMOID_CI_BINDING_CHUNK_BASE) readonly buffer ChunkBase { uint chunk_base[]; };
layout(std430, set = 0, binding = PRISMOID_CI_BINDING_SPLIT_TILES) buffer SplitTiles { uint split_tiles[]; };
layout(std430, set = 0, binding = PRISMOID_CI_BINDING_PARTIALS) readonly buffer Partials { ChunkPartial partials[]; };
layout(set = 0, binding = PRISMOID_CI_BINDING_OPTICAL_DEPTH, r32f) uniform writeonly image2D optical_depth_image;
layout(set = 0, binding = PRISMOID_CI_BINDING_EMISSION, rgba32f) uniform writeonly image2D emission_image;
layout(push_constant) uniform Push { ComputeIntervalsPush push; };

#include "../segment_integral.glsl"

shared bool s_redo;

void main() {
  uint count = stats[PRISMOID_CI_STAT_SPLIT_TILES], mode = push.options.x;
  for (uint item = gl_WorkGroupID.x; item < count; item += gl_NumWorkGroups.x) {
    uint tile = split_tiles[item];
    uvec2 range = ranges[tile];
    uint chunks = (range.y - range.x + push.chunks.z - 1u) / push.chunks.z;
    uint first = chunk_base[tile] * PRISMOID_CI_TILE_PIXELS + gl_LocalInvocationIndex;
    uvec2 pixel = uvec2(tile % push.tiles.x, tile / push.tiles.x) * PRISMOID_CI_TILE + gl_LocalInvocationID.xy;
    bool inside = pixel.x < push.options.y && pixel.y < push.options.z;
    ivec2 p = ivec2(pixel);
    if (!inside && mode != PRISMOID_CI_EMISSION && mode != PRISMOID_CI_MARCH_COLOR) continue;
    if (mode == PRISMOID_CI_OPTICAL_DEPTH || mode == PRISMOID_CI_MARCH_DEPTH) {
      float sum = 0.0;
      for (uint c = 0u; c < chunks; ++c) sum += partials[first + c * PRISMOID_CI_TILE_PIXELS].value.x;
      imageStore(optical_depth_image, p, vec4(sum, 0.0, 0.0, 0.0));
    } else if (mode == PRISMOID_CI_ISOSURFACE) {
      float nearest = uintBitsToFloat(0x7F800000u);
      vec4 hit = vec4(0.0);
      for (uint c = 0u; c < chunks; ++c) {
        ChunkPartial part = partials[first + c * PRISMOID_CI_TILE_PIXELS];
        if (part.keys.x < nearest) {
          nearest = part.keys.x;
          hit = part.value;
        }
      }
      imageStore(emission_image, p, hit);
    } else {
      // Every invocation reaches the barriers: a pixel outside the image only has nothing to add.
      if (gl_LocalInvocationIndex == 0u) s_redo = false;
      barrier();
      vec4 colour = vec4(0.0);
      float farthest = -uintBitsToFloat(0x7F800000u);
      bool inexact = false, crossed = false;
      for (uint c = 0u; inside && c < chunks; ++c) {
        ChunkPartial part = partials[first + c * PRISMOID_CI_TILE_PIXELS];
        inexact = inexact || part.keys.z != 0.0;
        crossed = crossed || part.keys.x < farthest;
        farthest = max(farthest, part.keys.y);
        colour = composite_under(colour, part.value);
      }
      if (crossed) s_redo = true;
      barrier();
      if (s_redo) {
        if (gl_LocalInvocationIndex == 0u) {
          split_tiles[item] = tile | PRISMOID_CI_REDO_BIT;
          atomicAdd(stats[PRISMOID_CI_STAT_REDO_TILES], 1u);
        }
      } else if (inside) {
        imageStore(emission_image, p, colour);
        if (inexact) atomicAdd(stats[PRISMOID_CI_STAT_INEXACT], 1u);
      }
      barrier();  // s_redo is read before the next tile resets it
    }
  }
}
