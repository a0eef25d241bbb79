// The Htex shading pass (Li & Guo 3.4): one ray-generation invocation per texel of each task
// shadel, launched as (8, 8, tasks) by vkCmdTraceRaysIndirectKHR. Each texel's point
// (htex_texel_point: vertex-corner texels at the vertex, ghost texels in the face's plane) is
// rebuilt as a surface point of its triangle and shaded by the shared shading code; the result
// goes to the texel's pool slot. Included by shade.rgen (with shadow rays) and
// shade_unshadowed.rgen (every light visible, as the CPU direct-light reference).
//
// Hook for indirect light (ReSTIR GI, Li & Guo 4): a later pass writes indirect radiance per
// texel into htex_indirect at the same slot (PRISMOID_HTEX_BINDING_INDIRECT), walking the same
// task list between HtexPass::record_shading and record_gather; with PRISMOID_HTEX_FLAG_INDIRECT
// the gather adds it. This pass never writes it.
#extension GL_GOOGLE_include_directive : require
#ifndef PRISMOID_SURFACE_VERTEX_BUFFERS
#define PRISMOID_SURFACE_VERTEX_BUFFERS
#endif
#include "../surface_point.glsl"
#include "htex.glsl"
#include "htex_residency.glsl"

void main() {
  uint shadel = htex_tasks[gl_LaunchIDEXT.z];
  uvec2 v = uvec2((shadel % htex_atlas.size.z) * 8u + gl_LaunchIDEXT.x, (shadel / htex_atlas.size.z) * 8u + gl_LaunchIDEXT.y);
  HtexTexelAddress t;
  if (!htex_texel_at(v, t)) return;  // padding
  uint page = htex_page_table[htex_group_of(v)];
  if (page == PRISMOID_HTEX_NOT_RESIDENT) return;  // never: the task list holds resident shadels only
  bool snap = (htex_push.image.z & PRISMOID_HTEX_FLAG_NO_SNAP) == 0u;
  HtexTexelPoint p = htex_texel_point(t.quad, htex_side(t.mesh, t.level), t.i, t.j, snap);
  uint triangle = htex_triangle_of_face[p.face];
  ShadingInput s = shading_input_at(triangle, p.bary, triangle_point(triangle, p.bary), frame.eye.xyz);
  htex_pool[htex_slot(page, v)] = vec4(shade_surface_point(s.point, s.material, s.emission), 1.0);
}
