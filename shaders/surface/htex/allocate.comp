#version 460
// The Htex backend's sparse allocator and task list (Li & Guo 3.3, 3.4), one compute shader
// whose step is htex_push.image.w (HtexPass records them in this order, with barriers between):
//   COUNT    (per group)  marked groups and shadels, while the loop runs
//   DECIDE   (one thread) over the pool's capacity and a coarser level left: bias + 1, re-mark;
//                         else the loop is done; sizes the loop's next CLEAR, REMARK and COUNT
//                         (indirect: nothing once done)
//   CLEAR    (per group)  re-marking: occupancy to zero
//   REMARK   (per pixel)  re-marking: the pixel's level raised to at least the bias, footprint marked
//   RELEASE  (per group)  a resident group no longer marked gives its page back to the free list
//   ALLOCATE (per group)  a marked group without a page takes one from the free list, or is
//                         counted as left without one (the pool is full even at the largest bias)
//   FINISH   (one thread) the free list loses what was taken
//   TASKS    (per group)  each marked shadel of a resident group joins the task list (with
//                         PRISMOID_HTEX_FLAG_REUSE only those not shaded since their page was
//                         taken: htex_shaded); the indirect launch (8, 8, tasks) counts them
// A group that stays marked keeps its page, so what is stored per texel (shading, and later
// reservoirs) persists from frame to frame at the same slot.
#extension GL_GOOGLE_include_directive : require
#define PRISMOID_SURFACE_VERTEX_BUFFERS
#include "../scene_bindings.glsl"
#include "htex.glsl"
#include "htex_residency.glsl"

layout(local_size_x = 64) in;

#define STEP_COUNT 0u
#define STEP_DECIDE 1u
#define STEP_CLEAR 2u
#define STEP_REMARK 3u
#define STEP_RELEASE 4u
#define STEP_ALLOCATE 5u
#define STEP_FINISH 6u
#define STEP_TASKS 7u

// The workgroups of a step over `invocations` (as HtexPass::dispatch_step lays them out).
uvec3 dispatch_size(uint invocations) {
  uint workgroups = max(1u, (invocations + 63u) / 64u);
  uint x = min(workgroups, PRISMOID_HTEX_DISPATCH_ROW);
  return uvec3(x, (workgroups + x - 1u) / x, 1u);
}

uvec2 occupancy(uint g) { return uvec2(htex_occupancy[2u * g], htex_occupancy[2u * g + 1u]); }
bool marked(uint g) { return any(notEqual(occupancy(g), uvec2(0u))); }

void main() {
  // Dispatched as (x, y) workgroups when one row of workgroups would exceed the device's limit.
  uint id = gl_WorkGroupID.y * gl_NumWorkGroups.x * 64u + gl_GlobalInvocationID.x;
  uint step = htex_push.image.w;
  uint groups = htex_atlas.counts.x;
  uint capacity = htex_atlas.counts.z;
  if (step == STEP_COUNT) {
    if (id >= groups || htex_state.marking.w == PRISMOID_HTEX_PHASE_DONE || !marked(id)) return;
    uvec2 o = occupancy(id);
    atomicAdd(htex_state.marking.x, 1u);
    atomicAdd(htex_state.marking.y, uint(bitCount(o.x) + bitCount(o.y)));
  } else if (step == STEP_DECIDE) {
    if (id != 0u || htex_state.marking.w == PRISMOID_HTEX_PHASE_DONE) return;
    if (htex_state.marking.z == 0u) htex_state.result.z = htex_state.marking.x;
    bool again = htex_state.marking.x > capacity && htex_state.marking.z + 1u < htex_atlas.counts.w;
    if (again) {
      htex_state.marking.z += 1u;
      htex_state.marking.x = 0u;
      htex_state.marking.y = 0u;
      htex_state.marking.w = PRISMOID_HTEX_PHASE_REMARK;
    } else {
      htex_state.marking.w = PRISMOID_HTEX_PHASE_DONE;
    }
    htex_state.loop_groups = uvec4(again ? dispatch_size(groups) : uvec3(0u), 0u);
    htex_state.loop_pixels = uvec4(again ? dispatch_size(htex_push.image.x * htex_push.image.y) : uvec3(0u), 0u);
  } else if (step == STEP_CLEAR) {
    if (id >= groups || htex_state.marking.w != PRISMOID_HTEX_PHASE_REMARK) return;
    htex_occupancy[2u * id] = 0u;
    htex_occupancy[2u * id + 1u] = 0u;
  } else if (step == STEP_REMARK) {
    if (id >= htex_push.image.x * htex_push.image.y || htex_state.marking.w != PRISMOID_HTEX_PHASE_REMARK) return;
    uvec4 vis = htex_visibility[id];
    if (vis.x == 0u || vis.y == PRISMOID_HTEX_NONE) return;
    uint triangle = vis.x - 1u;
    uint face = htex_face_of_triangle[triangle];
    uint mesh = triangles[triangle].info.y;
    uint level = min(max(vis.y, htex_state.marking.z), htex_meshes[mesh].info.w - 1u);
    htex_visibility[id].y = level;
    vec3 b = vec3(0.0, uintBitsToFloat(vis.z), uintBitsToFloat(vis.w));
    b.x = 1.0 - b.y - b.z;
    htex_mark_footprint(mesh, face, b, level);
  } else if (step == STEP_RELEASE) {
    if (id >= groups) return;
    uint page = htex_page_table[id];
    if (page == PRISMOID_HTEX_NOT_RESIDENT || marked(id)) return;
    htex_free_list[atomicAdd(htex_state.persistent.x, 1u)] = page;
    htex_page_table[id] = PRISMOID_HTEX_NOT_RESIDENT;
    htex_shaded[2u * id] = 0u;  // the page's texels belong to no one now
    htex_shaded[2u * id + 1u] = 0u;
    atomicAdd(htex_state.pages.x, 1u);
  } else if (step == STEP_ALLOCATE) {
    if (id >= groups || !marked(id) || htex_page_table[id] != PRISMOID_HTEX_NOT_RESIDENT) return;
    uint k = atomicAdd(htex_state.pages.y, 1u);
    uint free_pages = htex_state.persistent.x;  // not written during this step
    if (k < free_pages) {
      htex_page_table[id] = htex_free_list[free_pages - 1u - k];
      htex_shaded[2u * id] = 0u;  // a fresh page holds another group's old texels
      htex_shaded[2u * id + 1u] = 0u;
    } else {
      atomicAdd(htex_state.pages.z, 1u);
    }
  } else if (step == STEP_FINISH) {
    if (id != 0u) return;
    uint taken = min(htex_state.pages.y, htex_state.persistent.x);
    htex_state.persistent.x -= taken;
    htex_state.pages.y = taken;
    htex_state.result.x = htex_state.marking.x > capacity ? 1u : 0u;
  } else if (step == STEP_TASKS) {
    if (id >= groups || htex_page_table[id] == PRISMOID_HTEX_NOT_RESIDENT) return;
    atomicAdd(htex_state.pages.w, 1u);
    uvec2 marked_bits = occupancy(id);
    // Reuse: what was shaded into this page since it was taken is still right (the frame planner
    // asks for reuse only when nothing the shading depends on changed), so only the rest is shaded.
    bool reuse = (htex_push.image.z & PRISMOID_HTEX_FLAG_REUSE) != 0u;
    uvec2 done = reuse ? uvec2(htex_shaded[2u * id], htex_shaded[2u * id + 1u]) : uvec2(0u);
    uvec2 o = marked_bits & ~done;
    htex_shaded[2u * id] = done.x | marked_bits.x;
    htex_shaded[2u * id + 1u] = done.y | marked_bits.y;
    uint reused = uint(bitCount(marked_bits.x & done.x) + bitCount(marked_bits.y & done.y));
    if (reused > 0u) atomicAdd(htex_state.result.w, reused);
    uint group_columns = htex_atlas.size.w;
    for (uint bit = 0u; bit < 64u; ++bit) {
      if (((bit < 32u ? o.x : o.y) & (1u << (bit % 32u))) == 0u) continue;
      uvec2 shadel = uvec2((id % group_columns) * 8u + bit % 8u, (id / group_columns) * 8u + bit / 8u);
      uint texels = 0u;
      for (uint t = 0u; t < 64u; ++t) {
        HtexTexelAddress a;
        if (htex_texel_at(shadel * 8u + uvec2(t % 8u, t / 8u), a)) ++texels;
      }
      htex_tasks[atomicAdd(htex_state.trace.z, 1u)] = shadel.y * htex_atlas.size.z + shadel.x;
      atomicAdd(htex_state.trace.w, texels);
    }
  }
}
