// Layouts of ReSTIR GI in object space (Ouyang et al. 2021, "ReSTIR GI: Path Resampling for
// Real-Time Path Tracing", CGF 40(8); in object space as Li & Guo do it in "Real-time Seamless
// Object Space Shading", section 4), shared by shaders/surface/gi/ and
// renderer/surface/gi/restir_gi.cpp. All positions are float and relative to the scene origin
// (GpuSurfaceScene::origin, SceneAccel::origin).
//
// Vocabulary: a host (a shading backend: Htex shadels, the dense test set, ...) hands GI a set of
// *shading samples* (points x1 on surfaces, GiSample). Each sample owns a *slot* in a reservoir
// buffer that persists from frame to frame (for Htex: its physical texel), so temporal reuse
// reads last frame's reservoir at the same slot without reprojection. A second persistent
// buffer, the *fallback layer* (Htex: the finest mip level, always resident), holds a copy of
// every final reservoir and stands in when a slot's history is invalid.
#ifndef PRISMOID_SHARED_GI_H
#define PRISMOID_SHARED_GI_H
#include "common.h"

PRISMOID_SHARED_BEGIN

// Bindings of set 0 used by the GI passes (after the scene's, see surface.h). A host's own
// hook data starts at PRISMOID_GI_BINDING_HOST.
#define PRISMOID_GI_BINDING_SAMPLES 16     // readonly GiSample[]: the shading samples of this frame
#define PRISMOID_GI_BINDING_SLOTS 17       // GiReservoir[]: per slot, persists across frames
#define PRISMOID_GI_BINDING_TEMPORAL 18    // GiReservoir[]: per sample, pass 1's output, pass 2's input
#define PRISMOID_GI_BINDING_FALLBACK 19    // GiReservoir[]: the persistent fallback layer
#define PRISMOID_GI_BINDING_OUTPUT 20      // vec4[] per sample: rgb indirect radiance towards the viewer
#define PRISMOID_GI_BINDING_DIRECT 21      // vec4[] per sample: rgb direct shading (with PRISMOID_GI_WRITE_DIRECT)
#define PRISMOID_GI_BINDING_HOST 24        // first binding of a host's hook data

// Ray-generation shaders of a GI pipeline, by their index in the table's raygen region.
#define PRISMOID_GI_RAYGEN_INITIAL 0  // initial sample + temporal resampling
#define PRISMOID_GI_RAYGEN_SPATIAL 1  // spatial resampling, write-back, output

// GiSettings::params.z flags.
#define PRISMOID_GI_UNBIASED 1u         // visibility-checked reuse with the count normalization
#define PRISMOID_GI_FALLBACK 2u         // merge the fallback layer's reservoir when history is invalid
#define PRISMOID_GI_TEMPORAL 4u         // merge the history reservoir at the slot
#define PRISMOID_GI_NO_INITIAL 8u       // no new candidate this frame (tests of reuse alone)
#define PRISMOID_GI_WRITE_DIRECT 16u    // pass 2 also writes x1's direct shading (shade_surface_point, the
                                        // sky's ambient term left out) to the direct buffer

// GiReservoir::info.z flags.
#define PRISMOID_GI_SAMPLE_SKY 1u   // the bounce ray missed: sample_point.xyz is a unit direction
#define PRISMOID_GI_SAMPLE_VALID 2u // the reservoir holds a sample (W may still be 0)

// One shading sample x1.
struct GiSample {
  vec4 position;  // xyz: scene-local point; w: barycentric weight b1 of the triangle's corner 1
  vec4 viewer;    // xyz: unit direction towards the viewer (what the sample's radiance is for); w: b2
  uvec4 id;       // x: global triangle index; y, z, w: 0
};

// A reservoir: one reconnection sample (the point x2 a bounce ray from x1 found, its normal and
// the radiance it sends back to x1), its unbiased contribution weight W and its candidate count M.
struct GiReservoir {
  vec4 sample_point;   // xyz: x2 (or, for a sky sample, the unit direction); w: W
  vec4 sample_normal;  // xyz: unit geometric normal at x2 on x1's side (0 for sky); w: M
  vec4 radiance;       // rgb: Lo(x2 -> x1) (direct light at x2 without its emission, or the sky); w: w_sum
  vec4 origin;         // xyz: x1 the sample was last resampled for; w: target p^ there (luminance)
  vec4 origin_bary;    // xy: b1, b2 of x1 in its triangle; zw: the unit direction x1 -> sample, octahedral
                       // (exact where x2 nearly touches x1, e.g. rays from a concave edge or vertex)
  uvec4 info;          // x: x1's global triangle, y: age (frames since traced), z: PRISMOID_GI_SAMPLE_* flags, w: 0
};

// The per-frame settings (push constants of both passes).
struct GiSettings {
  uvec4 params;  // x: frame index (random streams), y: sample count, z: PRISMOID_GI_* flags, w: spatial neighbours k
  vec4 limits;   // x: M cap of the history, y: spatial radius (host units; dense set: texels), z: cos of the
                 // largest normal angle between neighbours, w: tau, shifts with a Jacobian outside [1/tau, tau] are not made
};

PRISMOID_SHARED_END

#ifdef __cplusplus
static_assert(sizeof(prismoid::gpu::GiSample) == 48);
static_assert(sizeof(prismoid::gpu::GiReservoir) == 96);
static_assert(sizeof(prismoid::gpu::GiSettings) == 32);
#endif

#endif
