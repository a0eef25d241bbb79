#version 460
// The triangle-ID and depth atlases made empty where this frame draws, or the last one drew
// (rows below both are never read: shading and the lookup stay in the rows used, the border pass
// reads no row beyond them). Clearing only those rows, in compute, rather than the whole atlas as
// a render pass's clear: on the GPU machine, whose graphics work runs on 2 TPCs, clearing two 8K
// attachments took 9.6 ms of a frame.
#extension GL_GOOGLE_include_directive : require
#include "fastatlas.glsl"

layout(local_size_x = 16, local_size_y = 16) in;
layout(set = 0, binding = PRISMOID_FA_BINDING_ID_ATLAS, r32ui) uniform writeonly uimage2D fa_id_atlas;
layout(set = 0, binding = PRISMOID_FA_BINDING_DEPTH_ATLAS, r32ui) uniform writeonly uimage2D fa_depth_atlas;

void main() {
  ivec2 t = ivec2(gl_GlobalInvocationID.xy);
  if (t.x >= int(fa_push.atlas.x) || t.y >= int(fa_push.atlas.y)) return;
  imageStore(fa_id_atlas, t, uvec4(PRISMOID_FA_NONE));
  imageStore(fa_depth_atlas, t, uvec4(0u));
}
