// Interval shading (Tricard 2024): each invocation projects one tetrahedron and emits its
// screen-space proxy at z = 0, w = 1, so the rasterizer interpolates 1/depth of the front
// and back surfaces with screen-space barycentrics. A workgroup handles
// PRISMOID_TETS_PER_WORKGROUP cells (1: the paper's one cell per workgroup), set by the file
// that includes this body (interval_w*.mesh).
#include "../shared/volume.h"
#include "near_clip.glsl"
#include "tet_projection.glsl"

layout(local_size_x = PRISMOID_TETS_PER_WORKGROUP) in;
layout(triangles, max_vertices = PRISMOID_WORKGROUP_MAX_VERTICES, max_primitives = PRISMOID_WORKGROUP_MAX_TRIANGLES) out;

#include "mesh_bindings.glsl"
layout(std430, set = 0, binding = PRISMOID_BINDING_ORDER) readonly buffer Order { uint draw_order[]; };
// The first workgroup of this draw: a mesh of more workgroups than one draw may launch
// (maxMeshWorkGroupCount) is drawn in consecutive draws, which keep the primitive order.
layout(push_constant) uniform MeshPush { uint first_group; } mesh_push;

#include "cell_field.glsl"

// Per bounding surface a, b: 1/depth, and relative to the cell's reference point c (its first
// vertex): (depth - depth_c)/depth and (field - field_c)/depth (tet_projection.glsl). Every
// proxy vertex has w = 1, so perspective-correct interpolation is exactly screen-space
// interpolation; we do not declare `noperspective` because lavapipe (Mesa 25.0) interpolates
// noperspective attributes wrongly on triangles its clipper cuts (proxies reaching far outside
// the viewport: camera inside or close to big cells), which gave optical-depth errors of 20%
// there while the H100 was exact.
layout(location = 0) out vec2 v_inv_depth[];
layout(location = 2) out vec4 v_relative[];
// c in mesh-local coordinates (xyz) and the cell's field at c (w): sigma for optical depth,
// the transfer function's normalized scalar for emission (linear in the cell, or constant).
layout(location = 1) perprimitiveEXT flat out vec4 p_reference[];

shared uint s_vertex_base[PRISMOID_TETS_PER_WORKGROUP];
shared uint s_triangle_base[PRISMOID_TETS_PER_WORKGROUP];

#ifdef PRISMOID_SHARED_VERTICES
// Tetlets: the workgroup's cells were grouped (renderer/volume/tetlets.cpp) so that they share
// points; each point is loaded and transformed once, by one invocation, into shared memory.
layout(std430, set = 0, binding = PRISMOID_BINDING_TETLETS) readonly buffer Tetlets { uvec4 tetlets[]; };
layout(std430, set = 0, binding = PRISMOID_BINDING_TETLET_POINTS) readonly buffer TetletPoints { uint tetlet_points[]; };
layout(std430, set = 0, binding = PRISMOID_BINDING_TETLET_CELLS) readonly buffer TetletCells { uvec2 tetlet_cells[]; };
shared vec3 s_position[PRISMOID_TETLET_MAX_POINTS];  // mesh-local, as in Positions
shared float s_value[PRISMOID_TETLET_MAX_POINTS];  // the point field (sigma or scalar), if any
#endif

void main() {
  uint local = gl_LocalInvocationIndex;
  uint group = mesh_push.first_group + gl_WorkGroupID.x;
  uint slot = group * PRISMOID_TETS_PER_WORKGROUP + local;
  uint tet_count = frame.counts.x;
  bool emission = frame.counts.z == PRISMOID_INTEGRAND_EMISSION;
  // Primitives are rasterized and blended in the order the workgroups and, within one, the
  // primitive indices give (the Vulkan spec's primitive order), so drawing slot i with the
  // i-th cell of a front-to-back list composites front to back.
  bool per_point = frame.counts.y != 0u;
#ifdef PRISMOID_SHARED_VERTICES
  // header: first point, point count, first cell, cell count
  uvec4 header = tetlets[group];
  for (uint v = local; v < header.y; v += PRISMOID_TETS_PER_WORKGROUP) {
    uint point = tetlet_points[header.x + v];
    s_position[v] = positions[point].xyz;
    if (per_point) s_value[v] = emission ? point_scalar[point] : point_sigma[point];
  }
  barrier();
  bool valid = local < header.w;
  uvec2 entry = valid ? tetlet_cells[header.z + local] : uvec2(0u);  // cell, 4 x 8-bit local corners
  uint tet_index = entry.x;
  uint corner[4] = uint[4](entry.y & 0xffu, (entry.y >> 8) & 0xffu, (entry.y >> 16) & 0xffu, entry.y >> 24);
#else
  uint tet_index = slot;
  if (frame.counts.w != 0u && slot < tet_count) tet_index = draw_order[slot];
  bool valid = slot < tet_count;
#endif

  TetProxy proxies[3];
  uint piece_count = 0u;
  uint vertex_count = 0u, triangle_count = 0u;
  vec4 reference = vec4(0.0);
  if (valid) {
    vec3 position[4];  // mesh-local
    float value[4];    // the point field at the corners (per_point only)
#ifdef PRISMOID_SHARED_VERTICES
    for (int i = 0; i < 4; ++i) {
      position[i] = s_position[corner[i]];
      value[i] = per_point ? s_value[corner[i]] : 0.0;
    }
#else
    uvec4 idx = tets[tet_index];
    for (int i = 0; i < 4; ++i) {
      position[i] = positions[idx[i]].xyz;
      value[i] = per_point ? (emission ? point_scalar[idx[i]] : point_sigma[idx[i]]) : 0.0;
    }
#endif
    float field[4];  // the cell's field at its corners
    float sigma_max = cell_field(tet_index, emission, per_point, value, field);
    if (sigma_max > 0.0) {
      // Everything is measured from the reference point c = the first corner: the corners'
      // offsets from it are rotated differences of nearby positions, exact to the cell's size,
      // where camera-space positions are only exact to their distance from the eye. The depth
      // of the near plane relative to c comes from (near - depth of the mesh origin), computed in
      // double, plus c's depth below the origin's.
      mat3 rotation = mat3(frame.view);
      vec3 cam_c = (frame.view * vec4(position[0], 1.0)).xyz;
      vec4 cell[4];
      for (int i = 0; i < 4; ++i) cell[i] = vec4(rotation * (position[i] - position[0]), field[i]);
      cell[0].xyz = vec3(0.0);
      float near_c = frame.ray_scale.w + (rotation * position[0]).z;
      reference = vec4(position[0], field[0]);
      ClipPiece pieces[3];
      piece_count = clip_near(cell, near_c, pieces);
      if (emission) order_pieces_front_to_back(pieces, piece_count, -cam_c);
      for (uint p = 0u; p < piece_count; ++p) {
        proxies[p] = project_tetrahedron(pieces[p].v, cam_c, field[0], frame.projection);
        vertex_count += proxies[p].vertex_count;
        triangle_count += proxies[p].triangle_count;
      }
    }
  }

  // Compact the proxies of the workgroup: each invocation reserves its range.
  s_vertex_base[local] = vertex_count;
  s_triangle_base[local] = triangle_count;
  barrier();
  uint vertex_base = 0u, triangle_base = 0u, vertex_total = 0u, triangle_total = 0u;
  for (uint i = 0u; i < PRISMOID_TETS_PER_WORKGROUP; ++i) {
    if (i < local) {
      vertex_base += s_vertex_base[i];
      triangle_base += s_triangle_base[i];
    }
    vertex_total += s_vertex_base[i];
    triangle_total += s_triangle_base[i];
  }
  SetMeshOutputsEXT(vertex_total, triangle_total);

  for (uint p = 0u; p < piece_count; ++p) {
    for (uint v = 0u; v < proxies[p].vertex_count; ++v) {
      gl_MeshVerticesEXT[vertex_base + v].gl_Position = vec4(proxies[p].ndc[v], 0.0, 1.0);
      v_inv_depth[vertex_base + v] = proxies[p].inv_depth[v];
      v_relative[vertex_base + v] = proxies[p].relative[v];
    }
    for (uint t = 0u; t < proxies[p].triangle_count; ++t) {
      gl_PrimitiveTriangleIndicesEXT[triangle_base + t] = proxies[p].triangles[t] + uvec3(vertex_base);
      p_reference[triangle_base + t] = reference;
    }
    vertex_base += proxies[p].vertex_count;
    triangle_base += proxies[p].triangle_count;
  }
}
