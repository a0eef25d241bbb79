#pragma once
// Checks the texture-space backends' tests share (texel shading, the meshlet shading atlas):
// shaded samples against the CPU direct light at their points, a pixel against the bilinear
// blend of its taps, and the flat-shaded cube whose image must equal the forward backend's.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <utility>
#include <vector>

#include <glm/geometric.hpp>
#include <glm/vec4.hpp>

#include "renderer/reference/direct_light.hpp"
#include "renderer/reference/tet_ray.hpp"
#include "renderer/surface/forward/forward_pass.hpp"
#include "scene/surface_scene.hpp"
#include "surface/forward_comparison.hpp"
#include "surface/surface_test_scenes.hpp"

namespace prismoid::test {

// A pass's device buffer read back as T (any pass with read_buffer).
template <typename T, typename Pass>
std::vector<T> read_as(const Pass& pass, const vk::Buffer& buffer) {
  const std::vector<std::byte> bytes = pass.read_buffer(buffer);
  std::vector<T> out(bytes.size() / sizeof(T));
  std::memcpy(out.data(), bytes.data(), out.size() * sizeof(T));
  return out;
}

// Global triangle ids (GpuSurfaceScene's order) to (mesh, triangle within it).
class TriangleIndex {
 public:
  explicit TriangleIndex(const SurfaceScene& scene) {
    uint32_t total = 0;
    for (const SceneMesh& m : scene.meshes) {
      first_.push_back(total);
      total += uint32_t(m.triangles.size());
    }
  }
  std::pair<uint32_t, uint32_t> local(uint32_t global) const {
    uint32_t mesh = 0;
    while (mesh + 1 < first_.size() && first_[mesh + 1] <= global) ++mesh;
    return {mesh, global - first_[mesh]};
  }

 private:
  std::vector<uint32_t> first_;
};

// Barycentric weights of the point where the ray through image point (x, y) of a width x height
// image meets global triangle `triangle`'s plane (double; Moeller-Trumbore without the inside test).
inline glm::dvec3 ray_plane_weights(const SurfaceScene& scene, const TriangleIndex& index, uint32_t triangle, const Camera& camera,
                                    uint32_t width, uint32_t height, double x, double y) {
  const auto [mesh, local] = index.local(triangle);
  const SceneMesh& m = scene.meshes[mesh];
  const auto& t = m.triangles[local];
  const glm::dvec3 p0 = m.positions[t[0]], e1 = m.positions[t[1]] - p0, e2 = m.positions[t[2]] - p0;
  const glm::dvec3 d = reference::ray_direction(camera, width, height, x, y);
  const glm::dvec3 pv = glm::cross(d, e2);
  const double det = glm::dot(e1, pv);
  const glm::dvec3 tv = camera.eye - p0;
  const double b1 = glm::dot(tv, pv) / det, b2 = glm::dot(d, glm::cross(tv, e1)) / det;
  return {1.0 - b1 - b2, b1, b2};
}

struct SampleCheck {
  size_t failures = 0;
  double worst = 0.0;  // largest error over its tolerance
  double peak = 0.0;   // largest reference value
};

// Every GPU sample (alpha 1: shaded) against reference::direct_light_at its query's point. The
// tolerance: how much the reference moves when the point moves by `probe` of its triangle (2e-6
// by default: above a float position's rounding; a backend whose GPU point comes through a longer
// float computation than the CPU's says how far), plus the float shading's rounding (kUlpBudget).
inline SampleCheck check_shaded_samples(const SurfaceScene& scene, const std::vector<reference::ShadingPointQuery>& queries,
                                        const std::vector<glm::vec4>& gpu, double probe = 2e-6) {
  constexpr double kU = 0x1p-24;
  std::vector<reference::ShadingPointQuery> probes;
  for (const auto& q : queries)
    for (int k = 0; k < 3; ++k) {
      reference::ShadingPointQuery p = q;
      p.bary[k] += probe;
      p.bary[(k + 1) % 3] -= probe;
      probes.push_back(p);
    }
  const auto ref = reference::direct_light_at(scene, queries);
  const auto probed = reference::direct_light_at(scene, probes);
  SampleCheck c;
  for (size_t k = 0; k < queries.size(); ++k) {
    const glm::vec4 g = gpu[k];
    double variation = 0.0;
    for (int p = 0; p < 3; ++p)
      for (int ch = 0; ch < 3; ++ch) variation = std::max(variation, std::abs(probed[3 * k + p].radiance[ch] - ref[k].radiance[ch]));
    const double tol = variation + kU * (kUlpBudget + ref[k].terms) * ref[k].rounding_scale;
    bool ok = g.w == 1.0f;
    for (int ch = 0; ch < 3; ++ch) {
      const double e = std::abs(double(g[ch]) - ref[k].radiance[ch]);
      if (tol > 0.0) c.worst = std::max(c.worst, e / tol);
      ok = ok && e <= tol;
      c.peak = std::max(c.peak, ref[k].radiance[ch]);
    }
    if (!ok && c.failures++ < 5)
      ADD_FAILURE() << "sample " << k << " (mesh " << queries[k].mesh << " triangle " << queries[k].triangle << ", bary " << queries[k].bary.x
                    << " " << queries[k].bary.y << " " << queries[k].bary.z << "): GPU " << g.x << " " << g.y << " " << g.z << " " << g.w
                    << ", reference " << ref[k].radiance.x << " " << ref[k].radiance.y << " " << ref[k].radiance.z << ", tolerance " << tol;
  }
  return c;
}

// A GPU pixel against the blend of its taps (rgb, weight) renormalized over the taps given. The
// GPU's tap position is within 1e-4 texel of the double one, so each weight moves by at most
// 2e-4; the blend by 4 * 2e-4 max|texel|, times 4 for renormalizing over at least a quarter of
// the weight, plus the float sum's 16 u. Returns the error over that tolerance (> 1: a failure).
inline double bilinear_pixel_error(const float* gpu_rgba, const std::vector<std::pair<glm::vec4, double>>& taps) {
  glm::dvec3 sum(0.0);
  double weight = 0.0, maxv = 0.0;
  for (const auto& [texel, w] : taps) {
    sum += w * glm::dvec3(texel);
    weight += w;
    maxv = std::max(maxv, double(std::max({texel.x, texel.y, texel.z})));
  }
  if (!(weight > 0.0) || gpu_rgba[3] != 1.0f) return 1e30;
  const glm::dvec3 expect = sum / weight;
  const double tol = maxv * (4.0 * 4.0 * 2e-4 + 16.0 * 0x1p-24) + 1e-30;
  double worst = 0.0;
  for (int ch = 0; ch < 3; ++ch) worst = std::max(worst, std::abs(double(gpu_rgba[ch]) - expect[ch]) / tol);
  return worst;
}

// A cube of flat faces under a directional light, diffuse, and a camera seeing three faces: the
// shading is constant on each face, so whatever its taps a correct texture-space backend
// reproduces the forward image within rounding; a tap from another face's chart, an unshaded
// texel or a wrong triangle would not.
inline SurfaceScene flat_cube_scene() {
  SurfaceScene scene = sphere_scene({});
  scene.meshes.clear();
  SceneMesh cube;
  const glm::dvec3 c[8] = {{-1, -1, -1}, {1, -1, -1}, {1, 1, -1}, {-1, 1, -1}, {-1, -1, 1}, {1, -1, 1}, {1, 1, 1}, {-1, 1, 1}};
  for (const auto& p : c) cube.positions.push_back(p * 0.8);
  cube.triangles = {{0, 2, 1}, {0, 3, 2}, {4, 5, 6}, {4, 6, 7}, {0, 1, 5}, {0, 5, 4}, {3, 7, 6}, {3, 6, 2}, {0, 4, 7}, {0, 7, 3}, {1, 2, 6}, {1, 6, 5}};
  scene.meshes.push_back(cube);
  scene.point_lights.clear();
  scene.directional_lights = {{glm::dvec3(-0.3, -0.5, -0.8), glm::dvec3(2.0)}};
  scene.camera.eye = {2.2, 1.7, 3.1};
  return scene;
}

// The backend's image of flat_cube_scene() against the forward pass's: every pixel both cover
// equal within 1e-5 relative; returns the pixels compared.
inline size_t expect_equals_forward(const vk::Device& device, const surface::GpuSurfaceScene& gpu, const Camera& camera, uint32_t w, uint32_t h,
                                    const std::vector<float>& rgba, const std::vector<glm::uvec4>& visibility) {
  surface::ForwardPass forward(device);
  const std::vector<float> fwd = surface::render_forward(device, forward, gpu, camera, {w, h}).rgba;
  size_t compared = 0, failures = 0;
  for (size_t i = 0; i < visibility.size(); ++i) {
    if (visibility[i].x == 0 || fwd[4 * i + 3] != 1.0f) continue;
    ++compared;
    for (int ch = 0; ch < 3; ++ch) {
      const double f = fwd[4 * i + size_t(ch)], t = rgba[4 * i + size_t(ch)];
      if (std::abs(f - t) > 1e-5 * std::max(1.0, std::abs(f)) && failures++ < 5)
        ADD_FAILURE() << "pixel " << i << " channel " << ch << ": " << t << ", forward " << f;
    }
  }
  EXPECT_EQ(failures, 0u);
  return compared;
}

}  // namespace prismoid::test
