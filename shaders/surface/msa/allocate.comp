#version 460
// The meshlet shading atlas's block management (Neff et al. 2022, 3, after Mueller et al.'s
// shading atlas): power-of-two blocks in superblocks that each hold one block size, allocated and
// released in parallel. One step per dispatch (msa_push.atlas.w, shaders/shared/msa.h):
// demand -> budget -> release -> claim -> pool -> allocate -> settle -> tasks. A meshlet seen
// again at the same block size keeps its block (and its shading); one not seen, or wanting
// another size, gives its slot back to its class's stack; a class whose stack and superblocks
// cannot serve its meshlets claims superblocks from the pool.
#extension GL_GOOGLE_include_directive : require
#include "msa.glsl"

layout(local_size_x = 64) in;

uint meshlet_count() { return msa_push.atlas.z; }

bool seen(uint m) { return msa_density[m] != 0u; }

uint wanted_class(uint m, float factor) {
  return msa_class_for(msa_meshlets[m].extent.xy, uintBitsToFloat(msa_density[m]) * factor);
}

void main() {
  uint i = gl_GlobalInvocationID.x + gl_GlobalInvocationID.y * gl_NumWorkGroups.x * gl_WorkGroupSize.x;
  uint step = msa_push.atlas.w;
  uint now = msa_push.image.w;
  if (step == PRISMOID_MSA_STEP_DEMAND) {
    if (i >= meshlet_count() || !seen(i)) return;
    uvec2 size = msa_class_size(wanted_class(i, 1.0));
    atomicAdd(msa_state.demand.x, size.x * size.y);
    atomicAdd(msa_state.blocks.x, 1u);
  } else if (step == PRISMOID_MSA_STEP_BUDGET) {
    if (i != 0u) return;
    float budget = float(msa_push.limits.y), demand = float(msa_state.demand.x);
    msa_state.budget.x = budget > 0.0 && demand > budget ? sqrt(budget / demand) : 1.0;
  } else if (step == PRISMOID_MSA_STEP_RELEASE) {
    if (i >= meshlet_count()) return;
    bool is_seen = seen(i);
    uint want = is_seen ? wanted_class(i, msa_state.budget.x) : PRISMOID_MSA_NONE;
    uvec4 b = msa_blocks[i].block;
    if (b.z != PRISMOID_MSA_NONE && b.z == want) return;  // keeps its block
    if (b.z != PRISMOID_MSA_NONE) {
      uint k = atomicAdd(msa_classes[b.z].counts.w, 1u);
      msa_free_slots[b.z * meshlet_count() + msa_classes[b.z].counts.x + k] = b.w;
      msa_blocks[i].block = uvec4(0u, 0u, PRISMOID_MSA_NONE, 0u);
      atomicAdd(msa_state.blocks.z, 1u);
    }
    if (is_seen) atomicAdd(msa_classes[want].frame.x, 1u);
  } else if (step == PRISMOID_MSA_STEP_CLAIM) {
    if (i >= PRISMOID_MSA_CLASSES) return;
    MsaClassGpu c = msa_classes[i];
    c.counts.x += c.counts.w;
    c.counts.w = 0u;
    uint per = msa_slots_per_superblock(i);
    uint need = c.frame.x > c.counts.x ? c.frame.x - c.counts.x : 0u;
    uint available = c.counts.z * per - c.counts.y;
    if (need > available) {
      uint k = (need - available + per - 1u) / per;
      uint first = atomicAdd(msa_state.pool.y, k);
      for (uint j = 0u; j < k; ++j) {
        if (first + j >= msa_state.pool.x) {
          msa_state.pool.z = 1u;  // out of superblocks: some meshlets go without a block this frame
          break;
        }
        msa_class_superblocks[i * msa_push.limits.x + c.counts.z] = msa_pool[msa_state.pool.x - 1u - (first + j)];
        c.counts.z += 1u;
      }
    }
    msa_classes[i] = c;
  } else if (step == PRISMOID_MSA_STEP_POOL) {
    if (i != 0u) return;
    msa_state.pool.x -= min(msa_state.pool.y, msa_state.pool.x);
    msa_state.pool.y = 0u;
  } else if (step == PRISMOID_MSA_STEP_ALLOCATE) {
    if (i >= meshlet_count() || !seen(i) || msa_blocks[i].block.z != PRISMOID_MSA_NONE) return;
    uint c = wanted_class(i, msa_state.budget.x);
    uint k = atomicAdd(msa_classes[c].frame.y, 1u);
    uint free_slots = msa_classes[c].counts.x;
    uint slot;
    if (k < free_slots) {
      slot = msa_free_slots[c * meshlet_count() + free_slots - 1u - k];
    } else {
      slot = msa_classes[c].counts.y + (k - free_slots);
      if (slot >= msa_classes[c].counts.z * msa_slots_per_superblock(c)) {
        atomicAdd(msa_state.pool.w, 1u);
        return;
      }
    }
    msa_blocks[i].block = uvec4(msa_slot_origin(c, slot), c, slot);
    msa_blocks[i].stamp.x = now;
    atomicAdd(msa_state.blocks.y, 1u);
  } else if (step == PRISMOID_MSA_STEP_SETTLE) {
    if (i >= PRISMOID_MSA_CLASSES) return;
    MsaClassGpu c = msa_classes[i];
    uint taken = min(c.frame.y, c.counts.x);
    if (c.frame.y > c.counts.x) c.counts.y = min(c.counts.y + (c.frame.y - c.counts.x), c.counts.z * msa_slots_per_superblock(i));
    c.counts.x -= taken;
    c.frame = uvec4(0u);
    msa_classes[i] = c;
  } else if (step == PRISMOID_MSA_STEP_TASKS) {
    if (i >= meshlet_count() || !seen(i)) return;
    MsaBlockGpu b = msa_blocks[i];
    if (b.block.z == PRISMOID_MSA_NONE) return;
    uvec2 size = msa_class_size(b.block.z);
    atomicAdd(msa_state.demand.y, size.x * size.y);
    bool shade = (msa_push.image.z & PRISMOID_MSA_FLAG_SHADE_ALL) != 0u || b.stamp.x == now || b.stamp.y == 0u;
    if (!shade) return;
    uint tiles = (size.x / 8u) * (size.y / 8u);
    uint base = atomicAdd(msa_state.demand.w, tiles);
    atomicMax(msa_state.trace.z, (base + tiles + PRISMOID_MSA_TILES_PER_LAUNCH - 1u) / PRISMOID_MSA_TILES_PER_LAUNCH);
    for (uint t = 0u; t < tiles; ++t) msa_tasks[base + t] = (i << 12u) | t;
    msa_blocks[i].stamp.y = now;
    atomicAdd(msa_state.blocks.w, 1u);
  }
}
