#version 460
// Turns accumulated optical depth into the frame's display colour and its numeric quantity.
#extension GL_GOOGLE_include_directive : require
#include "../shared/volume.h"

layout(local_size_x = 8, local_size_y = 8) in;
layout(set = 0, binding = 0, r32f) uniform readonly image2D optical_depth;
layout(set = 0, binding = 1, rgba32f) uniform writeonly image2D display;
layout(set = 0, binding = 2, r32f) uniform writeonly image2D quantity;
layout(push_constant) uniform Push { ResolvePush push; };

void main() {
  ivec2 p = ivec2(gl_GlobalInvocationID.xy);
  if (p.x >= int(push.params.y) || p.y >= int(push.params.z)) return;
  float tau = imageLoad(optical_depth, p).r;
  float transmittance = exp(-tau);
  float value = (push.params.x == PRISMOID_QUANTITY_TRANSMITTANCE) ? transmittance : tau;
  imageStore(quantity, p, vec4(value, 0.0, 0.0, 1.0));
  imageStore(display, p, vec4(mix(push.medium.rgb, push.background.rgb, transmittance), 1.0));
}
