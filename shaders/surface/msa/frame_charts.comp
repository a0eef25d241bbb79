#version 460
// Per-frame charts (Neff et al. 2022, 3.2, the MSA-P and MSA-O parametrizations): before the
// visibility pass, every meshlet's chart is made anew from this frame's camera. Perspective: each
// corner's position in the image (pixels, y down), so a texel per chart unit is a texel per pixel;
// a meshlet with a corner nearer than the near plane, where the division would fold it, takes the
// orthographic chart instead. Orthographic (the paper's "camera looking towards the meshlet
// center"): the corners projected along the direction from the eye to the meshlet's centre (the
// mean of its triangles' corners) onto the plane across it, in world units; a surface seen edge-on
// along the camera's own axis (a floor at eye height) is not degenerate there. The chart is shifted
// so that its lower corner is at 0, and its rectangle is the meshlet's extent. The CPU twin is
// msa::frame_charts.
#extension GL_GOOGLE_include_directive : require
#define PRISMOID_SURFACE_VERTEX_BUFFERS
#include "../scene_bindings.glsl"
#include "msa.glsl"

layout(local_size_x = 64) in;

void main() {
  uint m = gl_GlobalInvocationID.y * gl_NumWorkGroups.x * 64u + gl_GlobalInvocationID.x;
  if (m >= msa_push.atlas.z) return;
  MsaMeshletGpu meshlet = msa_meshlets[m];
  float near = uintBitsToFloat(msa_push.limits.z);
  bool perspective = (msa_push.image.z & PRISMOID_MSA_FLAG_PERSPECTIVE) != 0u;
  for (uint k = 0u; perspective && k < meshlet.info.y; ++k) {
    uint t = msa_meshlet_triangles[meshlet.info.x + k];
    for (uint c = 0u; c < 3u; ++c)
      if (-(frame.view * vec4(triangle_corner(t, c), 1.0)).z < near) perspective = false;
  }
  // The orthographic projection's axes (camera space): across the direction to the centre.
  vec3 centre = vec3(0.0);
  for (uint k = 0u; k < meshlet.info.y; ++k) {
    uint t = msa_meshlet_triangles[meshlet.info.x + k];
    for (uint c = 0u; c < 3u; ++c) centre += (frame.view * vec4(triangle_corner(t, c), 1.0)).xyz;
  }
  vec3 axis = length(centre) > 0.0 ? normalize(centre) : vec3(0.0, 0.0, -1.0);
  vec3 side = cross(axis, vec3(0.0, 1.0, 0.0));
  side = length(side) > 1e-6 ? normalize(side) : vec3(1.0, 0.0, 0.0);
  vec3 rise = cross(side, axis);
  vec2 lo = vec2(3.0e38), hi = vec2(-3.0e38);
  for (uint pass = 0u; pass < 2u; ++pass)
    for (uint k = 0u; k < meshlet.info.y; ++k) {
      uint t = msa_meshlet_triangles[meshlet.info.x + k];
      vec2 q[3];
      for (uint c = 0u; c < 3u; ++c) {
        vec3 v = (frame.view * vec4(triangle_corner(t, c), 1.0)).xyz;
        q[c] = perspective ? vec2((v.x / (-v.z * frame.camera_right.w) + 1.0) * 0.5 * float(msa_push.image.x),
                                  (1.0 - v.y / (-v.z * frame.camera_up.w)) * 0.5 * float(msa_push.image.y))
                           : vec2(dot(v, side), dot(v, rise));
        lo = min(lo, q[c]);
        hi = max(hi, q[c]);
      }
      if (pass == 1u) {
        msa_triangles[t].c01 = vec4(q[0] - lo, q[1] - lo);
        msa_triangles[t].c2 = vec4(q[2] - lo, 0.0, 0.0);
      }
    }
  msa_meshlets[m].extent = vec4(max(hi - lo, vec2(0.0)), 0.0, 0.0);
  msa_meshlets[m].info.z = perspective ? 1u : 0u;
}
