// The meshlet shading atlas's shading pass (Neff et al. 2022, 3: "shading of allocated blocks"):
// one ray-generation invocation per texel of each queued 8 x 8 tile of a block, launched as
// (8, 8, tiles) by vkCmdTraceRaysIndirectKHR. The texel's centre, mapped back into the meshlet's
// chart, lies in one of its triangles (the lowest in the meshlet's list on a shared edge), or
// within sqrt(2) texels of the nearest one (the one-texel dilation bilinear taps need: the point
// extrapolated in that triangle's plane, up to a triangle's width out), or outside the meshlet (alpha 0: never read). The shared
// shading code shades the point. Included by shade.rgen (shadow rays) and shade_unshadowed.rgen.
#extension GL_GOOGLE_include_directive : require
#ifndef PRISMOID_SURFACE_VERTEX_BUFFERS
#define PRISMOID_SURFACE_VERTEX_BUFFERS
#endif
#include "../surface_point.glsl"
#include "msa.glsl"

// Barycentric weights of chart point q in the triangle's chart corners (vec3(-1) if degenerate).
vec3 msa_chart_barycentric(uint triangle, vec2 q) {
  MsaTriangleGpu t = msa_triangles[triangle];
  vec2 d1 = t.c01.zw - t.c01.xy, d2 = t.c2.xy - t.c01.xy, r = q - t.c01.xy;
  float det = d1.x * d2.y - d1.y * d2.x;
  if (det == 0.0) return vec3(-1.0);
  float b1 = (r.x * d2.y - r.y * d2.x) / det, b2 = (d1.x * r.y - d1.y * r.x) / det;
  return vec3(1.0 - b1 - b2, b1, b2);
}

float msa_segment_distance(vec2 q, vec2 a, vec2 b) {
  vec2 ab = b - a;
  float l = dot(ab, ab);
  float t = l > 0.0 ? clamp(dot(q - a, ab) / l, 0.0, 1.0) : 0.0;
  return length(q - (a + t * ab));
}

void main() {
  uint queued = gl_LaunchIDEXT.z * PRISMOID_MSA_TILES_PER_LAUNCH + gl_LaunchIDEXT.y / 8u;  // PRISMOID_MSA_TILES_PER_LAUNCH says why
  if (queued >= msa_state.demand.w) return;
  uint task = msa_tasks[queued];
  uint m = task >> 12u, tile = task & 0xfffu;
  MsaBlockGpu b = msa_blocks[m];
  uvec2 size = msa_class_size(b.block.z);
  uint tiles_x = size.x / 8u;
  uvec2 local = uvec2((tile % tiles_x) * 8u + gl_LaunchIDEXT.x, (tile / tiles_x) * 8u + gl_LaunchIDEXT.y % 8u);
  uint index = msa_texel_index(b.block.xy + local);
  MsaMeshletGpu meshlet = msa_meshlets[m];
  float s = msa_block_scale(meshlet.extent.xy, b.block.z);
  vec2 q = (vec2(local) + 0.5 - 1.0) / s;
  uint best = PRISMOID_MSA_NONE;
  vec3 best_bary = vec3(0.0);
  float best_distance = sqrt(2.0) / s;  // the dilation: taps of any point inside lie within sqrt(2) texels
  // Per-frame charts project the meshlet onto the image plane, where its triangles can overlap
  // (a fold away from the eye, or its back behind its front): of the triangles holding the point
  // the one nearest the eye along the view, as the image shows it, is shaded.
  bool nearest = (msa_push.image.z & PRISMOID_MSA_FLAG_FRAME_CHARTS) != 0u;
  bool perspective = meshlet.info.z == 1u;
  float best_depth = 3.0e38;
  bool inside = false;
  for (uint k = 0u; k < meshlet.info.y; ++k) {
    uint triangle = msa_meshlet_triangles[meshlet.info.x + k];
    vec3 w = msa_chart_barycentric(triangle, q);
    if (w == vec3(-1.0)) continue;
    if (perspective) w = msa_surface_weights(w, msa_corner_depths(triangle));
    if (min(w.x, min(w.y, w.z)) >= 0.0) {
      float depth = nearest ? dot(triangle_point(triangle, w) - frame.eye.xyz, frame.camera_forward.xyz) : 0.0;
      if (!inside || depth < best_depth) {
        best = triangle;
        best_bary = w;
        best_depth = depth;
      }
      inside = true;
      if (!nearest) break;
      continue;
    }
    if (inside) continue;
    MsaTriangleGpu t = msa_triangles[triangle];
    float d = min(msa_segment_distance(q, t.c01.xy, t.c01.zw), min(msa_segment_distance(q, t.c01.zw, t.c2.xy), msa_segment_distance(q, t.c2.xy, t.c01.xy)));
    if (d <= best_distance) {
      best_distance = d;
      best = triangle;
      // A border texel near a triangle seen almost edge-on in the chart would extrapolate far along
      // its plane (weights in the tens): beyond a triangle's width out, the nearest point of the
      // triangle stands in, which rounding cannot move far.
      best_bary = min(w.x, min(w.y, w.z)) < -1.0 ? clamp_to_triangle(w) : w;
    }
  }
  if (best == PRISMOID_MSA_NONE) {
    msa_result[index] = vec4(0.0);
    return;
  }
  ShadingInput si = shading_input_at(best, best_bary, triangle_point(best, best_bary), frame.eye.xyz);
  msa_result[index] = vec4(shade_surface_point(si.point, si.material, si.emission), 1.0);
  atomicAdd(msa_state.trace.w, 1u);
}
