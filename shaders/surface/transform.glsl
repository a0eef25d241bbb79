// The clip-space position of a scene-local point. Both the depth pre-pass and the shading pass
// compute it with this same expression under `invariant`, so the shading pass's EQUAL depth
// test passes exactly where the pre-pass left the nearest surface.
#ifndef PRISMOID_SURFACE_TRANSFORM_GLSL
#define PRISMOID_SURFACE_TRANSFORM_GLSL

#include "../shared/surface.h"

layout(set = 0, binding = PRISMOID_SURFACE_BINDING_FRAME) uniform SurfaceFrameBlock { SurfaceFrame frame; };

invariant gl_Position;

vec4 surface_clip_position(vec3 position) { return frame.projection * (frame.view * vec4(position, 1.0)); }

#endif
