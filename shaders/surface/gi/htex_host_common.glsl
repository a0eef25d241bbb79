// What the Htex GI host's passes share (htex_host.glsl, htex_samples.rgen): the Htex tables and
// residency buffers in set 1 (set 0 is GI's), the host's own buffers, and the task texel of a
// launch. Include after the scene's and GI's bindings.
#ifndef PRISMOID_SURFACE_GI_HTEX_HOST_COMMON_GLSL
#define PRISMOID_SURFACE_GI_HTEX_HOST_COMMON_GLSL

#define PRISMOID_HTEX_SET 1
#include "../htex/htex.glsl"
#include "../htex/htex_walk.glsl"

layout(std430, set = 1, binding = PRISMOID_HTEX_BINDING_OCCUPANCY) readonly buffer GiHtexOccupancy { uint gi_htex_occupancy[]; };
layout(std430, set = 1, binding = PRISMOID_HTEX_BINDING_PAGE_TABLE) readonly buffer GiHtexPageTable { uint gi_htex_page_table[]; };
layout(std430, set = 1, binding = PRISMOID_HTEX_BINDING_TASKS) readonly buffer GiHtexTasks { uint gi_htex_tasks[]; };

// Per slot: xy: the virtual texel the slot's reservoir belongs to, z: frame index + 1 of the
// frame that wrote it (0: never).
layout(std430, set = 0, binding = PRISMOID_GI_BINDING_HOST) buffer GiHtexStamps { uvec4 gi_htex_stamps[]; };
// Per mesh: the persistent (fallback) layer: x: first entry, y: level, z: side (0: none).
layout(std430, set = 0, binding = PRISMOID_GI_BINDING_HOST + 1) readonly buffer GiHtexLayers { uvec4 gi_htex_layers[]; };

#define PRISMOID_GI_HTEX_NO_SNAP 256u  // GiSettings flag: vertex-corner texels at their nominal points

// The pool slot of virtual texel w when its group is resident and its shadel marked this frame.
bool gi_htex_task_slot(uvec2 w, out uint slot) {
  slot = 0u;
  if (w.x >= htex_atlas.size.x || w.y >= htex_atlas.size.y) return false;
  uint group = htex_group_of(w);
  uint page = gi_htex_page_table[group];
  if (page == PRISMOID_HTEX_NOT_RESIDENT) return false;
  uint bit = htex_group_bit(w);
  if ((gi_htex_occupancy[2u * group + bit / 32u] & (1u << (bit % 32u))) == 0u) return false;
  slot = htex_slot(page, w);
  return true;
}

// This invocation's texel: task gl_LaunchIDEXT.z, texel (x, y) of its shadel; false for padding.
bool gi_htex_launch_texel(out uvec2 v, out uint slot) {
  uint shadel = gi_htex_tasks[gl_LaunchIDEXT.z];
  v = uvec2((shadel % htex_atlas.size.z) * 8u + gl_LaunchIDEXT.x, (shadel / htex_atlas.size.z) * 8u + gl_LaunchIDEXT.y);
  slot = 0u;
  HtexTexelAddress t;
  if (!htex_texel_at(v, t)) return false;
  uint page = gi_htex_page_table[htex_group_of(v)];
  if (page == PRISMOID_HTEX_NOT_RESIDENT) return false;
  slot = htex_slot(page, v);
  return true;
}

#endif
