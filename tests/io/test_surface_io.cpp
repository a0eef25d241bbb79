// Surfaces from files and their tetrahedralization by TetGen: the volume is the enclosed
// volume, holes and non-manifold edges are named, TetGen's failures become InputErrors.
#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

#include "io/surface_io.hpp"
#include "scene/input_error.hpp"

namespace prismoid::io {
namespace {

namespace fs = std::filesystem;

fs::path scratch(const std::string& name) {
  const fs::path dir = fs::temp_directory_path() / ("prismoid_surface_" + std::to_string(::getpid()));
  fs::create_directories(dir);
  return dir / name;
}

// The unit cube as OFF, outward-wound; `drop` faces removed from the end (a hole).
std::string cube_off(int drop = 0, double scale = 1.0) {
  const char* faces[12] = {"0 2 1", "0 3 2", "4 5 6", "4 6 7", "0 1 5", "0 5 4", "1 2 6", "1 6 5", "2 3 7", "2 7 6", "3 0 4", "3 4 7"};
  std::string s = "OFF\n# a cube\n8 " + std::to_string(12 - drop) + " 0\n";
  for (int i = 0; i < 8; ++i)
    s += std::to_string(scale * (i == 1 || i == 2 || i == 5 || i == 6)) + " " + std::to_string(scale * (i == 2 || i == 3 || i == 6 || i == 7)) +
         " " + std::to_string(scale * (i >= 4)) + "\n";
  for (int f = 0; f < 12 - drop; ++f) s += std::string("3 ") + faces[f] + "\n";
  return s;
}

double total_volume(const TetMesh& m) {
  double v = 0.0;
  for (const auto& t : m.tets) v += std::abs(signed_volume(m.points[t[0]], m.points[t[1]], m.points[t[2]], m.points[t[3]]));
  return v;
}

TEST(SurfaceIo, EnclosedVolumeIsTheCubesAndSignedByWinding) {
  const fs::path path = scratch("cube3.off");
  std::ofstream(path) << cube_off(0, 3.0);
  SurfaceMesh s = read_surface(path.string());
  // Exact: every term is a product of small integers and halves, exactly representable.
  EXPECT_EQ(enclosed_volume(s), 27.0);
  for (auto& t : s.triangles) std::swap(t[1], t[2]);
  EXPECT_EQ(enclosed_volume(s), -27.0);
}

TEST(SurfaceIo, TargetCellCountLandsWithinTheTolerance) {
  const fs::path path = scratch("cube-target.off");
  std::ofstream(path) << cube_off(0, 2.0);
  const SurfaceMesh s = read_surface(path.string());
  for (uint64_t target : {2000u, 20000u}) {
    TetgenOptions options;
    options.target_cells = target;
    const TetMesh m = tetrahedralize(s, options);
    EXPECT_LE(std::abs(double(m.tets.size()) - double(target)), kTargetCellsTolerance * double(target))
        << m.tets.size() << " cells for a target of " << target;
    EXPECT_NEAR(total_volume(m), 8.0, 1e-12);  // still a partition of the cube
  }
  TetgenOptions both;
  both.target_cells = 100;
  both.max_volume = 0.1;
  EXPECT_THROW(tetrahedralize(s, both), InputError);
}

TEST(SurfaceIo, ClosedCubeFillsWithTetrahedraOfItsVolume) {
  const fs::path path = scratch("cube.off");
  std::ofstream(path) << cube_off(0, 2.0);
  const SurfaceMesh s = read_surface(path.string());
  EXPECT_EQ(s.points.size(), 8u);
  EXPECT_EQ(s.triangles.size(), 12u);
  EXPECT_TRUE(check_surface(s).closed());
  for (double max_volume : {0.0, 0.05}) {
    TetgenOptions options;
    options.max_volume = max_volume;
    const TetMesh m = tetrahedralize(s, options);
    EXPECT_NEAR(total_volume(m), 8.0, 1e-12);  // the cells partition the cube (side 2)
    if (max_volume > 0.0) {
      EXPECT_GE(m.tets.size(), size_t(8.0 / max_volume));
      for (const auto& t : m.tets)
        EXPECT_LE(std::abs(signed_volume(m.points[t[0]], m.points[t[1]], m.points[t[2]], m.points[t[3]])), max_volume * (1 + 1e-9));
    }
  }
}

TEST(SurfaceIo, StlCornersAreMergedIntoSharedPoints) {
  // ASCII STL repeats each corner per facet: a tetrahedron is 12 corners, 4 points once merged.
  const fs::path path = scratch("tet.stl");
  std::ofstream out(path);
  const double v[4][3] = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {0, 0, 1}};
  const int f[4][3] = {{0, 2, 1}, {0, 1, 3}, {1, 2, 3}, {0, 3, 2}};
  out << "solid t\n";
  for (const auto& face : f) {
    out << "facet normal 0 0 0\n outer loop\n";
    for (int k : face) out << "  vertex " << v[k][0] << " " << v[k][1] << " " << v[k][2] << "\n";
    out << " endloop\nendfacet\n";
  }
  out << "endsolid t\n";
  out.close();
  const SurfaceMesh s = read_surface(path.string());
  EXPECT_EQ(s.points.size(), 4u);
  EXPECT_TRUE(check_surface(s).closed());
  EXPECT_NEAR(total_volume(tetrahedralize(s, {})), 1.0 / 6.0, 1e-15);
}

TEST(SurfaceIo, OpenSurfaceIsNamedAndHolesCanBeFilled) {
  const fs::path path = scratch("open.off");
  std::ofstream(path) << cube_off(2);  // the x = 0 side is missing
  const SurfaceMesh s = read_surface(path.string());
  const SurfaceCheck c = check_surface(s);
  EXPECT_EQ(c.boundary_edges, 4u);
  EXPECT_EQ(c.nonmanifold_edges, 0u);
  try {
    tetrahedralize(s, {});
    ADD_FAILURE() << "an open surface was tetrahedralized";
  } catch (const InputError& e) {
    const std::string what = e.what();
    EXPECT_NE(what.find(path.string()), std::string::npos) << what;
    EXPECT_NE(what.find("4 boundary"), std::string::npos) << what;
    EXPECT_NE(what.find("--fill-holes"), std::string::npos) << what;
  }
  const SurfaceMesh filled = fill_holes(s);
  EXPECT_TRUE(check_surface(filled).closed());
  EXPECT_NEAR(total_volume(tetrahedralize(filled, {})), 1.0, 1e-12);
}

TEST(SurfaceIo, SelfIntersectingSurfaceIsRejectedWithTetGensReason) {
  // Two cubes overlapping in space, as one surface: TetGen finds the intersecting facets.
  std::string a = cube_off(), text = "OFF\n16 24 0\n";
  std::istringstream in(a);
  std::string line;
  std::vector<std::string> vertices, faces;
  std::getline(in, line);
  std::getline(in, line);
  std::getline(in, line);
  for (int i = 0; i < 8 && std::getline(in, line); ++i) vertices.push_back(line);
  while (std::getline(in, line)) faces.push_back(line);
  for (const auto& v : vertices) text += v + "\n";
  for (const auto& v : vertices) {
    std::istringstream xyz(v);
    double x, y, z;
    xyz >> x >> y >> z;
    text += std::to_string(x + 0.5) + " " + std::to_string(y + 0.3) + " " + std::to_string(z + 0.2) + "\n";
  }
  for (const auto& f : faces) text += f + "\n";
  for (const auto& f : faces) {
    std::istringstream abc(f);
    int n, p, q, r;
    abc >> n >> p >> q >> r;
    text += "3 " + std::to_string(p + 8) + " " + std::to_string(q + 8) + " " + std::to_string(r + 8) + "\n";
  }
  const fs::path path = scratch("overlap.off");
  std::ofstream(path) << text;
  const SurfaceMesh s = read_surface(path.string());
  EXPECT_TRUE(check_surface(s).closed());  // each cube is closed: only TetGen can tell
  try {
    tetrahedralize(s, {});
    ADD_FAILURE() << "a self-intersecting surface was tetrahedralized";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("intersects itself"), std::string::npos) << e.what();
  }
}

TEST(SurfaceIo, TetrahedraAreCachedByContentAndOptions) {
  const fs::path path = scratch("cached.off"), cache = scratch("cache");
  std::ofstream(path) << cube_off();
  SurfaceToTets options;
  options.cache_dir = cache.string();
  options.tetgen.max_volume = 0.02;
  const SurfaceTets first = surface_to_tets(path.string(), options);
  EXPECT_FALSE(first.from_cache);
  EXPECT_TRUE(fs::exists(first.cache_file));
  const SurfaceTets second = surface_to_tets(path.string(), options);
  EXPECT_TRUE(second.from_cache);
  EXPECT_EQ(second.mesh.tets, first.mesh.tets);
  EXPECT_EQ(second.mesh.points, first.mesh.points);  // .vtu stores doubles: exact
  options.tetgen.max_volume = 0.05;  // other options: another entry
  EXPECT_FALSE(surface_to_tets(path.string(), options).from_cache);
  std::ofstream(path) << cube_off(0, 2.0);  // other content: another entry
  EXPECT_FALSE(surface_to_tets(path.string(), options).from_cache);
}

TEST(SurfaceIo, TetGenReportsThatItRunsAndCanBeCancelled) {
  const fs::path path = scratch("cancel.off");
  std::ofstream(path) << cube_off();
  const SurfaceMesh s = read_surface(path.string());
  int calls = 0;
  const TetMesh m = tetrahedralize(s, {}, [&](double f, const std::string& stage) {
    EXPECT_LT(f, 0.0);  // TetGen cannot say how far it is
    EXPECT_EQ(stage, "TetGen");
    ++calls;
    return true;
  });
  EXPECT_GE(calls, 1);
  EXPECT_NEAR(total_volume(m), 1.0, 1e-12);
  EXPECT_THROW(tetrahedralize(s, {}, [](double, const std::string&) { return false; }), Cancelled);
}

TEST(SurfaceIo, BadFilesNameTheFileAndTheProblem) {
  struct Case { std::string name, text, fragment; };
  const std::vector<Case> cases = {
      {"header.off", "COFF\n3 1 0\n", "no 'OFF' header"},
      {"short.off", "OFF\n3 1 0\n0 0 0\n1 0 0\n", "ends early"},
      {"index.off", "OFF\n3 1 0\n0 0 0\n1 0 0\n0 1 0\n3 0 1 7\n", "names vertex 7"},
      {"nan.off", "OFF\n3 1 0\n0 0 nan\n1 0 0\n0 1 0\n3 0 1 2\n", "coordinate"},
      {"empty.off", "OFF\n0 0 0\n", "no surface triangles"},
      {"garbage.stl", "this is not an STL file at all", "garbage.stl"},
  };
  for (const auto& c : cases) {
    const fs::path path = scratch(c.name);
    std::ofstream(path) << c.text;
    try {
      read_surface(path.string());
      ADD_FAILURE() << c.name << " was accepted";
    } catch (const InputError& e) {
      const std::string what = e.what();
      EXPECT_NE(what.find(path.string()), std::string::npos) << what;
      EXPECT_NE(what.find(c.fragment), std::string::npos) << c.name << ": " << what;
    }
  }
  EXPECT_THROW(read_surface("/no/such/surface.ply"), InputError);
  fs::remove_all(scratch("").parent_path());
}

}  // namespace
}  // namespace prismoid::io
