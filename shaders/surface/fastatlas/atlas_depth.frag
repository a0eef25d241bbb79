#version 460
// The triangle-ID atlas, first of two draws: each covered texel keeps the nearest depth (reversed
// z: the largest; positive floats order as their bits). A depth attachment would do this, but its
// clear over the whole atlas cost more than the rest of the atlasing (clear.comp says why).
#extension GL_GOOGLE_include_directive : require
#include "../../shared/fastatlas.h"

layout(set = 0, binding = PRISMOID_FA_BINDING_DEPTH_ATLAS, r32ui) uniform uimage2D fa_depth_atlas;

void main() { imageAtomicMax(fa_depth_atlas, ivec2(gl_FragCoord.xy), floatBitsToUint(gl_FragCoord.z)); }
