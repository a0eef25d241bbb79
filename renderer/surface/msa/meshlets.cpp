#include "renderer/surface/msa/meshlets.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>
#include <map>
#include <string>
#include <utility>

#include <glm/trigonometric.hpp>
#include <glm/geometric.hpp>
#include <meshoptimizer.h>

#include "renderer/surface/charts/planar_charts.hpp"
#include "scene/input_error.hpp"
#include "shaders/shared/msa.h"

namespace prismoid::msa {

namespace {

constexpr uint32_t kMaxSettingTriangles = 126;

std::string fmt(double v) {
  char buffer[64];
  std::snprintf(buffer, sizeof buffer, "%.6g", v);
  return buffer;
}

void check(const SurfaceScene& scene, const MeshletSettings& s) {
  if (s.max_triangles == 0 || s.max_triangles > kMaxSettingTriangles)
    throw InputError(scene.name, "meshlets: the triangles per meshlet must be 1.." + std::to_string(kMaxSettingTriangles) + ", not " +
                                     std::to_string(s.max_triangles));
  if (!(s.max_normal_angle_deg > 0.0 && s.max_normal_angle_deg < 90.0))
    throw InputError(scene.name, "meshlets: the normal cone's angle must lie in (0, 90) degrees, not " + fmt(s.max_normal_angle_deg));
  if (!(s.cone_weight >= 0.0 && s.cone_weight <= 1.0))
    throw InputError(scene.name, "meshlets: meshoptimizer's cone weight must lie in [0, 1], not " + fmt(s.cone_weight));
}

void add(MeshletSet& set, const charts::PlanarChart& chart) {
  const uint32_t id = static_cast<uint32_t>(set.meshlets.size());
  Meshlet m;
  m.mesh = chart.mesh;
  m.triangles = chart.triangles;
  m.extent = chart.extent;
  m.normal = chart.normal;
  for (size_t k = 0; k < chart.triangles.size(); ++k) {
    set.meshlet_of_triangle[chart.triangles[k]] = id;
    set.corner_chart[chart.triangles[k]] = chart.corners[k];
  }
  set.meshlets.push_back(std::move(m));
}

// Charts `group` (in meshoptimizer's order); while that fails, its halves (by that order).
void chart_or_split(const std::vector<charts::TriangleGeometry>& tris, const std::vector<uint32_t>& group, MeshletSet& set) {
  if (group.empty()) return;
  if (auto chart = charts::chart_triangles(tris, group)) {
    add(set, *chart);
    return;
  }
  if (group.size() == 1) {
    // A single triangle always charts onto its own plane unless its coordinates overflow there:
    // then it gets a degenerate triangle's meshlet rather than a broken chart.
    charts::PlanarChart point;
    point.mesh = tris[group[0]].mesh;
    point.triangles = group;
    point.corners.assign(1, {glm::dvec2(0.0), glm::dvec2(0.0), glm::dvec2(0.0)});
    add(set, point);
    return;
  }
  const auto middle = group.begin() + static_cast<std::ptrdiff_t>(group.size() / 2);
  chart_or_split(tris, std::vector<uint32_t>(group.begin(), middle), set);
  chart_or_split(tris, std::vector<uint32_t>(middle, group.end()), set);
}

// meshopt_buildMeshlets over mesh `m`'s non-degenerate triangles: groups of global ids in
// meshoptimizer's order, each at most max_triangles.
std::vector<std::vector<uint32_t>> meshoptimizer_groups(const SceneMesh& mesh, uint32_t first, const std::vector<charts::TriangleGeometry>& tris,
                                                        const MeshletSettings& settings) {
  std::vector<uint32_t> input;  // local ids of the triangles given to meshoptimizer
  std::vector<uint32_t> indices;
  for (uint32_t k = 0; k < mesh.triangles.size(); ++k) {
    if (tris[first + k].degenerate) continue;
    input.push_back(k);
    indices.insert(indices.end(), mesh.triangles[k].begin(), mesh.triangles[k].end());
  }
  std::vector<std::vector<uint32_t>> groups;
  if (input.empty()) return groups;
  // Positions in float, centred on the used points' box and scaled to about unit size (so that
  // any finite double coordinates stay finite floats); clustering does not depend on the scale.
  glm::dvec3 lo(std::numeric_limits<double>::infinity()), hi(-std::numeric_limits<double>::infinity());
  for (uint32_t k : input)
    for (uint32_t v : mesh.triangles[k]) {
      lo = glm::min(lo, mesh.positions[v]);
      hi = glm::max(hi, mesh.positions[v]);
    }
  const glm::dvec3 centre = 0.5 * lo + 0.5 * hi;
  const double half = std::max({0.5 * hi.x - 0.5 * lo.x, 0.5 * hi.y - 0.5 * lo.y, 0.5 * hi.z - 0.5 * lo.z});
  const double scale = half > 0.0 && std::isfinite(half) ? 1.0 / half : 1.0;
  std::vector<float> positions(3 * mesh.positions.size(), 0.0f);
  for (size_t v = 0; v < mesh.positions.size(); ++v) {
    const glm::dvec3 p = (mesh.positions[v] - centre) * scale;
    if (!(std::isfinite(p.x) && std::isfinite(p.y) && std::isfinite(p.z))) continue;  // used by degenerate triangles only
    for (int c = 0; c < 3; ++c) positions[3 * v + c] = static_cast<float>(p[c]);
  }
  // meshoptimizer 0.18 wants a multiple of 4 triangles per meshlet.
  const size_t max_triangles = std::max<size_t>(4, settings.max_triangles / 4 * 4);
  const size_t bound = meshopt_buildMeshletsBound(indices.size(), kMeshoptMaxVertices, max_triangles);
  std::vector<meshopt_Meshlet> meshlets(bound);
  std::vector<unsigned int> meshlet_vertices(bound * kMeshoptMaxVertices);
  std::vector<unsigned char> meshlet_triangles(bound * max_triangles * 3);
  const size_t count = meshopt_buildMeshlets(meshlets.data(), meshlet_vertices.data(), meshlet_triangles.data(), indices.data(), indices.size(),
                                             positions.data(), mesh.positions.size(), 3 * sizeof(float), kMeshoptMaxVertices, max_triangles,
                                             static_cast<float>(settings.cone_weight));

  // Back to triangle ids: meshoptimizer emits vertex triples, in the input's winding. Triangles
  // with the same vertices (duplicates, or both windings) are told apart by their winding first.
  auto sorted = [](std::array<uint32_t, 3> t) {
    std::sort(t.begin(), t.end());
    return t;
  };
  auto same_winding = [](const std::array<uint32_t, 3>& a, const std::array<uint32_t, 3>& b) {
    for (int r = 0; r < 3; ++r)
      if (a[0] == b[r] && a[1] == b[(r + 1) % 3] && a[2] == b[(r + 2) % 3]) return true;
    return false;
  };
  std::map<std::array<uint32_t, 3>, std::vector<uint32_t>> by_vertices;
  for (uint32_t k : input) by_vertices[sorted(mesh.triangles[k])].push_back(k);
  std::vector<char> emitted(mesh.triangles.size(), 0);
  const size_t cut = settings.max_triangles;
  for (size_t i = 0; i < count; ++i) {
    const meshopt_Meshlet& ml = meshlets[i];
    std::vector<uint32_t> group;
    for (uint32_t t = 0; t < ml.triangle_count; ++t) {
      std::array<uint32_t, 3> v;
      for (int c = 0; c < 3; ++c) v[c] = meshlet_vertices[ml.vertex_offset + meshlet_triangles[ml.triangle_offset + 3 * t + c]];
      const auto found = by_vertices.find(sorted(v));
      if (found == by_vertices.end()) continue;
      std::vector<uint32_t>& candidates = found->second;
      if (candidates.empty()) continue;
      size_t pick = candidates.size() - 1;
      for (size_t c = 0; c < candidates.size(); ++c)
        if (same_winding(mesh.triangles[candidates[c]], v)) {
          pick = c;
          break;
        }
      const uint32_t k = candidates[pick];
      candidates.erase(candidates.begin() + static_cast<std::ptrdiff_t>(pick));
      emitted[k] = 1;
      group.push_back(first + k);
      if (group.size() == cut) groups.push_back(std::move(group)), group.clear();
    }
    if (!group.empty()) groups.push_back(std::move(group));
  }
  // Whatever meshoptimizer did not emit (it emits every triangle; this keeps the set complete
  // regardless), in id order.
  std::vector<uint32_t> rest;
  for (uint32_t k : input)
    if (!emitted[k]) {
      rest.push_back(first + k);
      if (rest.size() == cut) groups.push_back(std::move(rest)), rest.clear();
    }
  if (!rest.empty()) groups.push_back(std::move(rest));
  return groups;
}

uint32_t size_level(double n) {
  uint32_t level = 0;
  while (level + 1 < PRISMOID_MSA_SIZES && double(PRISMOID_MSA_MIN_BLOCK << level) < n) ++level;
  return level;
}

}  // namespace

MeshletSet build_meshlets(const SurfaceScene& scene, const MeshletSettings& settings) {
  check(scene, settings);
  const std::vector<charts::TriangleGeometry> tris = charts::triangle_geometry(scene);
  MeshletSet set;
  set.meshlet_of_triangle.assign(tris.size(), 0u);
  set.corner_chart.assign(tris.size(), {});
  if (settings.clustering == Clustering::NormalCone) {
    for (const charts::PlanarChart& chart : charts::grow_planar_charts(scene, tris, settings.max_triangles, settings.max_normal_angle_deg))
      add(set, chart);
  } else {
    uint32_t first = 0;
    for (const SceneMesh& mesh : scene.meshes) {
      for (const auto& group : meshoptimizer_groups(mesh, first, tris, settings)) chart_or_split(tris, group, set);
      for (uint32_t k = 0; k < mesh.triangles.size(); ++k)
        if (tris[first + k].degenerate) add(set, *charts::chart_triangles(tris, {first + k}));  // point-like
      first += static_cast<uint32_t>(mesh.triangles.size());
    }
  }
  if (settings.parametrization == Parametrization::Conformal)
    for (Meshlet& m : set.meshlets) {
      charts::PlanarChart projected;
      projected.mesh = m.mesh;
      projected.triangles = m.triangles;
      projected.extent = m.extent;
      projected.normal = m.normal;
      for (uint32_t t : m.triangles) projected.corners.push_back(set.corner_chart[t]);
      const std::optional<charts::PlanarChart> conformal = charts::conformal_chart(tris, projected);
      if (!conformal) {
        ++set.conformal_fallbacks;
        continue;
      }
      m.extent = conformal->extent;
      for (size_t k = 0; k < conformal->triangles.size(); ++k) set.corner_chart[conformal->triangles[k]] = conformal->corners[k];
      m.triangles = conformal->triangles;
    }
  return set;
}

uint32_t msa_class_for(const glm::dvec2& extent, double density) {
  return size_level(std::ceil(extent.x * density) + 2.0) * PRISMOID_MSA_SIZES + size_level(std::ceil(extent.y * density) + 2.0);
}

glm::uvec2 msa_class_size(uint32_t c) {
  return {PRISMOID_MSA_MIN_BLOCK << (c / PRISMOID_MSA_SIZES), PRISMOID_MSA_MIN_BLOCK << (c % PRISMOID_MSA_SIZES)};
}

double msa_block_scale(const glm::dvec2& extent, uint32_t c) {
  const glm::dvec2 size(msa_class_size(c));
  const double sx = extent.x > 0.0 ? (size.x - 2.0) / extent.x : 1e300, sy = extent.y > 0.0 ? (size.y - 2.0) / extent.y : 1e300;
  const double s = std::min(sx, sy);
  return s < 1e300 ? s : 1.0;
}

MeshletStats meshlet_stats(const SurfaceScene& scene, const MeshletSet& set, double texels_per_unit) {
  if (!(texels_per_unit > 0.0) || !std::isfinite(texels_per_unit))
    throw InputError(scene.name, "meshlet stats: texels per unit must be positive and finite, not " + fmt(texels_per_unit));
  const std::vector<charts::TriangleGeometry> tris = charts::triangle_geometry(scene);
  if (set.meshlet_of_triangle.size() != tris.size() || set.corner_chart.size() != tris.size())
    throw InputError(scene.name, "meshlet stats: the meshlets were built from another scene");
  MeshletStats stats;
  stats.meshlets = set.meshlets.size();
  size_t triangles = 0;
  double sampling_sum = 0.0, sampling_weight = 0.0;
  double deviation = 0.0, weight = 0.0, chart_area = 0.0, rect_area = 0.0, scaled_area = 0.0, block_area = 0.0;
  for (const Meshlet& m : set.meshlets) {
    triangles += m.triangles.size();
    stats.max_triangles = std::max(stats.max_triangles, static_cast<uint32_t>(m.triangles.size()));
    double area = 0.0;
    for (uint32_t t : m.triangles) {
      if (t >= tris.size()) throw InputError(scene.name, "meshlet stats: the meshlets were built from another scene");
      const auto& c = set.corner_chart[t];
      const glm::dvec2 u = c[1] - c[0], v = c[2] - c[0];
      area += 0.5 * std::abs(u.x * v.y - u.y * v.x);
      const charts::TriangleGeometry& g = tris[t];
      if (g.degenerate || m.normal == glm::dvec3(0.0)) continue;
      const double sampling = std::sqrt(0.5 * std::abs(u.x * v.y - u.y * v.x) / g.area);
      stats.sampling_min = sampling_weight > 0.0 ? std::min(stats.sampling_min, sampling) : sampling;
      sampling_sum += g.area * sampling;
      sampling_weight += g.area;
      const double cosine = std::clamp(glm::dot(g.normal, m.normal), -1.0, 1.0);
      deviation += g.area * std::acos(cosine) * (180.0 / 3.14159265358979323846);
      weight += g.area;
    }
    if (!(m.extent.x > 0.0 && m.extent.y > 0.0)) continue;  // a degenerate triangle's meshlet: never drawn
    chart_area += area;
    rect_area += m.extent.x * m.extent.y;
    const uint32_t c = msa_class_for(m.extent, texels_per_unit);
    const glm::dvec2 size(msa_class_size(c));
    const double s = std::min(texels_per_unit, msa_block_scale(m.extent, c));
    scaled_area += area * s * s;
    block_area += size.x * size.y;
  }
  if (!set.meshlets.empty()) stats.mean_triangles = double(triangles) / double(set.meshlets.size());
  if (weight > 0.0) stats.mean_normal_deviation_deg = deviation / weight;
  if (rect_area > 0.0) stats.chart_fill = chart_area / rect_area;
  if (block_area > 0.0) stats.block_fill = scaled_area / block_area;
  if (sampling_weight > 0.0) stats.sampling_mean = sampling_sum / sampling_weight;
  return stats;
}

const char* parametrization_name(Parametrization p) {
  switch (p) {
    case Parametrization::Projection: return "projection";
    case Parametrization::Conformal: return "conformal";
    case Parametrization::Perspective: return "perspective";
    case Parametrization::Orthographic: return "orthographic";
  }
  return "projection";
}

bool parse_parametrization(const std::string& word, Parametrization& out) {
  for (Parametrization p : {Parametrization::Projection, Parametrization::Conformal, Parametrization::Perspective, Parametrization::Orthographic})
    if (word == parametrization_name(p)) {
      out = p;
      return true;
    }
  return false;
}

FrameCharts frame_charts(const SurfaceScene& scene, const MeshletSet& set, const Camera& camera, uint32_t width, uint32_t height,
                         Parametrization kind) {
  std::vector<glm::dvec3> corners;  // per global triangle corner, in camera space
  for (const SceneMesh& mesh : scene.meshes)
    for (const auto& t : mesh.triangles)
      for (uint32_t k : t) corners.push_back(glm::dvec3(view_matrix(camera, camera.eye) * glm::dvec4(mesh.positions[k] - camera.eye, 1.0)));
  const double tan_half = std::tan(glm::radians(camera.fovy_degrees) * 0.5), aspect = double(width) / double(height);
  FrameCharts out;
  out.corner_chart.assign(set.corner_chart.size(), {});
  out.extent.assign(set.meshlets.size(), glm::dvec2(0.0));
  out.perspective.assign(set.meshlets.size(), 0);
  for (size_t m = 0; m < set.meshlets.size(); ++m) {
    const Meshlet& meshlet = set.meshlets[m];
    bool perspective = kind == Parametrization::Perspective;
    for (uint32_t t : meshlet.triangles)
      for (int k = 0; k < 3; ++k) perspective = perspective && -corners[3 * size_t(t) + size_t(k)].z >= camera.near_distance;
    // Orthographic: along the direction from the eye to the meshlet's centre (camera space).
    glm::dvec3 centre(0.0);
    for (uint32_t t : meshlet.triangles)
      for (int k = 0; k < 3; ++k) centre += corners[3 * size_t(t) + size_t(k)];
    const glm::dvec3 axis = glm::length(centre) > 0.0 ? glm::normalize(centre) : glm::dvec3(0.0, 0.0, -1.0);
    glm::dvec3 side = glm::cross(axis, glm::dvec3(0.0, 1.0, 0.0));
    side = glm::length(side) > 1e-6 ? glm::normalize(side) : glm::dvec3(1.0, 0.0, 0.0);
    const glm::dvec3 rise = glm::cross(side, axis);
    glm::dvec2 lo(std::numeric_limits<double>::max()), hi(-std::numeric_limits<double>::max());
    for (uint32_t t : meshlet.triangles)
      for (int k = 0; k < 3; ++k) {
        const glm::dvec3 v = corners[3 * size_t(t) + size_t(k)];
        const glm::dvec2 q = perspective ? glm::dvec2((v.x / (-v.z * tan_half * aspect) + 1.0) * 0.5 * width,
                                                      (1.0 - v.y / (-v.z * tan_half)) * 0.5 * height)
                                         : glm::dvec2(glm::dot(v, side), glm::dot(v, rise));
        out.corner_chart[t][size_t(k)] = q;
        lo = glm::min(lo, q);
        hi = glm::max(hi, q);
      }
    for (uint32_t t : meshlet.triangles)
      for (auto& q : out.corner_chart[t]) q -= lo;
    if (!meshlet.triangles.empty()) out.extent[m] = glm::max(hi - lo, glm::dvec2(0.0));
    out.perspective[m] = perspective;
  }
  return out;
}

}  // namespace prismoid::msa
