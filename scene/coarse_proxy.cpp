#include "scene/coarse_proxy.hpp"

#include <algorithm>
#include <cmath>
#include <optional>

#include <glm/common.hpp>

#include "scene/generators.hpp"
#include "scene/tet_mesh.hpp"

namespace prismoid {

namespace {

// Cells binned by their bounding boxes on a uniform grid: which cell holds a point.
class CellLocator {
 public:
  explicit CellLocator(const TetMesh& mesh) : mesh_(mesh) {
    const Bounds b = bounds_of(mesh);
    lo_ = b.min;
    const glm::dvec3 size = glm::max(b.max - b.min, glm::dvec3(1e-300));
    bins_ = std::clamp(uint32_t(std::cbrt(double(mesh.tets.size()) / 4.0)), 1u, 64u);
    step_ = size / double(bins_);
    cells_.resize(size_t(bins_) * bins_ * bins_);
    for (uint32_t c = 0; c < mesh.tets.size(); ++c) {
      glm::dvec3 cmin(1e300), cmax(-1e300);
      for (uint32_t i : mesh.tets[c]) {
        cmin = glm::min(cmin, mesh.points[i]);
        cmax = glm::max(cmax, mesh.points[i]);
      }
      const glm::uvec3 a = bin_of(cmin), z = bin_of(cmax);
      for (uint32_t x = a.x; x <= z.x; ++x)
        for (uint32_t y = a.y; y <= z.y; ++y)
          for (uint32_t w = a.z; w <= z.z; ++w) cells_[index(x, y, w)].push_back(c);
    }
  }

  // The cell holding p, with p's barycentric weights in it; none when p is outside every cell.
  std::optional<std::pair<uint32_t, std::array<double, 4>>> find(const glm::dvec3& p) const {
    const glm::uvec3 k = bin_of(p);
    for (uint32_t c : cells_[index(k.x, k.y, k.z)]) {
      const auto& t = mesh_.tets[c];
      const glm::dvec3 v[4] = {mesh_.points[t[0]], mesh_.points[t[1]], mesh_.points[t[2]], mesh_.points[t[3]]};
      const double whole = signed_volume(v[0], v[1], v[2], v[3]);
      if (whole == 0.0) continue;
      std::array<double, 4> w;
      bool inside = true;
      for (int i = 0; i < 4 && inside; ++i) {
        glm::dvec3 u[4] = {v[0], v[1], v[2], v[3]};
        u[i] = p;
        w[i] = signed_volume(u[0], u[1], u[2], u[3]) / whole;
        inside = w[i] >= -1e-9;  // on a face or an edge: either neighbour gives the same value
      }
      if (inside) return std::make_pair(c, w);
    }
    return std::nullopt;
  }

 private:
  glm::uvec3 bin_of(const glm::dvec3& p) const {
    const glm::dvec3 f = glm::clamp((p - lo_) / step_, glm::dvec3(0.0), glm::dvec3(double(bins_ - 1)));
    return glm::uvec3(f);
  }
  size_t index(uint32_t x, uint32_t y, uint32_t z) const { return (size_t(z) * bins_ + y) * bins_ + x; }

  const TetMesh& mesh_;
  glm::dvec3 lo_{0.0}, step_{1.0};
  uint32_t bins_ = 1;
  std::vector<std::vector<uint32_t>> cells_;
};

}  // namespace

TetMesh coarse_proxy(const TetMesh& mesh, uint32_t n) {
  const Bounds b = bounds_of(mesh);
  TetMesh proxy = make_box_mesh(b.min, b.max, std::max(1u, n), [](const glm::dvec3&) { return 0.0; });
  proxy.name = mesh.name + " (coarse proxy, " + std::to_string(proxy.tets.size()) + " cells at most)";
  const CellLocator locate(mesh);
  const bool scalars = !mesh.point_scalars.empty() || !mesh.cell_scalars.empty();
  double lowest = 0.0;
  if (!mesh.point_scalars.empty()) lowest = *std::min_element(mesh.point_scalars.begin(), mesh.point_scalars.end());
  else if (!mesh.cell_scalars.empty()) lowest = *std::min_element(mesh.cell_scalars.begin(), mesh.cell_scalars.end());
  std::vector<bool> inside(proxy.points.size(), false);
  proxy.point_extinction.assign(proxy.points.size(), 0.0);
  proxy.point_scalars.assign(scalars ? proxy.points.size() : 0, lowest);
  for (size_t i = 0; i < proxy.points.size(); ++i) {
    const auto hit = locate.find(proxy.points[i]);
    if (!hit) continue;
    inside[i] = true;
    const auto& [c, w] = *hit;
    const auto& t = mesh.tets[c];
    auto linear = [&](const std::vector<double>& at_points) {
      double v = 0.0;
      for (int k = 0; k < 4; ++k) v += w[k] * at_points[t[k]];
      return v;
    };
    proxy.point_extinction[i] = std::max(0.0, mesh.point_extinction.empty() ? mesh.cell_extinction[c] : linear(mesh.point_extinction));
    if (!mesh.point_scalars.empty()) proxy.point_scalars[i] = linear(mesh.point_scalars);
    else if (!mesh.cell_scalars.empty()) proxy.point_scalars[i] = mesh.cell_scalars[c];
  }
  // Keep the cells that reach into the data; each cell's extinction is its points' mean.
  std::vector<std::array<uint32_t, 4>> kept;
  std::vector<double> kept_sigma;
  for (const auto& t : proxy.tets) {
    if (!(inside[t[0]] || inside[t[1]] || inside[t[2]] || inside[t[3]])) continue;
    kept.push_back(t);
    double sum = 0.0;
    for (uint32_t i : t) sum += proxy.point_extinction[i];
    kept_sigma.push_back(0.25 * sum);
  }
  proxy.tets = std::move(kept);
  proxy.cell_extinction = std::move(kept_sigma);
  proxy.cell_scalars.clear();
  return proxy;
}

}  // namespace prismoid
