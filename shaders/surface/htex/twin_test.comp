#version 460
// Test only (tests/surface/test_htex_gpu.cpp): evaluates the GLSL twins of htex.glsl at a list of
// queries so that the test can hold them to the double-precision C++.
#extension GL_GOOGLE_include_directive : require
#include "htex.glsl"

layout(local_size_x = 64) in;

struct TwinQuery {
  uvec4 ids;    // x: mesh, y: global face, z: level, w: snap vertex corners
  vec4 bary;
  vec4 dx;      // barycentric change per pixel in x
  vec4 dy;
  uvec4 texel;  // x: global edge, y: side n, z: i, w: j
};

struct TwinResult {
  ivec4 locate;          // x: global halfedge
  vec4 uv;
  uvec4 quad_edges;      // xyz: global edges of the three quads
  vec4 quad_xy[3];
  vec4 lod;              // x: level of detail, y: alpha, z: footprint count
  uvec4 fp_texel[12];    // quad, level, i, j
  vec4 fp_weight[3];
  uvec4 fp_virtual[12];  // xy: virtual texel, z: 1 when texel_at found it, w: shadel
  uvec4 fp_back[12];     // texel_at: quad, level, i, j
  uvec4 tp;              // texel point: x: global face, y: ghost, z: vertex
  vec4 tp_bary;
};

layout(std430, set = 0, binding = 40) readonly buffer Queries { TwinQuery queries[]; };
layout(std430, set = 0, binding = 41) writeonly buffer Results { TwinResult results[]; };
layout(push_constant) uniform Push { uint count; };

void main() {
  uint id = gl_GlobalInvocationID.x;
  if (id >= count) return;
  TwinQuery q = queries[id];
  TwinResult r;
  HtexHalfedgePoint p = htex_locate_in_face(q.ids.y, q.bary.xyz);
  r.locate = ivec4(p.halfedge, 0, 0, 0);
  r.uv = vec4(p.uv, 0.0, 0.0);
  HtexQuadPoint quads[3];
  htex_face_point_quads(q.ids.y, q.bary.xyz, quads);
  r.quad_edges = uvec4(quads[0].edge, quads[1].edge, quads[2].edge, 0u);
  for (int k = 0; k < 3; ++k) r.quad_xy[k] = vec4(quads[k].xy, 0.0, 0.0);
  HtexFootprint fp = htex_footprint(q.ids.x, q.ids.y, q.bary.xyz, q.ids.z);
  r.lod = vec4(htex_level_of_detail(q.ids.x, q.ids.y, q.bary.xyz, q.dx.xyz, q.dy.xyz), fp.alpha, float(fp.count), 0.0);
  for (uint k = 0u; k < 12u; ++k) {
    r.fp_texel[k] = uvec4(0u);
    r.fp_virtual[k] = uvec4(0u);
    r.fp_back[k] = uvec4(0u);
    r.fp_weight[k / 4u][k % 4u] = 0.0;
    if (k >= fp.count) continue;
    r.fp_texel[k] = fp.texel[k];
    r.fp_weight[k / 4u][k % 4u] = fp.weight[k];
    uvec2 v = htex_virtual_texel(q.ids.x, fp.texel[k].x, fp.texel[k].y, fp.texel[k].z, fp.texel[k].w);
    HtexTexelAddress back;
    bool found = htex_texel_at(v, back);
    r.fp_virtual[k] = uvec4(v, found ? 1u : 0u, htex_shadel_of(v));
    r.fp_back[k] = uvec4(back.quad, back.level, back.i, back.j);
  }
  HtexTexelPoint t = htex_texel_point(q.texel.x, q.texel.y, q.texel.z, q.texel.w, q.ids.w != 0u);
  r.tp = uvec4(t.face, t.ghost ? 1u : 0u, t.vertex ? 1u : 0u, 0u);
  r.tp_bary = vec4(t.bary, 0.0);
  results[id] = r;
}
