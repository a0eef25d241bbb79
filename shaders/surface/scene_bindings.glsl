// The scene's shading data in set 0 (shaders/shared/surface.h lists the bindings).
#ifndef PRISMOID_SURFACE_SCENE_BINDINGS_GLSL
#define PRISMOID_SURFACE_SCENE_BINDINGS_GLSL

#include "../shared/surface.h"

layout(set = 0, binding = PRISMOID_SURFACE_BINDING_FRAME) uniform SurfaceFrameBlock { SurfaceFrame frame; };
layout(std430, set = 0, binding = PRISMOID_SURFACE_BINDING_MATERIALS) readonly buffer MaterialBuffer { SurfaceMaterialGpu materials[]; };
layout(std430, set = 0, binding = PRISMOID_SURFACE_BINDING_TRIANGLES) readonly buffer TriangleBuffer { SurfaceTriangleGpu triangles[]; };
layout(std430, set = 0, binding = PRISMOID_SURFACE_BINDING_POINT_LIGHTS) readonly buffer PointLightBuffer { PointLightGpu point_lights[]; };
layout(std430, set = 0, binding = PRISMOID_SURFACE_BINDING_DIRECTIONAL_LIGHTS) readonly buffer DirectionalLightBuffer {
  DirectionalLightGpu directional_lights[];
};
layout(std430, set = 0, binding = PRISMOID_SURFACE_BINDING_EMITTERS) readonly buffer EmitterBuffer { EmitterGpu emitters[]; };

#ifdef PRISMOID_SURFACE_VERTEX_BUFFERS
layout(std430, set = 0, binding = PRISMOID_SURFACE_BINDING_POSITIONS) readonly buffer PositionBuffer { float vertex_positions[]; };
layout(std430, set = 0, binding = PRISMOID_SURFACE_BINDING_ATTRIBUTES) readonly buffer AttributeBuffer { float vertex_attributes[]; };
layout(std430, set = 0, binding = PRISMOID_SURFACE_BINDING_INDICES) readonly buffer IndexBuffer { uint triangle_indices[]; };
layout(std430, set = 0, binding = PRISMOID_SURFACE_BINDING_MESHES) readonly buffer MeshBuffer { SurfaceMeshGpu scene_meshes[]; };
#endif

#endif
