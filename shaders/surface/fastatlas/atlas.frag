#version 460
// The triangle-ID atlas, second draw: the triangle whose depth is the texel's nearest keeps it
// (the same vertex shader, so the same depth bit for bit); of two at the same depth the lower
// triangle, whatever order they arrive in.
#extension GL_GOOGLE_include_directive : require
#include "../../shared/fastatlas.h"

layout(location = 0) flat in uint in_triangle;
layout(set = 0, binding = PRISMOID_FA_BINDING_ID_ATLAS, r32ui) uniform uimage2D fa_id_atlas;
layout(set = 0, binding = PRISMOID_FA_BINDING_DEPTH_ATLAS, r32ui) uniform readonly uimage2D fa_depth_atlas;

void main() {
  ivec2 t = ivec2(gl_FragCoord.xy);
  if (imageLoad(fa_depth_atlas, t).x == floatBitsToUint(gl_FragCoord.z)) imageAtomicMin(fa_id_atlas, t, in_triangle);
}
