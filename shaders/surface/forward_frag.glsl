// The forward shading pass's fragment stage (forward.frag, forward_counted.frag): one
// invocation per covered pixel, since the depth pre-pass has left only the nearest surface's
// depth and this pass tests EQUAL before shading (early fragment tests).
#extension GL_GOOGLE_include_directive : require

#include "shading.glsl"

layout(early_fragment_tests) in;

layout(location = 0) in vec3 v_position;
layout(location = 1) in vec3 v_normal;
layout(location = 2) in vec3 v_color;
layout(location = 0) out vec4 out_color;

#ifdef PRISMOID_COUNT_SHADING
layout(set = 0, binding = PRISMOID_SURFACE_BINDING_SHADE_COUNT, r32ui) uniform uimage2D shade_count;
#endif

void main() {
  uint triangle = uint(gl_PrimitiveID);
  SurfaceTriangleGpu tri = triangles[triangle];
  SurfacePoint sp = make_surface_point(v_position, tri.normal.xyz, v_normal, frame.eye.xyz, triangle);
  SurfaceMaterialGpu material = materials[tri.info.x];
  ShadingMaterial m = shading_material(material, v_color * tri.color.rgb);
  out_color = vec4(shade_surface_point(sp, m, material.emission.rgb), 1.0);
#ifdef PRISMOID_COUNT_SHADING
  imageAtomicAdd(shade_count, ivec2(gl_FragCoord.xy), 1u);
#endif
}
