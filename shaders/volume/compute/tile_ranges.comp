#version 460
// Compute interval backend, after the sort: where each tile's pairs begin and end (tiles that
// hold none keep the (0, 0) the buffer was cleared to).
#extension GL_GOOGLE_include_directive : require
#include "../../shared/compute_intervals.h"

layout(local_size_x = PRISMOID_CI_WORKGROUP) in;
layout(std430, set = 0, binding = PRISMOID_CI_BINDING_KEYS) readonly buffer Keys { uint keys[]; };
layout(std430, set = 0, binding = PRISMOID_CI_BINDING_TILE_RANGES) buffer TileRanges { uvec2 ranges[]; };
layout(std430, set = 0, binding = PRISMOID_CI_BINDING_STATS) readonly buffer Stats { uint stats[]; };
layout(push_constant) uniform Push { ComputeIntervalsPush push; };

void main() {
  uint count = stats[PRISMOID_CI_STAT_SORTED], depth_bits = push.tiles.z;
  for (uint i = gl_GlobalInvocationID.x; i < count; i += gl_NumWorkGroups.x * PRISMOID_CI_WORKGROUP) {
    uint tile = keys[i] >> depth_bits;
    if (tile >= push.tiles.x * push.tiles.y) continue;  // a pair bin-cells wrote past every tile (bin_emit.comp)
    if (i == 0u || (keys[i - 1u] >> depth_bits) != tile) ranges[tile].x = i;
    if (i + 1u == count || (keys[i + 1u] >> depth_bits) != tile) ranges[tile].y = i + 1u;
  }
}
