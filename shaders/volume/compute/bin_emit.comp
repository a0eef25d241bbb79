#version 460
// Compute interval backend, bin-cells step 3 (after the prefix sum of the pair counts): each
// cell writes its (tile << depth bits | depth key, cell) pairs from its first pair on, tiles in
// row order; pairs beyond the capacity are counted, not written. The last cell records how
// many pairs there are, which the sort reads on the GPU. The tiles are decided again, as step 1
// decided them (cell_bounds.glsl); where rounding in this pipeline decides a tile within a
// pixel of the silhouette otherwise, at most the counted pairs are written and the rest are
// written as a key past every tile (sorted last, drawn by none): such a tile holds no pixel the
// cell covers. Big cells (more than PRISMOID_CI_BIG_CELL_TILES tiles) are left to
// big_emit.comp, whose dispatch the last cell sizes.
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
layout(std430, set = 0, binding = PRISMOID_CI_BINDING_STATS) buffer Stats { uint stats[]; };

void main() {
  uint count = frame.counts.x, capacity = push.tiles.w, depth_bits = push.tiles.z;
  for (uint cell = gl_GlobalInvocationID.x; cell < count; cell += gl_NumWorkGroups.x * PRISMOID_CI_WORKGROUP) {
    uvec4 bin = bins[cell];
    uint first = offsets[cell];
    if (cell == count - 1u) {
      uint total = first + bin.w;
      stats[PRISMOID_CI_STAT_PAIRS] = total;
      stats[PRISMOID_CI_STAT_SORTED] = min(total, capacity);
      stats[PRISMOID_CI_ARGS_BIG_EMIT] = min(stats[PRISMOID_CI_STAT_BIG_CELLS], PRISMOID_CI_MAX_GROUPS);
      stats[PRISMOID_CI_ARGS_BIG_EMIT + 1] = 1u;
      stats[PRISMOID_CI_ARGS_BIG_EMIT + 2] = 1u;
    }
    if (bin.w == 0u || first >= capacity) continue;
    // The tiles of the cell's pixel bounds.
    uint x0 = (bin.x & 0xFFFFu) / PRISMOID_CI_TILE, x1 = (bin.x >> 16) / PRISMOID_CI_TILE;
    uint y0 = (bin.y & 0xFFFFu) / PRISMOID_CI_TILE, y1 = (bin.y >> 16) / PRISMOID_CI_TILE;
    if ((x1 - x0 + 1u) * (y1 - y0 + 1u) > PRISMOID_CI_BIG_CELL_TILES) continue;
    CellBounds b = cell_bounds(load_cell(cell).position);
    uint pair = first, end = min(first + bin.w, capacity);
    for (uint y = y0; y <= y1 && pair < end; ++y)
      for (uint x = x0; x <= x1 && pair < end; ++x) {
        if (!tile_touched(b, uvec2(x, y))) continue;
        keys[pair] = ((y * push.tiles.x + x) << depth_bits) | bin.z;
        values[pair] = cell;
        ++pair;
      }
    for (; pair < end; ++pair) {
      keys[pair] = 0xFFFFFFFFu;
      values[pair] = cell;
    }
  }
}
