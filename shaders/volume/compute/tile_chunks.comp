#version 460
// Compute interval backend, after the tile ranges: a tile holding more than a chunk of pairs
// (push.chunks.z: PRISMOID_CI_CHUNK or, for colour, PRISMOID_CI_CHUNK_COLOR) is split into chunks of that many, each rastered by a workgroup of its own into a slot
// of partial results (tile_raster.glsl), which tile_merge.comp combines in chunk order. Each
// split tile takes consecutive slots, its first chunk (rastered by the tile's own workgroup)
// the first of them, and lists its other chunks as work for a second raster dispatch. Slots are
// taken in no fixed order, but every result lands in its tile's own slots: images stay
// deterministic. A tile that finds no slots left (cannot happen: the slots are sized for the
// most chunks the pair capacity can make) is rastered whole by its own workgroup.
#extension GL_GOOGLE_include_directive : require
#include "../../shared/compute_intervals.h"

layout(local_size_x = PRISMOID_CI_WORKGROUP) in;
layout(std430, set = 0, binding = PRISMOID_CI_BINDING_TILE_RANGES) readonly buffer TileRanges { uvec2 ranges[]; };
layout(std430, set = 0, binding = PRISMOID_CI_BINDING_CHUNK_BASE) writeonly buffer ChunkBase { uint chunk_base[]; };
layout(std430, set = 0, binding = PRISMOID_CI_BINDING_CHUNK_WORK) writeonly buffer ChunkWork { uvec2 chunk_work[]; };
layout(std430, set = 0, binding = PRISMOID_CI_BINDING_SPLIT_TILES) writeonly buffer SplitTiles { uint split_tiles[]; };
layout(std430, set = 0, binding = PRISMOID_CI_BINDING_STATS) buffer Stats { uint stats[]; };
layout(push_constant) uniform Push { ComputeIntervalsPush push; };

void main() {
  uint tiles = push.tiles.x * push.tiles.y;
  for (uint tile = gl_GlobalInvocationID.x; tile < tiles; tile += gl_NumWorkGroups.x * PRISMOID_CI_WORKGROUP) {
    uvec2 range = ranges[tile];
    uint pairs = range.y - range.x;
    uint base = PRISMOID_CI_UNSPLIT;
    uint chunk = push.chunks.z;
    if (pairs > chunk) {
      uint chunks = (pairs + chunk - 1u) / chunk;
      uint slot = atomicAdd(stats[PRISMOID_CI_STAT_CHUNK_SLOTS], chunks);
      if (slot + chunks <= push.chunks.x) {
        base = slot;
        split_tiles[atomicAdd(stats[PRISMOID_CI_STAT_SPLIT_TILES], 1u)] = tile;
        uint work = atomicAdd(stats[PRISMOID_CI_STAT_EXTRA_CHUNKS], chunks - 1u);
        for (uint c = 1u; c < chunks; ++c) chunk_work[work + c - 1u] = uvec2(tile, c);
      }
    }
    chunk_base[tile] = base;
  }
}
