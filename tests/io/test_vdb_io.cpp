// OpenVDB grids read as voxel tetrahedra and dense samples, and written from surfaces. The
// input grids are made here with OpenVDB itself.
#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <unistd.h>

#include <glm/geometric.hpp>
#include <glm/vec4.hpp>
#include <openvdb/openvdb.h>
#include <openvdb/io/File.h>
#include <openvdb/tools/LevelSetSphere.h>
#include <openvdb/tools/LevelSetUtil.h>

#include "io/vdb_io.hpp"
#include "scene/generators.hpp"
#include "scene/input_error.hpp"
#include "support/mesh_faces.hpp"

namespace prismoid {
namespace {

namespace fs = std::filesystem;
using openvdb::Coord;
using openvdb::FloatGrid;

fs::path temp_path(const std::string& name) {
  static const fs::path dir = [] {
    fs::path d = fs::temp_directory_path() / ("prismoid_vdb_" + std::to_string(::getpid()));
    fs::create_directories(d);
    return d;
  }();
  return dir / name;
}

std::string write_grids(const std::string& name, const openvdb::GridPtrVec& grids) {
  openvdb::initialize();
  const std::string path = temp_path(name).string();
  openvdb::io::File file(path);
  file.write(grids);
  file.close();
  return path;
}

// An affine index-to-world map with non-uniform scale, a rotation and a translation, so a test
// catches any place that assumes an axis-aligned unit grid.
openvdb::math::Transform::Ptr skewed_transform() {
  openvdb::Mat4d m = openvdb::Mat4d::identity();
  m.preScale(openvdb::Vec3d(0.5, 2.0, 1.25));
  m.postRotate(openvdb::math::Z_AXIS, 0.3);
  m.postTranslate(openvdb::Vec3d(10.0, -3.0, 7.0));
  return openvdb::math::Transform::createLinearTransform(m);
}

glm::dvec3 world(const openvdb::math::Transform& xform, const Coord& c) {
  const openvdb::Vec3d w = xform.indexToWorld(c);
  return {w[0], w[1], w[2]};
}

// A fog grid whose values are affine in the index, active on a 4 x 3 x 5 block.
double affine_value(const openvdb::Vec3d& ijk) { return 1.0 + 0.1 * ijk.x() + 0.2 * ijk.y() + 0.3 * ijk.z(); }
FloatGrid::Ptr affine_block(bool with_transform) {
  FloatGrid::Ptr grid = FloatGrid::create(0.0f);
  grid->setName("density");
  grid->setGridClass(openvdb::GRID_FOG_VOLUME);
  if (with_transform) grid->setTransform(skewed_transform());
  auto acc = grid->getAccessor();
  for (int k = 0; k < 5; ++k)
    for (int j = 0; j < 3; ++j)
      for (int i = 0; i < 4; ++i) acc.setValue(Coord(i - 1, j + 2, k - 3), float(affine_value(openvdb::Vec3d(i - 1, j + 2, k - 3))));
  return grid;
}

TEST(VdbIo, OneActiveVoxelMakesItsEightDualCells) {
  FloatGrid::Ptr grid = FloatGrid::create(0.0f);
  grid->setName("d");
  grid->tree().setValue(Coord(5, -2, 7), 0.75f);
  const std::string path = write_grids("one.vdb", {grid});
  io::VdbReadOptions options;
  options.density_scale = 2.0;
  const TetMesh mesh = io::read_vdb_voxels(path, options);
  // The voxel is a corner of 8 cells; their corners are the 3 x 3 x 3 voxels around it.
  EXPECT_EQ(mesh.points.size(), 27u);
  EXPECT_EQ(mesh.tets.size(), 48u);
  size_t active = 0;
  for (size_t i = 0; i < mesh.points.size(); ++i) {
    // Unit voxels, identity transform: the point is the voxel's index.
    const bool centre = mesh.points[i] == glm::dvec3(5, -2, 7);
    active += centre;
    EXPECT_EQ(mesh.point_scalars[i], centre ? 0.75 : 0.0);
    EXPECT_EQ(mesh.point_extinction[i], centre ? 1.5 : 0.0);
  }
  EXPECT_EQ(active, 1u);
}

TEST(VdbIo, PointsAreVoxelCentresWithTheGridValuesAndTheMeshIsConforming) {
  const FloatGrid::Ptr grid = affine_block(true);
  const std::string path = write_grids("affine.vdb", {grid});
  const TetMesh mesh = io::read_vdb_voxels(path);
  // Active block 4 x 3 x 5 voxels: cells whose box touches it span 5 x 4 x 6, points 6 x 5 x 7.
  EXPECT_EQ(mesh.tets.size(), 6u * 5 * 4 * 6);
  ASSERT_EQ(mesh.points.size(), 6u * 5 * 7);
  const auto& xform = grid->transform();
  auto acc = grid->getConstAccessor();
  for (size_t i = 0; i < mesh.points.size(); ++i) {
    const openvdb::Vec3d ijk = xform.worldToIndex(openvdb::Vec3d(mesh.points[i].x, mesh.points[i].y, mesh.points[i].z));
    const Coord c(int(std::lround(ijk.x())), int(std::lround(ijk.y())), int(std::lround(ijk.z())));
    // The point is exactly where the transform puts that voxel (same double arithmetic)...
    EXPECT_EQ(mesh.points[i], world(xform, c));
    // ...and carries the grid's value there, bit for bit (float widened to double).
    EXPECT_EQ(mesh.point_scalars[i], double(acc.getValue(c)));
  }
  for (const auto& [face, uses] : test::face_uses(mesh)) EXPECT_TRUE(uses == 1 || uses == 2);
  for (const auto& t : mesh.tets) EXPECT_GT(signed_volume(mesh.points[t[0]], mesh.points[t[1]], mesh.points[t[2]], mesh.points[t[3]]), 0.0);
}

TEST(VdbIo, LinearInterpolationOverTheTetrahedraReproducesAnAffineField) {
  // Values affine in the index on every point (the inactive ring too), so the Kuhn interpolant
  // must equal the field everywhere, not only at the voxel centres. Tolerance: values are floats
  // of magnitude <= 4, so each carries a rounding of 2^-24 * 4 = 2.4e-7; the interpolant is a convex
  // combination of four of them and adds only double rounding.
  FloatGrid::Ptr grid = affine_block(true);
  auto acc = grid->getAccessor();
  for (int k = -5; k <= 3; ++k)  // fill the ring of inactive voxels with the field too
    for (int j = 0; j <= 6; ++j)
      for (int i = -3; i <= 4; ++i)
        if (!acc.isValueOn(Coord(i, j, k))) acc.setValueOff(Coord(i, j, k), float(affine_value(openvdb::Vec3d(i, j, k))));
  const std::string path = write_grids("affine_ring.vdb", {grid});
  io::VdbReadOptions options;
  options.role = io::ArrayRole::Scalars;  // the ring's field goes negative, which no density may
  const TetMesh mesh = io::read_vdb_voxels(path, options);
  const auto& xform = grid->transform();
  for (const auto& t : mesh.tets)
    for (const glm::dvec4 bary : {glm::dvec4(0.25), glm::dvec4(0.1, 0.2, 0.3, 0.4), glm::dvec4(0.7, 0.1, 0.1, 0.1)}) {
      glm::dvec3 p(0.0);
      double interpolated = 0.0;
      for (int v = 0; v < 4; ++v) {
        p += bary[v] * mesh.points[t[size_t(v)]];
        interpolated += bary[v] * mesh.point_scalars[t[size_t(v)]];
      }
      const double exact = affine_value(xform.worldToIndex(openvdb::Vec3d(p.x, p.y, p.z)));
      EXPECT_NEAR(interpolated, exact, 3e-7);
    }
}

TEST(VdbIo, SubsampleKeepsEveryKthVoxel) {
  const FloatGrid::Ptr grid = affine_block(false);
  const std::string path = write_grids("affine_plain.vdb", {grid});
  io::VdbReadOptions options;
  options.subsample = 2;
  const TetMesh mesh = io::read_vdb_voxels(path, options);
  ASSERT_FALSE(mesh.points.empty());
  auto acc = grid->getConstAccessor();
  for (size_t i = 0; i < mesh.points.size(); ++i) {
    const glm::dvec3 p = mesh.points[i];
    for (int a = 0; a < 3; ++a) EXPECT_EQ(std::fmod(std::abs(p[a]), 2.0), 0.0) << "point " << i;
    EXPECT_EQ(mesh.point_scalars[i], double(acc.getValue(Coord(int(p.x), int(p.y), int(p.z)))));
  }
  for (const auto& [face, uses] : test::face_uses(mesh)) EXPECT_TRUE(uses == 1 || uses == 2);
  // Every active voxel lies in some tetrahedron's bounding box: no active region is dropped.
  const TetMesh full = io::read_vdb_voxels(path);
  EXPECT_LT(mesh.tets.size(), full.tets.size());
  Bounds b = bounds_of(mesh);
  for (auto it = grid->cbeginValueOn(); it; ++it)
    for (int a = 0; a < 3; ++a) {
      EXPECT_GE(it.getCoord()[a], b.min[a]);
      EXPECT_LE(it.getCoord()[a], b.max[a]);
    }
}

TEST(VdbIo, LevelSetExtinctionIsOpenVdbsFogMappingAndTheInteriorIsFilled) {
  constexpr float kRadius = 1.0f, kVoxel = 0.1f, kHalfWidth = 3.0f;
  FloatGrid::Ptr sphere = openvdb::tools::createLevelSetSphere<FloatGrid>(kRadius, openvdb::Vec3f(0.0f), kVoxel, kHalfWidth);
  sphere->setName("surface");
  const std::string path = write_grids("ls.vdb", {sphere});
  const TetMesh mesh = io::read_vdb_voxels(path);
  // The band's inside depth: the smallest distance stored (sdfToFogVolume's cutoff).
  double deepest = 0.0;
  for (double s : mesh.point_scalars) deepest = std::min(deepest, s);
  ASSERT_LT(deepest, 0.0);
  bool centre_seen = false;
  for (size_t i = 0; i < mesh.points.size(); ++i) {
    const double sdf = mesh.point_scalars[i];
    // Expected per the mapping documented in vdb_io.hpp; float values, so 1e-6 relative.
    const double expected = sdf >= 0.0 ? 0.0 : std::min(1.0, sdf / deepest);
    EXPECT_NEAR(mesh.point_extinction[i], expected, 1e-6) << "sdf " << sdf;
    if (glm::length(mesh.points[i]) < 1e-9) {
      centre_seen = true;
      EXPECT_EQ(mesh.point_extinction[i], 1.0);  // deep inside: the solid interior
    }
  }
  EXPECT_TRUE(centre_seen) << "the interior is not filled with cells";
  for (const auto& [face, uses] : test::face_uses(mesh)) EXPECT_TRUE(uses == 1 || uses == 2);
}

TEST(VdbIo, InspectDescribesEveryGridAndWhatReadingMakes) {
  FloatGrid::Ptr fog = openvdb::tools::createLevelSetSphere<FloatGrid>(1.0f, openvdb::Vec3f(0.0f), 0.1f);
  openvdb::tools::sdfToFogVolume(*fog);
  fog->setName("fog");
  auto vectors = openvdb::Vec3SGrid::create();
  vectors->setName("velocity");
  vectors->tree().setValue(Coord(1, 2, 3), openvdb::Vec3s(1, 0, 0));
  const FloatGrid::Ptr block = affine_block(true);
  const std::string path = write_grids("several.vdb", {vectors, fog, block});
  const io::VdbInfo info = io::inspect_vdb(path);
  // In the file's order: velocity, fog, density (the block).
  ASSERT_EQ(info.grids.size(), 3u);
  EXPECT_EQ(info.grids[0].name, "velocity");
  EXPECT_EQ(info.grids[0].value_type, "vec3s");
  EXPECT_FALSE(info.grids[0].has_range);
  EXPECT_EQ(info.grids[1].grid_class, io::VdbClass::FogVolume);
  EXPECT_EQ(info.grids[1].active_voxels, fog->activeVoxelCount());
  EXPECT_EQ(info.grids[1].value_max, 1.0);
  const io::VdbGridInfo& b = info.grids[2];
  EXPECT_EQ(b.active_voxels, 60u);
  EXPECT_EQ(b.index_min, glm::ivec3(-1, 2, -3));
  EXPECT_EQ(b.index_max, glm::ivec3(2, 4, 1));
  EXPECT_FLOAT_EQ(float(b.value_min), float(affine_value(openvdb::Vec3d(-1, 2, -3))));
  for (int a = 0; a < 3; ++a) EXPECT_NEAR(b.voxel_size[a], glm::dvec3(0.5, 2.0, 1.25)[a], 1e-12);  // through a rotation
  // The conversion it announces is the one the reader makes; the first float grid is the fog.
  io::VdbReadOptions options;
  options.grid = "density";
  const TetMesh mesh = io::read_vdb_voxels(path, options);
  EXPECT_EQ(b.tets(), mesh.tets.size());
  EXPECT_EQ(b.mesh_points, mesh.points.size());
  const TetMesh fog_mesh = io::read_vdb_voxels(path);
  EXPECT_EQ(fog_mesh.tets.size(), info.grids[1].tets());
  EXPECT_EQ(fog_mesh.points.size(), info.grids[1].mesh_points);
}

TEST(VdbIo, DenseSamplesCoverTheActiveBoxWithTheGridValues) {
  const FloatGrid::Ptr block = affine_block(false);
  block->setTransform(openvdb::math::Transform::createLinearTransform(0.25));
  const std::string path = write_grids("dense.vdb", {block});
  const io::VdbDense dense = io::read_vdb_dense(path);
  EXPECT_EQ(dense.dims, glm::uvec3(4, 3, 5));
  EXPECT_EQ(dense.origin, glm::dvec3(-0.25, 0.5, -0.75));
  EXPECT_EQ(dense.spacing, glm::dvec3(0.25));
  EXPECT_EQ(dense.grid_class, io::VdbClass::FogVolume);
  auto acc = block->getConstAccessor();
  for (uint32_t z = 0; z < 5; ++z)
    for (uint32_t y = 0; y < 3; ++y)
      for (uint32_t x = 0; x < 4; ++x)
        EXPECT_EQ(dense.values[x + 4 * (y + 3 * z)], acc.getValue(Coord(int(x) - 1, int(y) + 2, int(z) - 3)));
  // Leaf nodes are 8^3 boxes at multiples of 8: the block (x from -1, z from -3) straddles x = 0
  // and z = 0, so four leaves, at x in {-8, 0}, y 0, z in {-8, 0}, relative to the origin (-1, 2, -3).
  ASSERT_EQ(dense.active_boxes.size(), 4u);
  for (const auto& box : dense.active_boxes) {
    EXPECT_EQ(box.size, glm::ivec3(8));
    EXPECT_TRUE(box.min.x == -7 || box.min.x == 1) << box.min.x;
    EXPECT_EQ(box.min.y, -2);
    EXPECT_TRUE(box.min.z == -5 || box.min.z == 3) << box.min.z;
  }
  EXPECT_THROW(io::read_vdb_dense(path, {}, 59), InputError);
  EXPECT_THROW(io::read_vdb_dense(write_grids("rotated.vdb", {affine_block(true)})), InputError);
}

TEST(VdbIo, LevelSetFromASurfaceCrossesZeroWithinAVoxelOfIt) {
  // The icosphere's surface (the ball's boundary), through OpenVDB's meshToLevelSet.
  const TetMesh ball = make_ball_mesh(glm::dvec3(0.5, -0.25, 2.0), 1.0, 3, 1.0);
  const SurfaceMesh surface = io::boundary_surface(ball);
  EXPECT_EQ(surface.triangles.size(), ball.tets.size());  // one boundary face per cell
  const std::string path = temp_path("ball_ls.vdb").string();
  io::VdbWriteOptions options;
  options.fog = false;
  options.voxel_size = 0.05;
  const io::VdbWriteReport report = io::write_vdb_from_surface(path, surface, options);
  EXPECT_EQ(report.voxel_size, 0.05);
  io::VdbReadOptions read;
  read.role = io::ArrayRole::Scalars;
  const TetMesh mesh = io::read_vdb_voxels(path, read);
  // Along every tetrahedron edge whose ends straddle zero, the linear zero crossing lies within
  // one voxel of the surface. The icosphere's flat faces sit inside the unit sphere by at most
  // 1 - cos(half the largest edge angle) < 0.005 (3 subdivisions), which the bound adds.
  size_t crossings = 0;
  for (const auto& t : mesh.tets)
    for (int a = 0; a < 4; ++a)
      for (int b = a + 1; b < 4; ++b) {
        const double fa = mesh.point_scalars[t[size_t(a)]], fb = mesh.point_scalars[t[size_t(b)]];
        if ((fa < 0.0) == (fb < 0.0)) continue;
        const glm::dvec3 p = mesh.points[t[size_t(a)]] + (fa / (fa - fb)) * (mesh.points[t[size_t(b)]] - mesh.points[t[size_t(a)]]);
        EXPECT_NEAR(glm::length(p - glm::dvec3(0.5, -0.25, 2.0)), 1.0 - 0.0025, 0.05 + 0.0025);
        ++crossings;
      }
  EXPECT_GT(crossings, 1000u);
}

TEST(VdbIo, FogFromAClosedCubeIsOneInsideAndZeroOutside) {
  SurfaceMesh cube;
  cube.name = "cube";
  for (int i = 0; i < 8; ++i) cube.points.emplace_back(2.0 * (i & 1), 2.0 * ((i >> 1) & 1), 2.0 * (i >> 2));
  cube.triangles = {{0, 2, 1}, {1, 2, 3}, {4, 5, 6}, {5, 7, 6}, {0, 1, 4}, {1, 5, 4},
                    {2, 6, 3}, {3, 6, 7}, {0, 4, 2}, {2, 4, 6}, {1, 3, 5}, {3, 7, 5}};
  const std::string path = temp_path("cube_fog.vdb").string();
  io::VdbWriteOptions options;
  options.voxel_size = 0.1;
  io::write_vdb_from_surface(path, cube, options);
  EXPECT_FALSE(fs::exists(path + ".partial"));
  const TetMesh mesh = io::read_vdb_voxels(path);
  size_t deep = 0;
  for (size_t i = 0; i < mesh.points.size(); ++i) {
    const glm::dvec3 p = mesh.points[i];
    // Distance inside the cube (negative outside).
    const double inside = std::min({p.x, p.y, p.z, 2.0 - p.x, 2.0 - p.y, 2.0 - p.z});
    // The band reaches 3 voxels inside; half a voxel more covers where the ramp ends.
    if (inside > 0.35) {
      EXPECT_EQ(mesh.point_extinction[i], 1.0) << p.x << " " << p.y << " " << p.z;
      ++deep;
    }
    if (inside < -0.05) {
      EXPECT_EQ(mesh.point_extinction[i], 0.0) << p.x << " " << p.y << " " << p.z;
    }
  }
  EXPECT_GT(deep, 1000u);
}

// A closed slab 0.01 thick, tilted 45 degrees so that its bounding box is 1.4 or more on every
// side: a voxel size of 0.5 passes the bounding-box rule, yet no voxel centre lies inside the
// slab, so the fog would be empty and the level set all outside. Both are refused, naming why.
TEST(VdbIo, WritingRefusesAShapeThatHoldsNoVoxelCentre) {
  SurfaceMesh slab;
  slab.name = "slab";
  const double r = std::sqrt(0.5);
  for (int i = 0; i < 8; ++i) {
    const double x = 2.0 * (i & 1), y = 2.0 * ((i >> 1) & 1), z = 0.1 + 0.01 * (i >> 2);  // z = 0.1 to 0.11: no grid point
    slab.points.emplace_back(x, r * (y - z), r * (y + z));
  }
  slab.triangles = {{0, 2, 1}, {1, 2, 3}, {4, 5, 6}, {5, 7, 6}, {0, 1, 4}, {1, 5, 4},
                    {2, 6, 3}, {3, 6, 7}, {0, 4, 2}, {2, 4, 6}, {1, 3, 5}, {3, 7, 5}};
  for (const bool fog : {true, false}) {
    const std::string path = temp_path(fog ? "slab_fog.vdb" : "slab_levelset.vdb").string();
    io::VdbWriteOptions options;
    options.fog = fog;
    options.voxel_size = 0.5;
    try {
      io::write_vdb_from_surface(path, slab, options);
      ADD_FAILURE() << "a slab thinner than a voxel was written";
    } catch (const InputError& e) {
      EXPECT_NE(std::string(e.what()).find("slab: no voxel centre lies inside the surface at voxel size 0.5"), std::string::npos) << e.what();
    }
    EXPECT_FALSE(fs::exists(path));
  }
  // Finer voxels hold it.
  io::VdbWriteOptions fine;
  fine.voxel_size = 0.004;
  EXPECT_GT(io::write_vdb_from_surface(temp_path("slab_fine.vdb").string(), slab, fine).active_voxels, 0u);
}

TEST(VdbIo, WritingRefusesOpenSurfacesAndLeavesNoFileOnFailure) {
  SurfaceMesh open;
  open.name = "open";
  open.points = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}};
  open.triangles = {{0, 1, 2}};
  const std::string path = temp_path("open.vdb").string();
  try {
    io::write_vdb_from_surface(path, open, {});
    FAIL() << "an open surface was accepted";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("not closed"), std::string::npos) << e.what();
  }
  EXPECT_FALSE(fs::exists(path));
  const TetMesh ball = make_ball_mesh(glm::dvec3(0.0), 1.0, 1, 1.0);
  const std::string nowhere = (temp_path("missing_dir") / "x.vdb").string();
  EXPECT_THROW(io::write_vdb_from_surface(nowhere, io::boundary_surface(ball), {}), InputError);
  EXPECT_FALSE(fs::exists(nowhere + ".partial"));
  io::VdbWriteOptions tiny;
  tiny.voxel_size = 1e-4;  // 20000^3 voxels
  EXPECT_THROW(io::write_vdb_from_surface(temp_path("tiny.vdb").string(), io::boundary_surface(ball), tiny), InputError);
}

std::string error_of(const std::function<void()>& f) {
  try {
    f();
  } catch (const InputError& e) {
    return e.what();
  }
  return "(no error)";
}

TEST(VdbIo, BadFilesAndGridsAreInputErrorsNamingTheProblem) {
  auto voxels = [](const std::string& path, const std::string& grid = "") {
    return error_of([&] {
      io::VdbReadOptions o;
      o.grid = grid;
      io::read_vdb_voxels(path, o);
    });
  };
  EXPECT_NE(voxels(temp_path("absent.vdb").string()).find("does not exist"), std::string::npos);
  const std::string garbage = temp_path("garbage.vdb").string();
  std::ofstream(garbage) << "this is not a VDB file at all, just some text that goes on for a while...";
  EXPECT_NE(voxels(garbage).find("not a readable VDB file"), std::string::npos) << voxels(garbage);

  FloatGrid::Ptr fog = openvdb::tools::createLevelSetSphere<FloatGrid>(1.0f, openvdb::Vec3f(0.0f), 0.1f);
  openvdb::tools::sdfToFogVolume(*fog);
  fog->setName("fog");
  const std::string whole = write_grids("whole.vdb", {fog});
  std::string bytes(fs::file_size(whole), '\0');
  std::ifstream(whole, std::ios::binary).read(bytes.data(), std::streamsize(bytes.size()));
  for (const size_t keep : {size_t(8), size_t(100), bytes.size() / 2, bytes.size() - 10}) {
    const std::string cut = temp_path("cut_" + std::to_string(keep) + ".vdb").string();
    std::ofstream(cut, std::ios::binary).write(bytes.data(), std::streamsize(keep));
    const std::string e = voxels(cut);
    EXPECT_NE(e.find(cut + ": "), std::string::npos) << e;
    EXPECT_NE(e.find("not a readable VDB file"), std::string::npos) << keep << ": " << e;
  }
  std::string flipped = bytes;
  for (size_t i = bytes.size() / 3; i < bytes.size() / 3 + 64; ++i) flipped[i] = char(~flipped[i]);
  const std::string corrupt = temp_path("corrupt.vdb").string();
  std::ofstream(corrupt, std::ios::binary) << flipped;
  EXPECT_NE(voxels(corrupt).find(corrupt + ": "), std::string::npos);  // an error naming the file, whatever OpenVDB makes of it

  auto vectors = openvdb::Vec3SGrid::create();
  vectors->setName("velocity");
  vectors->tree().setValue(Coord(1, 2, 3), openvdb::Vec3s(1, 0, 0));
  const std::string no_float = write_grids("vectors.vdb", {vectors});
  EXPECT_NE(voxels(no_float).find("has no float grid"), std::string::npos);
  EXPECT_NE(voxels(no_float).find("'velocity' (vec3s)"), std::string::npos) << voxels(no_float);
  EXPECT_NE(voxels(whole, "smoke").find("has no grid 'smoke' (grids: 'fog' (float))"), std::string::npos) << voxels(whole, "smoke");

  FloatGrid::Ptr empty = FloatGrid::create(0.0f);
  empty->setName("nothing");
  EXPECT_NE(voxels(write_grids("empty.vdb", {empty})).find("'nothing' (float) is empty"), std::string::npos);

  FloatGrid::Ptr nan = affine_block(false);
  nan->tree().setValue(Coord(0, 3, 0), std::nanf(""));
  EXPECT_NE(voxels(write_grids("nan.vdb", {nan})).find("non-finite value at voxel (0, 3, 0)"), std::string::npos);

  FloatGrid::Ptr frustum = affine_block(false);
  frustum->setTransform(openvdb::math::Transform::createFrustumTransform(openvdb::BBoxd(openvdb::Vec3d(0), openvdb::Vec3d(10)), 0.5, 1.0, 0.1));
  EXPECT_NE(voxels(write_grids("frustum.vdb", {frustum})).find("non-linear"), std::string::npos);

  const std::string affine = write_grids("guard.vdb", {affine_block(false)});
  const std::string guard = error_of([&] {
    io::VdbReadOptions o;
    o.max_cells = 100;
    io::read_vdb_voxels(affine, o);
  });
  EXPECT_NE(guard.find("more than the limit of 100; try --subsample"), std::string::npos) << guard;
}

TEST(VdbIo, ProgressIsReportedAndCancels) {
  FloatGrid::Ptr fog = openvdb::tools::createLevelSetSphere<FloatGrid>(1.0f, openvdb::Vec3f(0.0f), 0.02f);
  openvdb::tools::sdfToFogVolume(*fog);
  const std::string path = write_grids("progress.vdb", {fog});
  io::VdbReadOptions options;
  int calls = 0;
  options.progress = [&](double, const std::string&) { return ++calls < 3; };
  EXPECT_THROW(io::read_vdb_voxels(path, options), io::Cancelled);
  EXPECT_EQ(calls, 3);
}

}  // namespace
}  // namespace prismoid
