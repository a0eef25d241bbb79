// The Htex backend's residency buffers and push constants (shaders/shared/htex.h), for the
// passes that mark, allocate, shade and gather. Include after htex.glsl.
#ifndef PRISMOID_HTEX_RESIDENCY_GLSL
#define PRISMOID_HTEX_RESIDENCY_GLSL

layout(std430, set = 0, binding = PRISMOID_HTEX_BINDING_OCCUPANCY) buffer HtexOccupancyBuffer { uint htex_occupancy[]; };
layout(std430, set = 0, binding = PRISMOID_HTEX_BINDING_PAGE_TABLE) buffer HtexPageTableBuffer { uint htex_page_table[]; };
layout(std430, set = 0, binding = PRISMOID_HTEX_BINDING_FREE_LIST) buffer HtexFreeListBuffer { uint htex_free_list[]; };
layout(std430, set = 0, binding = PRISMOID_HTEX_BINDING_STATE) buffer HtexStateBuffer { HtexStateGpu htex_state; };
layout(std430, set = 0, binding = PRISMOID_HTEX_BINDING_TASKS) buffer HtexTaskBuffer { uint htex_tasks[]; };
layout(std430, set = 0, binding = PRISMOID_HTEX_BINDING_POOL) buffer HtexPoolBuffer { vec4 htex_pool[]; };
layout(std430, set = 0, binding = PRISMOID_HTEX_BINDING_INDIRECT) buffer HtexIndirectBuffer { vec4 htex_indirect[]; };
layout(std430, set = 0, binding = PRISMOID_HTEX_BINDING_SHADED) buffer HtexShadedBuffer { uint htex_shaded[]; };
layout(std430, set = 0, binding = PRISMOID_HTEX_BINDING_VISIBILITY) buffer HtexVisibilityBuffer { uvec4 htex_visibility[]; };

layout(push_constant) uniform HtexPushBlock { HtexPush htex_push; };

// Marks every shadel the lookup at (face, bary, level) reads: its occupancy bit (the group is
// marked when any of its 64 bits is).
void htex_mark_footprint(uint mesh, uint face, vec3 bary, uint level) {
  HtexFootprint fp = htex_footprint(mesh, face, bary, level);
  for (uint k = 0u; k < fp.count; ++k) {
    uvec2 v = htex_virtual_texel(mesh, fp.texel[k].x, level, fp.texel[k].z, fp.texel[k].w);
    uint bit = htex_group_bit(v);
    atomicOr(htex_occupancy[2u * htex_group_of(v) + bit / 32u], 1u << (bit % 32u));
  }
}

#endif
