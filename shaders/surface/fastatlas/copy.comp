#version 460
// Temporal reuse (FastAtlas, appendix D): the rows of the colour atlas the last frame used, kept
// before this frame's shading writes over them (dispatched over those rows alone).
#extension GL_GOOGLE_include_directive : require
#include "fastatlas.glsl"

layout(local_size_x = 16, local_size_y = 16) in;
layout(set = 0, binding = PRISMOID_FA_BINDING_COLOR_ATLAS, rgba32f) uniform readonly image2D fa_color_atlas;
layout(set = 0, binding = PRISMOID_FA_BINDING_PREV_COLOR, rgba32f) uniform writeonly image2D fa_prev_color;

void main() {
  ivec2 t = ivec2(gl_GlobalInvocationID.xy);
  if (t.x >= int(fa_push.atlas.x) || t.y >= int(fa_push.atlas.y)) return;
  imageStore(fa_prev_color, t, imageLoad(fa_color_atlas, t));
}
