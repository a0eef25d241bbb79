// Layouts shared by the Htex backend's shaders (shaders/surface/htex/) and renderer/surface
// (htex_tables.hpp, htex_pass.hpp). The CPU twins of the shaders' arithmetic are
// renderer/surface/htex/htex_layout.hpp (charts, quads, atlas) and renderer/reference/
// htex_reference.hpp (footprint, level of detail).
//
// Identifiers on the GPU are global over the scene's meshes: a global face is the mesh's
// first_face plus the face within the mesh, its halfedges are 3 face + k (so face, next, prev and
// corner stay arithmetic), a global edge is the mesh's first_quad plus the edge within the mesh
// and is also the quad's id in the atlas (htex::MeshLayout::first_quad).
//
// Residency (Li & Guo 3.3): the virtual atlas is cut into shadel groups of 64 x 64 texels (8 x 8
// shadels); a group is the unit of allocation. Each group has 64 occupancy bits (two uints: bit
// (sy % 8) * 8 + sx % 8 for shadel (sx, sy)), one page-table entry (a physical page or
// PRISMOID_HTEX_NOT_RESIDENT) and, when resident, 4096 texels in the pool at
// slot = page * 4096 + (y % 64) * 64 + x % 64 for virtual texel (x, y).
#ifndef PRISMOID_SHARED_HTEX_H
#define PRISMOID_SHARED_HTEX_H
#include "common.h"

PRISMOID_SHARED_BEGIN

#define PRISMOID_HTEX_NOT_RESIDENT 0xffffffffu
#define PRISMOID_HTEX_NONE 0xffffffffu
#define PRISMOID_HTEX_SHADEL_TEXELS 8u
#define PRISMOID_HTEX_GROUP_TEXELS 64u
#define PRISMOID_HTEX_PAGE_TEXELS 4096u
#define PRISMOID_HTEX_MAX_LEVELS 16u
#define PRISMOID_HTEX_FOOTPRINT 12u  // texels one lookup reads at most (4 per quad, 3 quads)

// Descriptor bindings of set 0, from PRISMOID_SURFACE_BINDING_BACKEND on (the scene's are below).
// Geometry tables (read only, written once per scene):
#define PRISMOID_HTEX_BINDING_MESHES 16            // HtexAtlasGpu, then HtexMeshGpu[] per mesh
#define PRISMOID_HTEX_BINDING_TWIN 17              // int[] per global halfedge: global twin, -1 on a boundary
#define PRISMOID_HTEX_BINDING_EDGE_OF 18           // uint[] per global halfedge: global edge (= quad)
#define PRISMOID_HTEX_BINDING_EDGE_HALFEDGE 19     // int[] per global edge: its primary (global) halfedge
#define PRISMOID_HTEX_BINDING_FACE_OF_TRIANGLE 20  // uint[] per global triangle: global face, NONE if dropped
#define PRISMOID_HTEX_BINDING_TRIANGLE_OF_FACE 21  // uint[] per global face: global triangle
#define PRISMOID_HTEX_BINDING_SHADEL_REGION 22     // uint[] per virtual shadel: mesh * 16 + level, NONE: padding
// Residency and shading (read and written by the passes):
#define PRISMOID_HTEX_BINDING_OCCUPANCY 23         // uint[] 2 per group: this frame's marked shadels
#define PRISMOID_HTEX_BINDING_PAGE_TABLE 24        // uint[] per group: physical page or NOT_RESIDENT (persists)
#define PRISMOID_HTEX_BINDING_FREE_LIST 25         // uint[] capacity: free pages, the first HtexStateGpu::persistent.x
#define PRISMOID_HTEX_BINDING_STATE 26             // HtexStateGpu: counters and the indirect launch
#define PRISMOID_HTEX_BINDING_TASKS 27             // uint[]: virtual shadel ids to shade this frame
#define PRISMOID_HTEX_BINDING_POOL 28              // vec4[] per slot: shaded radiance (rgb), a = 1 once shaded
#define PRISMOID_HTEX_BINDING_INDIRECT 29          // vec4[] per slot: indirect radiance added at gather (GI hook)
#define PRISMOID_HTEX_BINDING_VISIBILITY 30        // uvec4[] per pixel: triangle + 1 (0: sky), level, b1, b2 bits
// One more geometry table:
#define PRISMOID_HTEX_BINDING_SHADED 32            // uint[] 2 per group: shadels whose pool texels hold valid shading (persists)
#define PRISMOID_HTEX_BINDING_VERTEX_CORNER 31     // int[] per global halfedge: htex::canonical_corner (global)

// Push-constant flags.
#define PRISMOID_HTEX_FLAG_NO_SNAP 1u   // vertex-corner texels at their nominal points (tests' control only)
#define PRISMOID_HTEX_FLAG_INDIRECT 2u  // the gather adds the indirect buffer
#define PRISMOID_HTEX_FLAG_REUSE 4u     // shadels shaded in an earlier frame and still resident are not shaded again

// The allocation steps run 64 invocations per workgroup, at most this many workgroups per row of
// the dispatch (more rows beyond).
#define PRISMOID_HTEX_DISPATCH_ROW 32768u

// The allocation loop's phases (HtexStateGpu::marking.w).
#define PRISMOID_HTEX_PHASE_COUNT 0u
#define PRISMOID_HTEX_PHASE_REMARK 1u
#define PRISMOID_HTEX_PHASE_DONE 2u

struct HtexAtlasGpu {
  uvec4 size;    // x: width, y: height (virtual texels, multiples of 64), z: shadel columns, w: group columns
  uvec4 counts;  // x: groups, y: meshes, z: pool capacity (pages), w: largest level count of any mesh
};

struct HtexMeshGpu {
  uvec4 info;       // x: first_quad (global edge of the mesh's edge 0), y: quad count, z: log2 of the level-0 side, w: levels
  uvec4 grid;       // x: quad columns, y: quad rows, z: first global face, w: first global triangle
  uvec4 origin[8];  // level l's rectangle origin (virtual texel of quad 0's texel (0, 0)): origin[l / 2].xy or .zw
};

// Counters and the indirect launch. The first 64 bytes are per frame (cleared when a frame
// starts); `persistent` carries the free list's length from frame to frame.
struct HtexStateGpu {
  uvec4 trace;       // xyz: VkTraceRaysIndirectCommandKHR of the shading pass (8, 8, shadels); w: texels to shade
  uvec4 pages;       // x: pages released, y: pages taken from the free list, z: marked groups left without a page,
                     // w: resident groups after allocation
  uvec4 marking;     // x: marked groups, y: marked shadels, z: bias levels applied, w: phase (PRISMOID_HTEX_PHASE_*)
  uvec4 result;      // x: 1 when the marked groups exceeded the pool even at the largest bias, y: gather pixels with a
                     // footprint texel not resident (holes), z: groups marked before any bias, w: marked shadels
                     // reused (shaded in an earlier frame, PRISMOID_HTEX_FLAG_REUSE)
  uvec4 persistent;  // x: pages on the free list
  // The allocation loop's next CLEAR and COUNT (over groups) and REMARK (over pixels) steps:
  // VkDispatchIndirectCommand in xyz, written by DECIDE; zero once the loop is done, so the
  // loop's remaining iterations launch nothing.
  uvec4 loop_groups;
  uvec4 loop_pixels;
};

struct HtexPush {
  uvec4 image;  // x: width, y: height, z: flags (PRISMOID_HTEX_FLAG_*), w: iteration or raygen variant
  vec4 lod;     // x: level-of-detail bias added before rounding
};

PRISMOID_SHARED_END

#ifdef __cplusplus
static_assert(sizeof(prismoid::gpu::HtexAtlasGpu) == 32);
static_assert(sizeof(prismoid::gpu::HtexMeshGpu) == 160);
static_assert(sizeof(prismoid::gpu::HtexStateGpu) == 112);
static_assert(sizeof(prismoid::gpu::HtexPush) == 32);
#endif

#endif
