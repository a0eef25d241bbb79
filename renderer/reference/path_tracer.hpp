#pragma once
// The CPU double-precision path tracer of a SurfaceScene: the reference every GPU surface
// backend (forward, Htex, meshlet atlas, texel shading, ReSTIR GI) is tested against.
//
// Estimator: unidirectional path tracing from the camera. At every surface point it samples
// one light (point, directional or an emissive triangle, chosen in proportion to power) for
// next-event estimation and the BSDF (renderer/reference/surface_bsdf.hpp) for the next
// direction; emissive triangles found by either are weighted by the power heuristic (Veach
// 1995, beta = 2). Point and directional lights are reached only by light sampling; the sky
// only by BSDF sampling. Russian roulette after `roulette_after` reflections (unbiased).
//
// Bias: only the depth cap. Paths with more than `max_bounces` reflections are cut, so the
// image is the sum of the light paths with at most max_bounces reflections; e.g. in the
// furnace (albedo A, emission Le) the expectation is Le (1 - A^(D+1)) / (1 - A) with
// D = max_bounces, below the true Le / (1 - A) by Le A^(D+1) / (1 - A).
//
// Per-pixel error bars: `variance` is the sample variance of one sample, so a pixel's mean has
// standard error sqrt(variance / N). It is trustworthy when a pixel's rare outcomes occur many
// times among its N samples. Russian roulette (survival q = the throughput's largest channel)
// makes such outcomes: survivors carry weight 1/q, and a pixel that drew none has a low mean
// AND a low variance. Comparisons pixel by pixel at small N should set roulette_after >=
// max_bounces (no roulette: exactly the same expectation, more time) or use N q >> 1.
//
// Determinism: every (pixel, sample) draws from its own counter-based random stream keyed by
// (seed, pixel, sample), so the image does not depend on the thread count.
//
// Guards: samples whose BSDF pdf comes out zero end their path and are counted; a sample whose
// radiance is NaN or infinite is counted and contributes zero; shading normals facing away
// from the viewer are replaced by the geometric normal and counted; zero-area triangles are
// skipped and counted. Tests assert these counts.
//
// The scene is rendered as given: callers that want the "never black" rule apply
// with_default_lighting (scene/surface_scene.hpp) with their camera first.
#include <cstdint>
#include <span>
#include <vector>

#include <glm/vec3.hpp>

#include "scene/camera.hpp"
#include "scene/surface_scene.hpp"

namespace prismoid::reference {

// Which estimators of the light reaching a surface point contribute. Mis is the renderer;
// the others are for tests (all three converge to the same image for emissive triangles):
// BsdfOnly never samples lights (point and directional lights then give nothing);
// LightOnly counts emissive triangles only through light sampling (and directly seen).
enum class LightSampling { Mis, BsdfOnly, LightOnly };

struct PathTracerSettings {
  uint32_t width = 64;
  uint32_t height = 64;
  uint32_t samples_per_pixel = 16;
  uint32_t max_bounces = 64;     // reflections per path; 0: emission and sky seen directly
  uint32_t min_bounces = 0;      // light reaching the eye after fewer reflections is left out (e.g. 2 with
                                 // max_bounces 2: the one-bounce indirect light alone)
  uint32_t roulette_after = 3;   // paths with up to this many reflections are never cut by Russian roulette
  LightSampling light_sampling = LightSampling::Mis;
  bool jitter = true;            // false: every sample through the pixel centre
  uint64_t seed = 1;
  unsigned threads = 0;          // 0: std::thread::hardware_concurrency()
};

struct PathTracerCounts {
  uint64_t paths = 0;
  uint64_t rays = 0;                  // camera, continuation and shadow rays
  uint64_t zero_pdf = 0;              // BSDF samples with pdf 0 (path ended)
  uint64_t non_finite = 0;            // samples whose radiance was NaN or infinite (counted as 0)
  uint64_t backfacing_normals = 0;    // shading normals facing away from the viewer
  uint64_t degenerate_triangles = 0;  // zero-area triangles skipped
};

struct PathTracedImage {
  uint32_t width = 0, height = 0, samples_per_pixel = 0;
  std::vector<glm::dvec3> mean;      // linear RGB radiance per pixel, row-major, row 0 at the top
  std::vector<glm::dvec3> variance;  // per pixel: unbiased sample variance of one sample's radiance
  PathTracerCounts counts;
  double seconds = 0.0;              // wall-clock time of the render (for reports, not tests)
  glm::dvec3 standard_error(size_t pixel) const;  // sqrt(variance / samples_per_pixel)
  std::vector<float> rgb() const;                 // 3 floats per pixel, the layout of image_error and PFM
};

// Throws InputError for an invalid scene (validate) or camera, or a zero image size / sample count.
PathTracedImage path_trace(const SurfaceScene& scene, const Camera& camera, const PathTracerSettings& settings);

// Radiance leaving given surface points towards given directions (for object-space shading:
// a shading sample's radiance towards its viewer), estimated by the same integrator as
// path_trace, each point with settings.samples_per_pixel paths of its own random stream
// (seed, point index, path). The first "hit" is the point itself: its emission counts (front
// side, as seen from `wo`), reflection there is shaded for the viewer at `wo` (the shading
// normal turned to wo's side, as for a camera ray arriving along -wo). width, height and jitter
// are ignored. With max_bounces = 2 the result is emission + direct light + light reflected
// once more (one bounce): what direct shading plus one-bounce GI (renderer/surface/gi/restir_gi)
// converges to; min_bounces = max_bounces = 2 gives the one-bounce part alone.
struct SurfacePointQuery {
  uint32_t mesh = 0, triangle = 0;  // the scene's mesh and the triangle within it
  double b1 = 0.0, b2 = 0.0;        // barycentric weights of the triangle's corners 1 and 2
  glm::dvec3 wo{0.0, 0.0, 1.0};     // unit direction towards the viewer
};
struct PointRadiance {
  glm::dvec3 mean{0.0};
  glm::dvec3 variance{0.0};  // unbiased sample variance of one path's radiance
  uint32_t samples = 0;
  glm::dvec3 standard_error() const;  // sqrt(variance / samples)
};
// Throws InputError for an invalid scene, a zero sample count, a point naming no triangle or a
// zero-area one, or a direction that is not finite and non-zero.
std::vector<PointRadiance> radiance_leaving(const SurfaceScene& scene, std::span<const SurfacePointQuery> points,
                                            const PathTracerSettings& settings, PathTracerCounts* counts = nullptr);

// The first surface along each ray (for tests and tools: what a pixel sees). Builds the
// hierarchy once for all rays.
struct SurfaceRay {
  glm::dvec3 origin{0.0};
  glm::dvec3 direction{0.0, 0.0, -1.0};
  double t_min = 0.0;
};
struct SurfaceHit {
  bool hit = false;
  double t = 0.0;
  glm::dvec3 position{0.0};
  glm::dvec3 normal{0.0};  // unit winding normal of the triangle
  uint32_t mesh = 0, triangle = 0;
  double b1 = 0.0, b2 = 0.0;  // barycentric weights of the triangle's corners 1 and 2
};
std::vector<SurfaceHit> first_hits(const SurfaceScene& scene, std::span<const SurfaceRay> rays);

}  // namespace prismoid::reference
