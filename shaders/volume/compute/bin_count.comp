#version 460
// Compute interval backend, bin-cells step 1: each cell's conservative screen bounds in
// tiles (cell_bounds.glsl), the depth key that orders it within a tile (its nearest depth),
// and how many (tile, cell) pairs it needs: the tiles of its bounds its silhouette touches,
// or, for a cell spanning more than PRISMOID_CI_BIG_CELL_TILES tiles, every tile of its bounds
// (big_emit.comp decides each, one per invocation; a tile it misses gets a dropped pair).
#extension GL_GOOGLE_include_directive : require
#include "../../shared/volume.h"
#include "../../shared/compute_intervals.h"

layout(local_size_x = PRISMOID_CI_WORKGROUP) in;
#include "mesh_input.glsl"
#include "cell_bounds.glsl"
layout(std430, set = 0, binding = PRISMOID_CI_BINDING_BINS) writeonly buffer Bins { uvec4 bins[]; };
layout(std430, set = 0, binding = PRISMOID_CI_BINDING_OFFSETS) writeonly buffer Offsets { uint offsets[]; };
layout(std430, set = 0, binding = PRISMOID_CI_BINDING_BIG_CELLS) writeonly buffer BigCells { uint big_cells[]; };
layout(std430, set = 0, binding = PRISMOID_CI_BINDING_STATS) buffer Stats { uint stats[]; };

void main() {
  uint count = frame.counts.x;
  for (uint cell = gl_GlobalInvocationID.x; cell < count; cell += gl_NumWorkGroups.x * PRISMOID_CI_WORKGROUP) {
    CellInput c = load_cell(cell);
    CellBounds b = cell_bounds(c.position);
    uvec4 bin = uvec4(0u);
    if (c.drawn && b.visible) {
      uvec2 t0 = b.lo / PRISMOID_CI_TILE, t1 = b.hi / PRISMOID_CI_TILE;
      uint max_key = push.tiles.z >= 32u ? 0xFFFFFFFFu : (1u << push.tiles.z) - 1u;
      float key = clamp((b.nearest - push.depth.x) * push.depth.y, 0.0, float(max_key));
      uint pairs = (t1.x - t0.x + 1u) * (t1.y - t0.y + 1u);
      if (pairs > PRISMOID_CI_BIG_CELL_TILES) {
        big_cells[atomicAdd(stats[PRISMOID_CI_STAT_BIG_CELLS], 1u)] = cell;
      } else {
        pairs = 0u;
        for (uint y = t0.y; y <= t1.y; ++y)
          for (uint x = t0.x; x <= t1.x; ++x) pairs += tile_touched(b, uvec2(x, y)) ? 1u : 0u;
      }
      // The pixel bounds (the tile raster reads them for each pixel's first test).
      bin = uvec4(b.lo.x | (b.hi.x << 16), b.lo.y | (b.hi.y << 16), min(uint(key), max_key), pairs);
    }
    bins[cell] = bin;
    offsets[cell] = bin.w;
  }
}
