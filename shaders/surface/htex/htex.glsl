// Htex on the GPU: the float twins of renderer/surface/htex/htex_layout.cpp (charts, quads, atlas
// addressing, texel points) and renderer/reference/htex_reference.cpp (the lookup's footprint and
// level of detail), line for line, over the global tables of shaders/shared/htex.h. Tested
// against the double-precision C++ at many points (tests/surface/test_htex_gpu.cpp).
#ifndef PRISMOID_HTEX_GLSL
#define PRISMOID_HTEX_GLSL

#include "../../shared/htex.h"

// The descriptor set of the tables (0 for the Htex passes; a pass whose set 0 is taken, e.g. the
// GI host, defines another before including this file).
#ifndef PRISMOID_HTEX_SET
#define PRISMOID_HTEX_SET 0
#endif

layout(std430, set = PRISMOID_HTEX_SET, binding = PRISMOID_HTEX_BINDING_MESHES) readonly buffer HtexMeshBuffer {
  HtexAtlasGpu htex_atlas;
  HtexMeshGpu htex_meshes[];
};
layout(std430, set = PRISMOID_HTEX_SET, binding = PRISMOID_HTEX_BINDING_TWIN) readonly buffer HtexTwinBuffer { int htex_twin[]; };
layout(std430, set = PRISMOID_HTEX_SET, binding = PRISMOID_HTEX_BINDING_EDGE_OF) readonly buffer HtexEdgeOfBuffer { uint htex_edge_of[]; };
layout(std430, set = PRISMOID_HTEX_SET, binding = PRISMOID_HTEX_BINDING_EDGE_HALFEDGE) readonly buffer HtexEdgeHalfedgeBuffer { int htex_edge_halfedge[]; };
layout(std430, set = PRISMOID_HTEX_SET, binding = PRISMOID_HTEX_BINDING_FACE_OF_TRIANGLE) readonly buffer HtexFaceOfTriangleBuffer { uint htex_face_of_triangle[]; };
layout(std430, set = PRISMOID_HTEX_SET, binding = PRISMOID_HTEX_BINDING_TRIANGLE_OF_FACE) readonly buffer HtexTriangleOfFaceBuffer { uint htex_triangle_of_face[]; };
layout(std430, set = PRISMOID_HTEX_SET, binding = PRISMOID_HTEX_BINDING_SHADEL_REGION) readonly buffer HtexShadelRegionBuffer { uint htex_shadel_region[]; };
layout(std430, set = PRISMOID_HTEX_SET, binding = PRISMOID_HTEX_BINDING_VERTEX_CORNER) readonly buffer HtexVertexCornerBuffer { int htex_vertex_corner[]; };

// ---- Halfedges (global ids; scene/halfedge_mesh.hpp) ----------------------------------------
int htex_face(int h) { return h / 3; }
int htex_corner(int h) { return h % 3; }
int htex_next(int h) { return h - h % 3 + (h % 3 + 1) % 3; }
int htex_prev(int h) { return h - h % 3 + (h % 3 + 2) % 3; }
bool htex_primary(int h) { return htex_twin[h] < h; }  // true on a boundary (twin -1)

// ---- Mesh layout -------------------------------------------------------------------------
uint htex_side(uint mesh, uint level) { return (1u << htex_meshes[mesh].info.z) >> level; }
uvec2 htex_origin(uint mesh, uint level) {
  uvec4 o = htex_meshes[mesh].origin[level / 2u];
  return (level % 2u) == 0u ? o.xy : o.zw;
}

// ---- Charts (htex::locate_in_face, face_barycentric, quad_coordinates) --------------------
struct HtexHalfedgePoint {
  int halfedge;  // global
  vec2 uv;
};

HtexHalfedgePoint htex_locate_in_face(uint face, vec3 bary) {
  int m = 0;
  if (bary[1] < bary[m]) m = 1;
  if (bary[2] < bary[m]) m = 2;
  int k = (m + 1) % 3;
  HtexHalfedgePoint p;
  p.halfedge = int(3u * face) + k;
  p.uv = vec2(bary[k] - bary[m], bary[(k + 1) % 3] - bary[m]);
  return p;
}

// The unit vector along component k (0, 1 or 2). Components are set through it rather than by
// a dynamically indexed write (b[k] += x): NVIDIA's driver (580) dropped such writes to a local
// vector in ray-generation shaders, so texel points came out wrong on the GPU machine while the
// same code was right in compute shaders and on lavapipe.
vec3 htex_unit3(int k) { return vec3(equal(ivec3(k), ivec3(0, 1, 2))); }

vec3 htex_face_barycentric(int halfedge, vec2 uv) {
  int k = htex_corner(halfedge);
  return vec3((1.0 - uv.x - uv.y) / 3.0) + uv.x * htex_unit3(k) + uv.y * htex_unit3((k + 1) % 3);
}

vec2 htex_quad_coordinates(int halfedge, vec2 uv) { return htex_primary(halfedge) ? uv : vec2(1.0) - uv; }

struct HtexQuadPoint {
  uint edge;  // global edge = quad id
  vec2 xy;
};

// The three quads a point of a face blends (htex::face_point_quads).
void htex_face_point_quads(uint face, vec3 bary, out HtexQuadPoint quads[3]) {
  HtexHalfedgePoint p = htex_locate_in_face(face, bary);
  int h = p.halfedge, n = htex_next(h), q = htex_prev(h);
  float u = p.uv.x, v = p.uv.y;
  quads[0] = HtexQuadPoint(htex_edge_of[h], htex_quad_coordinates(h, vec2(u, v)));
  quads[1] = HtexQuadPoint(htex_edge_of[n], htex_quad_coordinates(n, vec2(v, -u)));
  quads[2] = HtexQuadPoint(htex_edge_of[q], htex_quad_coordinates(q, vec2(-v, u)));
}

// ---- Texel points (htex::quad_surface_point, texel_point) ---------------------------------
struct HtexTexelPoint {
  uint face;   // global
  vec3 bary;   // of the face's corners; one weight < 0 for a ghost texel
  bool ghost;  // beyond a boundary edge, in the face's plane
  bool vertex; // a vertex-corner texel: bary is one-hot at that vertex
};

HtexTexelPoint htex_quad_surface_point(uint edge, vec2 xy) {
  int p = htex_edge_halfedge[edge];
  int t = htex_twin[p];
  HtexTexelPoint s;
  s.vertex = false;
  if (xy.x + xy.y <= 1.0 || t < 0) {
    s.face = uint(htex_face(p));
    s.bary = htex_face_barycentric(p, xy);
    s.ghost = xy.x + xy.y > 1.0;
  } else {
    s.face = uint(htex_face(t));
    s.bary = htex_face_barycentric(t, vec2(1.0) - xy);
    s.ghost = false;
  }
  return s;
}

HtexTexelPoint htex_texel_point(uint edge, uint n, uint i, uint j, bool snap_vertex_corners) {
  if (snap_vertex_corners && n >= 2u && ((i == n - 1u && j == 0u) || (i == 0u && j == n - 1u))) {
    int p = htex_edge_halfedge[edge];
    int c = htex_vertex_corner[i == n - 1u ? p : htex_next(p)];  // start(p) at (1, 0), end(p) at (0, 1)
    HtexTexelPoint s;
    s.face = uint(htex_face(c));
    s.bary = htex_unit3(htex_corner(c));
    s.ghost = false;
    s.vertex = true;
    return s;
  }
  return htex_quad_surface_point(edge, vec2((float(i) + 0.5) / float(n), (float(j) + 0.5) / float(n)));
}

// ---- Atlas addressing (AtlasLayout::virtual_texel, texel_at) ------------------------------
struct HtexTexelAddress {
  uint quad;  // global
  uint level;
  uint i, j;
  uint mesh;
};

uvec2 htex_virtual_texel(uint mesh, uint quad, uint level, uint i, uint j) {
  HtexMeshGpu m = htex_meshes[mesh];
  uint n = htex_side(mesh, level);
  uint local = quad - m.info.x;
  return htex_origin(mesh, level) + uvec2((local % m.grid.x) * n + i, (local / m.grid.x) * n + j);
}

uint htex_shadel_of(uvec2 v) { return (v.y / PRISMOID_HTEX_SHADEL_TEXELS) * htex_atlas.size.z + v.x / PRISMOID_HTEX_SHADEL_TEXELS; }
uint htex_group_of(uvec2 v) { return (v.y / PRISMOID_HTEX_GROUP_TEXELS) * htex_atlas.size.w + v.x / PRISMOID_HTEX_GROUP_TEXELS; }
// The occupancy bit of the shadel holding virtual texel v within its group.
uint htex_group_bit(uvec2 v) { return ((v.y / 8u) % 8u) * 8u + (v.x / 8u) % 8u; }
// Where virtual texel v lives in the pool of a resident group with page `page`.
uint htex_slot(uint page, uvec2 v) { return page * PRISMOID_HTEX_PAGE_TEXELS + (v.y % 64u) * 64u + v.x % 64u; }

bool htex_texel_at(uvec2 v, out HtexTexelAddress t) {
  t = HtexTexelAddress(0u, 0u, 0u, 0u, 0u);
  if (v.x >= htex_atlas.size.x || v.y >= htex_atlas.size.y) return false;
  uint region = htex_shadel_region[htex_shadel_of(v)];
  if (region == PRISMOID_HTEX_NONE) return false;
  uint mesh = region / 16u, level = region % 16u;
  HtexMeshGpu m = htex_meshes[mesh];
  uint n = htex_side(mesh, level);
  uvec2 d = v - htex_origin(mesh, level);
  uint column = d.x / n, row = d.y / n;
  if (column >= m.grid.x || row >= m.grid.y) return false;
  uint local = row * m.grid.x + column;
  if (local >= m.info.y) return false;
  t = HtexTexelAddress(m.info.x + local, level, d.x % n, d.y % n, mesh);
  return true;
}

// ---- The lookup's footprint (reference::htex_footprint) -----------------------------------
struct HtexFootprint {
  uint count;
  float alpha;  // the sum of the three alpha masks (the divisor)
  uvec4 texel[PRISMOID_HTEX_FOOTPRINT];  // x: quad (global), y: level, z: i, w: j
  float weight[PRISMOID_HTEX_FOOTPRINT]; // normalized
};

HtexFootprint htex_footprint(uint mesh, uint face, vec3 bary, uint level) {
  uint n = htex_side(mesh, level);
  HtexQuadPoint quads[3];
  htex_face_point_quads(face, bary, quads);
  HtexFootprint fp;
  fp.count = 0u;
  fp.alpha = 0.0;
  // `precise`: no contraction, so every stage (marking, re-marking, gather) computes the same
  // footprint from the same inputs.
  for (int q = 0; q < 3; ++q) {
    precise vec2 s = quads[q].xy * float(n) - 0.5;
    vec2 i0 = floor(s);
    precise vec2 f = s - i0;
    for (int dy = 0; dy < 2; ++dy)
      for (int dx = 0; dx < 2; ++dx) {
        int i = int(i0.x) + dx, j = int(i0.y) + dy;
        precise float w = (dx == 1 ? f.x : 1.0 - f.x) * (dy == 1 ? f.y : 1.0 - f.y);
        if (i < 0 || j < 0 || i >= int(n) || j >= int(n) || !(w > 0.0)) continue;  // border: colour and alpha 0
        fp.texel[fp.count] = uvec4(quads[q].edge, level, uint(i), uint(j));
        fp.weight[fp.count] = w;
        fp.alpha += w;
        ++fp.count;
      }
  }
  for (uint k = 0u; k < fp.count; ++k) fp.weight[k] /= fp.alpha;
  return fp;
}

// ---- Level of detail (reference::htex_level_of_detail) -----------------------------------
float htex_level_of_detail(uint mesh, uint face, vec3 bary, vec3 dbary_dx, vec3 dbary_dy) {
  HtexHalfedgePoint p = htex_locate_in_face(face, bary);
  int k = htex_corner(p.halfedge), m = (k + 2) % 3;
  vec2 lx = vec2(dbary_dx[k] - dbary_dx[m], dbary_dx[(k + 1) % 3] - dbary_dx[m]);
  vec2 ly = vec2(dbary_dy[k] - dbary_dy[m], dbary_dy[(k + 1) % 3] - dbary_dy[m]);
  return log2(max(length(lx), length(ly)) * float(htex_side(mesh, 0u)));
}

// The level a pixel reads: the level of detail plus `bias`, rounded to the nearest level
// (about one texel per pixel along the pixel's longer footprint axis), clamped to the mesh's
// chain, and never below `floor_level` (the allocator's bias, Li & Guo 3.3).
uint htex_pick_level(uint mesh, float lod, float bias, uint floor_level) {
  float l = lod + bias + 0.5;
  uint last = htex_meshes[mesh].info.w - 1u;
  uint level = l >= 1.0 ? uint(min(floor(l), float(last))) : 0u;  // NaN and -inf (a point) give level 0
  return min(max(level, floor_level), last);
}

#endif
