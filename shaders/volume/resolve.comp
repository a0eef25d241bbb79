#version 460
// Turns what the interval pass accumulated into the frame's display colour and its numeric
// quantity: optical depth (additive) or composited emission (premultiplied colour, alpha).
#extension GL_GOOGLE_include_directive : require
#include "../shared/volume.h"

layout(local_size_x = 8, local_size_y = 8) in;
layout(set = 0, binding = 0, r32f) uniform readonly image2D optical_depth;
layout(set = 0, binding = 1, rgba32f) uniform writeonly image2D display;
layout(set = 0, binding = 2, r32f) uniform writeonly image2D quantity;
layout(set = 0, binding = 3, rgba32f) uniform readonly image2D emission;
layout(push_constant) uniform Push { ResolvePush push; };

void main() {
  ivec2 p = ivec2(gl_GlobalInvocationID.xy);
  if (p.x >= int(push.params.y) || p.y >= int(push.params.z)) return;
  if (push.params.x == PRISMOID_QUANTITY_COLOR) {
    vec4 c = imageLoad(emission, p);  // premultiplied colour, alpha = 1 - transmittance
    float transmittance = 1.0 - c.a;
    imageStore(quantity, p, vec4(transmittance, 0.0, 0.0, 1.0));
    imageStore(display, p, vec4(c.rgb + transmittance * push.background.rgb, 1.0));
    return;
  }
  if (push.params.x == PRISMOID_QUANTITY_ISOSURFACE) {
    vec4 hit = imageLoad(emission, p);  // shaded rgb, distance to the hit (0: none)
    imageStore(quantity, p, vec4(hit.a, 0.0, 0.0, 1.0));
    imageStore(display, p, vec4(hit.a > 0.0 ? hit.rgb : push.background.rgb, 1.0));
    return;
  }
  float tau = imageLoad(optical_depth, p).r;
  float transmittance = exp(-tau);
  float value = (push.params.x == PRISMOID_QUANTITY_TRANSMITTANCE) ? transmittance : tau;
  imageStore(quantity, p, vec4(value, 0.0, 0.0, 1.0));
  imageStore(display, p, vec4(mix(push.medium.rgb, push.background.rgb, transmittance), 1.0));
}
