#version 460
// Compute interval backend, bin-cells step 4: the pairs of the cells bin_count.comp found too
// big for one invocation (more than PRISMOID_CI_BIG_CELL_TILES tiles), a workgroup per cell and
// an invocation per tile of its bounds, from the cell's first pair on, tiles in row order (as
// bin_emit.comp writes them). A tile its silhouette misses gets a key past every tile (sorted
// last, drawn by none), so the cell's pair count is known before its silhouette is tested.
#extension GL_GOOGLE_include_directive : require
#include "../../shared/volume.h"
#include "../../shared/compute_intervals.h"

layout(local_size_x = PRISMOID_CI_WORKGROUP) in;
#include "mesh_input.glsl"
#include "cell_bounds.glsl"
layout(std430, set = 0, binding = PRISMOID_CI_BINDING_BINS) readonly buffer Bins { uvec4 bins[]; };
layout(std430, set = 0, binding = PRISMOID_CI_BINDING_OFFSETS) readonly buffer Offsets { uint offsets[]; };
layout(std430, set = 0, binding = PRISMOID_CI_BINDING_KEYS) writeonly buffer Keys { uint keys[]; };
layout(std430, set = 0, binding = PRISMOID_CI_BINDING_VALUES) writeonly buffer Values { uint values[]; };
layout(std430, set = 0, binding = PRISMOID_CI_BINDING_BIG_CELLS) readonly buffer BigCells { uint big_cells[]; };
layout(std430, set = 0, binding = PRISMOID_CI_BINDING_STATS) readonly buffer Stats { uint stats[]; };

void main() {
  uint count = stats[PRISMOID_CI_STAT_BIG_CELLS], capacity = push.tiles.w, depth_bits = push.tiles.z;
  for (uint item = gl_WorkGroupID.x; item < count; item += gl_NumWorkGroups.x) {
    uint cell = big_cells[item];
    uvec4 bin = bins[cell];
    uint first = offsets[cell];
    if (first >= capacity) continue;
    // The tiles of the cell's pixel bounds.
    uint x0 = (bin.x & 0xFFFFu) / PRISMOID_CI_TILE, x1 = (bin.x >> 16) / PRISMOID_CI_TILE, y0 = (bin.y & 0xFFFFu) / PRISMOID_CI_TILE;
    uint width = x1 - x0 + 1u;
    // Every invocation decides the same bounds from the same numbers (cell_bounds.glsl).
    CellBounds b = cell_bounds(load_cell(cell).position);
    uint end = min(bin.w, capacity - first);
    for (uint i = gl_LocalInvocationID.x; i < end; i += PRISMOID_CI_WORKGROUP) {
      uvec2 tile = uvec2(x0 + i % width, y0 + i / width);
      keys[first + i] = tile_touched(b, tile) ? ((tile.y * push.tiles.x + tile.x) << depth_bits) | bin.z : 0xFFFFFFFFu;
      values[first + i] = cell;
    }
  }
}
