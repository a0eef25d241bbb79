#include "scene/generators.hpp"
#include "scene/tet_mesh.hpp"

#include <cmath>
#include <map>
#include <string>
#include <utility>
#include <vector>
#include <algorithm>
#include <glm/geometric.hpp>

namespace prismoid {

TetMesh make_box_mesh(const glm::dvec3& lo, const glm::dvec3& hi, uint32_t n,
                      const std::function<double(const glm::dvec3&)>& sigma) {
  TetMesh mesh;
  const uint32_t m = n + 1;
  auto point_index = [m](uint32_t i, uint32_t j, uint32_t k) { return (k * m + j) * m + i; };
  mesh.points.reserve(size_t(m) * m * m);
  for (uint32_t k = 0; k < m; ++k)
    for (uint32_t j = 0; j < m; ++j)
      for (uint32_t i = 0; i < m; ++i) {
        glm::dvec3 t(double(i) / n, double(j) / n, double(k) / n);
        mesh.points.push_back(lo + t * (hi - lo));
      }
  // Kuhn split: the six paths from corner 000 to corner 111 through the cube's edges.
  static const uint32_t kPaths[6][3] = {{0, 1, 2}, {0, 2, 1}, {1, 0, 2}, {1, 2, 0}, {2, 0, 1}, {2, 1, 0}};
  for (uint32_t k = 0; k < n; ++k)
    for (uint32_t j = 0; j < n; ++j)
      for (uint32_t i = 0; i < n; ++i)
        for (const auto& path : kPaths) {
          uint32_t c[3] = {i, j, k};
          std::array<uint32_t, 4> tet;
          tet[0] = point_index(c[0], c[1], c[2]);
          for (int s = 0; s < 3; ++s) {
            ++c[path[s]];
            tet[s + 1] = point_index(c[0], c[1], c[2]);
          }
          const auto& p = mesh.points;
          if (signed_volume(p[tet[0]], p[tet[1]], p[tet[2]], p[tet[3]]) < 0.0) std::swap(tet[2], tet[3]);
          mesh.tets.push_back(tet);
        }
  for (const auto& tet : mesh.tets) {
    glm::dvec3 centroid(0.0);
    for (uint32_t v : tet) centroid += mesh.points[v];
    mesh.cell_extinction.push_back(sigma(centroid * 0.25));
  }
  for (const auto& p : mesh.points) mesh.point_scalars.push_back(sigma(p));
  return mesh;
}

SurfaceMesh make_icosphere(const glm::dvec3& center, double radius, uint32_t subdivisions) {
  const double t = (1.0 + std::sqrt(5.0)) / 2.0;
  std::vector<glm::dvec3> points = {{-1, t, 0}, {1, t, 0}, {-1, -t, 0}, {1, -t, 0}, {0, -1, t}, {0, 1, t},
                                    {0, -1, -t}, {0, 1, -t}, {t, 0, -1}, {t, 0, 1}, {-t, 0, -1}, {-t, 0, 1}};
  for (auto& p : points) p = glm::normalize(p);
  std::vector<std::array<uint32_t, 3>> faces = {{0, 11, 5}, {0, 5, 1}, {0, 1, 7}, {0, 7, 10}, {0, 10, 11}, {1, 5, 9}, {5, 11, 4},
                                                {11, 10, 2}, {10, 7, 6}, {7, 1, 8}, {3, 9, 4}, {3, 4, 2}, {3, 2, 6}, {3, 6, 8},
                                                {3, 8, 9}, {4, 9, 5}, {2, 4, 11}, {6, 2, 10}, {8, 6, 7}, {9, 8, 1}};
  for (uint32_t s = 0; s < subdivisions; ++s) {
    std::map<std::pair<uint32_t, uint32_t>, uint32_t> midpoints;  // shared edges get one midpoint
    auto midpoint = [&](uint32_t a, uint32_t b) {
      const auto key = std::minmax(a, b);
      const auto found = midpoints.find(key);
      if (found != midpoints.end()) return found->second;
      points.push_back(glm::normalize(points[a] + points[b]));
      return midpoints[key] = static_cast<uint32_t>(points.size() - 1);
    };
    std::vector<std::array<uint32_t, 3>> finer;
    for (const auto& f : faces) {
      const uint32_t ab = midpoint(f[0], f[1]), bc = midpoint(f[1], f[2]), ca = midpoint(f[2], f[0]);
      finer.push_back({f[0], ab, ca});
      finer.push_back({f[1], bc, ab});
      finer.push_back({f[2], ca, bc});
      finer.push_back({ab, bc, ca});
    }
    faces = std::move(finer);
  }
  SurfaceMesh sphere;
  sphere.name = "icosphere (" + std::to_string(faces.size()) + " triangles)";
  for (const auto& p : points) sphere.points.push_back(center + radius * p);
  sphere.triangles = std::move(faces);
  return sphere;
}

SurfaceMesh make_cube_surface(const glm::dvec3& center, double half, uint32_t n) {
  n = std::max(n, 1u);
  SurfaceMesh cube;
  cube.name = "cube (" + std::to_string(12 * n * n) + " triangles)";
  std::map<std::array<uint32_t, 3>, uint32_t> index;  // grid point (0..n per axis) -> point
  auto point = [&](std::array<uint32_t, 3> g) {
    const auto found = index.find(g);
    if (found != index.end()) return found->second;
    const glm::dvec3 t = glm::dvec3(g[0], g[1], g[2]) / static_cast<double>(n);
    cube.points.push_back(center + half * (2.0 * t - 1.0));
    return index[g] = static_cast<uint32_t>(cube.points.size() - 1);
  };
  for (uint32_t axis = 0; axis < 3; ++axis)
    for (uint32_t side = 0; side < 2; ++side) {
      const uint32_t a = (axis + 1) % 3, b = (axis + 2) % 3;  // (a, b, axis) is right-handed
      for (uint32_t i = 0; i < n; ++i)
        for (uint32_t j = 0; j < n; ++j) {
          std::array<uint32_t, 4> q;
          const uint32_t corners[4][2] = {{i, j}, {i + 1, j}, {i + 1, j + 1}, {i, j + 1}};
          for (int c = 0; c < 4; ++c) {
            std::array<uint32_t, 3> g{};
            g[axis] = side * n;
            g[a] = corners[c][0];
            g[b] = corners[c][1];
            q[c] = point(g);
          }
          // Counter-clockwise about +axis on the far side, clockwise on the near side.
          if (side == 1) {
            cube.triangles.push_back({q[0], q[1], q[2]});
            cube.triangles.push_back({q[0], q[2], q[3]});
          } else {
            cube.triangles.push_back({q[0], q[2], q[1]});
            cube.triangles.push_back({q[0], q[3], q[2]});
          }
        }
    }
  return cube;
}

TetMesh make_ball_mesh(const glm::dvec3& center, double radius, uint32_t subdivisions, double sigma) {
  const SurfaceMesh sphere = make_icosphere(center, radius, subdivisions);
  const auto& faces = sphere.triangles;
  TetMesh mesh;
  mesh.name = "ball (" + std::to_string(faces.size()) + " tetrahedra)";
  mesh.points = sphere.points;
  const auto centre_index = static_cast<uint32_t>(mesh.points.size());
  mesh.points.push_back(center);
  for (const auto& f : faces) {
    std::array<uint32_t, 4> tet = {centre_index, f[0], f[1], f[2]};
    const auto& p = mesh.points;
    if (signed_volume(p[tet[0]], p[tet[1]], p[tet[2]], p[tet[3]]) < 0.0) std::swap(tet[2], tet[3]);
    mesh.tets.push_back(tet);
    mesh.cell_extinction.push_back(sigma);
  }
  return mesh;
}

TetMesh make_default_volume() {
  auto density = [](const glm::dvec3& p) {
    auto blob = [&](glm::dvec3 c, double r, double a) {
      double d2 = glm::dot(p - c, p - c);
      return a * std::exp(-d2 / (r * r));
    };
    return blob({-0.35, 0.25, 0.0}, 0.45, 3.0) + blob({0.4, -0.2, 0.2}, 0.35, 5.0) + blob({0.1, 0.55, -0.4}, 0.25, 6.0);
  };
  TetMesh mesh = make_box_mesh(glm::dvec3(-1.0), glm::dvec3(1.0), 16, density);
  mesh.name = "default (embedded: three Gaussian blobs, 24576 tetrahedra)";
  return mesh;
}

}  // namespace prismoid
