#version 460
// The sky's radiance along each pixel's ray (Sky::radiance) where no surface is seen; alpha 0.
#extension GL_GOOGLE_include_directive : require
#include "scene_bindings.glsl"

layout(location = 0) out vec4 out_color;

void main() {
  // The pixel's image point, in the convention of reference::ray_direction (row 0 at the top).
  vec2 ndc = (gl_FragCoord.xy + frame.subpixel.xy) * frame.viewport.zw * 2.0 - 1.0;
  vec3 d = normalize(frame.camera_forward.xyz + ndc.x * frame.camera_right.w * frame.camera_right.xyz -
                     ndc.y * frame.camera_up.w * frame.camera_up.xyz);
  float t = 0.5 * (1.0 + dot(d, frame.sky_up.xyz));
  out_color = vec4(frame.sky_bottom.rgb + (frame.sky_top.rgb - frame.sky_bottom.rgb) * t, 0.0);
}
