// Layouts shared by the meshlet shading atlas's shaders (shaders/surface/msa/) and
// renderer/surface/msa/msa_pass.hpp. Meshlets and their charts: renderer/surface/msa/meshlets.hpp.
//
// Atlas: a grid of superblocks of PRISMOID_MSA_SUPERBLOCK^2 texels (atlas texel (x, y) at
// y * width + x of the result buffer). A superblock belongs to one block size class at a time:
// class c = log2(w / 8) * 6 + log2(h / 8) for blocks of w x h texels (w, h in 8 .. 256). Its
// blocks fill it in columns of width w and rows of height h: slot k of the superblock sits at
// ((k % (S / w)) w, (k / (S / w)) h). A class's slot id is its superblock's index in the class's
// list times the slots per superblock plus the slot within it.
//
// A meshlet's block maps its chart (world units, [0, extent]) to texels as
// texel = block origin + 1 + chart * s with s = min((w - 2) / extent.x, (h - 2) / extent.y): one
// texel of border on every side for bilinear taps. s depends on the class only, so a meshlet that
// keeps its block keeps its texels' meaning (shading can be reused).
#ifndef PRISMOID_SHARED_MSA_H
#define PRISMOID_SHARED_MSA_H
#include "common.h"

PRISMOID_SHARED_BEGIN

#define PRISMOID_MSA_SUPERBLOCK 256u
#define PRISMOID_MSA_MIN_BLOCK 8u
#define PRISMOID_MSA_SIZES 6u      // 8, 16, ..., 256 per side
#define PRISMOID_MSA_CLASSES 36u
#define PRISMOID_MSA_NONE 0xffffffffu
// The shading launch stacks this many 8 x 8 tiles along y in each of its z slices, so that z
// stays below 65,536: a refined Cornell box at 1920x1080 queues 67,040 tiles, and while the tiles
// were z the H200 shaded only what a launch of 67,040 - 65,536 tiles holds (its driver seems to
// keep a ray launch's depth in 16 bits, though the specification allows more).
#define PRISMOID_MSA_TILES_PER_LAUNCH 8u

// Descriptor bindings of set 0, from PRISMOID_SURFACE_BINDING_BACKEND on.
#define PRISMOID_MSA_BINDING_TRIANGLES 16         // MsaTriangleGpu[] per global triangle (read only)
#define PRISMOID_MSA_BINDING_MESHLETS 17          // MsaMeshletGpu[] per meshlet (read only)
#define PRISMOID_MSA_BINDING_MESHLET_TRIANGLES 18 // uint[]: each meshlet's triangles, MsaMeshletGpu::info.x on (read only)
#define PRISMOID_MSA_BINDING_BLOCKS 19            // MsaBlockGpu[] per meshlet (persists)
#define PRISMOID_MSA_BINDING_DENSITY 20           // uint[] per meshlet: this frame's texels per unit wanted (float bits, max over its pixels; 0: not seen)
#define PRISMOID_MSA_BINDING_CLASSES 21           // MsaClassGpu[PRISMOID_MSA_CLASSES] (persists)
#define PRISMOID_MSA_BINDING_CLASS_SUPERBLOCKS 22 // uint[classes * superblocks]: each class's superblocks in order (persists)
#define PRISMOID_MSA_BINDING_FREE_SLOTS 23        // uint[classes * meshlets]: each class's released slots, a stack (persists)
#define PRISMOID_MSA_BINDING_POOL 24              // uint[superblocks]: free superblocks, a stack of MsaStateGpu::pool.x (persists)
#define PRISMOID_MSA_BINDING_STATE 25             // MsaStateGpu
#define PRISMOID_MSA_BINDING_TASKS 26             // uint[]: meshlet << 12 | tile within its block, to shade this frame
#define PRISMOID_MSA_BINDING_RESULT 27            // vec4[] per atlas texel: radiance, a = 1 where a triangle was shaded
#define PRISMOID_MSA_BINDING_VISIBILITY 28        // uvec4[] per pixel: triangle + 1 (0: sky), 0, b1, b2 bits

#define PRISMOID_MSA_FLAG_SHADOWS 1u
#define PRISMOID_MSA_FLAG_SHADE_ALL 2u  // a shading frame: every visible block is shaded (else only new blocks)
#define PRISMOID_MSA_FLAG_FRAME_CHARTS 4u  // charts are made every frame (frame_charts.comp): shading takes the nearest triangle
#define PRISMOID_MSA_FLAG_PERSPECTIVE 8u   // with FRAME_CHARTS: perspective charts (MSA-P), else orthographic (MSA-O)

// allocate.comp's steps.
#define PRISMOID_MSA_STEP_DEMAND 0u    // per meshlet: texels wanted at full density -> state.demand.x
#define PRISMOID_MSA_STEP_BUDGET 1u    // one thread: the budget's density factor
#define PRISMOID_MSA_STEP_RELEASE 2u   // per meshlet: blocks of meshlets not seen or changing class go back
#define PRISMOID_MSA_STEP_CLAIM 3u     // per class: released slots joined; superblocks claimed for the rest
#define PRISMOID_MSA_STEP_POOL 4u      // one thread: the pool's stack shrinks by what was claimed
#define PRISMOID_MSA_STEP_ALLOCATE 5u  // per meshlet: a slot for each seen meshlet without a block
#define PRISMOID_MSA_STEP_SETTLE 6u    // per class: stacks and bump pointers after allocation
#define PRISMOID_MSA_STEP_TASKS 7u     // per meshlet: tiles of blocks to shade

struct MsaTriangleGpu {
  vec4 c01;    // chart corner 0 xy, corner 1 xy (world units; pixels for perspective per-frame charts)
  vec4 c2;     // chart corner 2 xy, zw: 0
  uvec4 info;  // x: meshlet, yzw: 0
};

struct MsaMeshletGpu {
  vec4 extent;  // xy: chart rectangle, zw: 0
  uvec4 info;   // x: first entry in the meshlet-triangle list, y: triangle count, z: 1 when its chart is perspective this frame, w: 0
};

struct MsaBlockGpu {
  uvec4 block;  // x, y: origin (atlas texels), z: class or NONE, w: slot within the class
  uvec4 stamp;  // x: frame the block was (re)allocated, y: frame it was last shaded, zw: 0
};

struct MsaClassGpu {
  uvec4 counts;  // x: free slots on the stack, y: slots handed out from the class's superblocks (bump), z: superblocks owned,
                 // w: released this frame (pushed above the stack)
  uvec4 frame;   // x: seen meshlets wanting a block of this class this frame, y: allocation counter, zw: 0
};

struct MsaStateGpu {
  uvec4 trace;   // xyz: VkTraceRaysIndirectCommandKHR of the shading pass (8, 8 * TILES_PER_LAUNCH, launches); w: texels shaded
  uvec4 pool;    // x: free superblocks (stack size), y: claimed this frame, z: 1 when the pool ran out this frame, w: meshlets left without a block
  uvec4 blocks;  // x: seen meshlets, y: blocks allocated this frame, z: blocks released this frame, w: blocks shaded this frame
  uvec4 demand;  // x: texels wanted at full density, y: texels of the blocks held after allocation, z: gather pixels with no shaded tap,
                 // w: 8 x 8 tiles queued for shading (PRISMOID_MSA_BINDING_TASKS)
  vec4 budget;   // x: density factor applied (1: none), yzw: 0
  uvec4 stretch; // display: x, w: low and high word of the sum over pixels of (Gamma^2 + gamma^2) / 2 in 1/4096 (shaders/surface/stretch.glsl), y: pixels, z: largest Gamma (float bits)
};

struct MsaPush {
  uvec4 image;   // x: width, y: height, z: flags (PRISMOID_MSA_FLAG_*), w: this frame's stamp (>= 1)
  uvec4 atlas;   // x: atlas width (texels), y: superblock columns, z: meshlets, w: step
  uvec4 limits;  // x: superblocks, y: texel budget per frame (0: none), z: the near plane's distance (float bits), w: 0
};

PRISMOID_SHARED_END

#ifdef __cplusplus
static_assert(sizeof(prismoid::gpu::MsaTriangleGpu) == 48);
static_assert(sizeof(prismoid::gpu::MsaMeshletGpu) == 32);
static_assert(sizeof(prismoid::gpu::MsaBlockGpu) == 32);
static_assert(sizeof(prismoid::gpu::MsaClassGpu) == 32);
static_assert(sizeof(prismoid::gpu::MsaStateGpu) == 96);
static_assert(sizeof(prismoid::gpu::MsaPush) == 48);
#endif
#endif
