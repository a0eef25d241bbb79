// Opening datasets without a window: the loader thread (results, errors naming the file,
// cancellation), the recent-files list, the union of several meshes, and the scene's list of
// datasets (visibility, active, what the mode falls back to).
#include <gtest/gtest.h>

#include <chrono>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <thread>

#include "app/viewer/dataset_list.hpp"
#include "app/viewer/load_job.hpp"
#include "app/viewer/recent_files.hpp"
#include "app/viewer/scene_merge.hpp"
#include "scene/generators.hpp"
#include "support/cube_surface.hpp"

namespace prismoid {
namespace {

namespace fs = std::filesystem;

fs::path scratch(const std::string& name) {
  const fs::path dir = fs::temp_directory_path() / ("prismoid-loading-" + name);
  fs::remove_all(dir);
  fs::create_directories(dir);
  return dir;
}

app::LoadOutcome wait_for(app::DatasetLoad& job, double seconds = 120.0) {
  const auto deadline = std::chrono::steady_clock::now() + std::chrono::duration<double>(seconds);
  while (!job.done() && std::chrono::steady_clock::now() < deadline) std::this_thread::sleep_for(std::chrono::milliseconds(5));
  EXPECT_TRUE(job.done()) << "the load did not end within " << seconds << " s";
  return job.take();
}

TEST(DatasetLoad, LoadsOnItsThreadIntoADataset) {
  app::LoadRequest request;
  request.path = "ball:2";
  app::DatasetLoad job(request);
  const app::LoadOutcome outcome = wait_for(job);
  ASSERT_TRUE(outcome.dataset) << outcome.error;
  EXPECT_EQ(outcome.dataset->mesh->tets.size(), 20u * 16u);  // the icosahedron, each face split in 4 twice
  EXPECT_FALSE(outcome.cancelled);
}

TEST(DatasetLoad, BadFilesGiveTheDataLayersMessageNamingTheFile) {
  const fs::path dir = scratch("bad");
  const fs::path truncated = dir / "truncated.vtu";
  std::ofstream(truncated) << "<?xml version=\"1.0\"?>\n<VTKFile type=\"UnstructuredGrid\" version=\"1.0\">\n<UnstructuredGrid>\n<Piece NumberOfPoints=\"4\"";
  for (const fs::path& path : {truncated, dir / "missing.vtu"}) {
    app::LoadRequest request;
    request.path = path.string();
    app::DatasetLoad job(request);
    const app::LoadOutcome outcome = wait_for(job);
    EXPECT_FALSE(outcome.dataset);
    EXPECT_FALSE(outcome.cancelled);
    EXPECT_NE(outcome.error.find(path.string()), std::string::npos) << outcome.error;
  }
}

// Cancelling stops TetGen's child process: the job ends long before the fill would (over a
// million cells at this bound) and says it was cancelled. Destroying a running job does the same.
TEST(DatasetLoad, CancelStopsTetGenPromptly) {
  const fs::path dir = scratch("cancel");
  setenv("XDG_CACHE_HOME", (dir / "cache").c_str(), 1);  // no cached result to make it quick
  test::write_cube_off(dir / "cube.off");
  app::LoadRequest request;
  request.path = (dir / "cube.off").string();
  request.tetgen.max_volume = 5e-7;
  app::DatasetLoad job(request);
  while (job.stage() != "TetGen" && !job.done()) std::this_thread::sleep_for(std::chrono::milliseconds(5));
  ASSERT_FALSE(job.done());
  const auto start = std::chrono::steady_clock::now();
  job.cancel();
  const app::LoadOutcome outcome = wait_for(job, 5.0);
  EXPECT_TRUE(outcome.cancelled);
  EXPECT_FALSE(outcome.dataset);
  EXPECT_LT(std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count(), 2.0);
  {
    app::DatasetLoad abandoned(request);
    std::this_thread::sleep_for(std::chrono::milliseconds(200));
  }  // the destructor cancels and joins
}

TEST(RecentFiles, MostRecentFirstWithoutDuplicatesAndAtMostTen) {
  const fs::path dir = scratch("recent");
  const fs::path file = dir / "config" / "prismoid" / "recent.txt";
  EXPECT_TRUE(app::read_recent(file).empty());  // no list yet
  for (int i = 0; i < 12; ++i) app::remember_opened(file, (dir / ("f" + std::to_string(i) + ".vtu")).string());
  app::remember_opened(file, (dir / "f5.vtu").string());
  app::remember_opened(file, "ball:3");  // a spec, not a file: not kept
  const auto list = app::read_recent(file);
  ASSERT_EQ(list.size(), app::kMaxRecent);
  EXPECT_EQ(list[0], (dir / "f5.vtu").string());
  EXPECT_EQ(list[1], (dir / "f11.vtu").string());
  EXPECT_EQ(std::count(list.begin(), list.end(), (dir / "f5.vtu").string()), 1);
  EXPECT_EQ(std::find(list.begin(), list.end(), (dir / "f0.vtu").string()), list.end()) << "the oldest falls off";
  // Relative paths are stored absolute, so the list works from any directory.
  const auto relative = app::with_opened({}, "data/x.vtu");
  EXPECT_TRUE(fs::path(relative.at(0)).is_absolute());
  setenv("XDG_CONFIG_HOME", (dir / "xdg").c_str(), 1);
  EXPECT_EQ(app::recent_files_path(), dir / "xdg" / "prismoid" / "recent.txt");
}

TEST(SceneMerge, ConcatenatesPointsAndCellsWithOffsetsAndKeepsValues) {
  const TetMesh a = make_box_mesh(glm::dvec3(0.0), glm::dvec3(1.0), 1, [](const glm::dvec3& p) { return 1.0 + p.x; });
  const TetMesh b = make_ball_mesh(glm::dvec3(5.0), 1.0, 0, 3.0);
  const TetMesh m = app::merge_meshes({&a, &b});
  ASSERT_EQ(m.points.size(), a.points.size() + b.points.size());
  ASSERT_EQ(m.tets.size(), a.tets.size() + b.tets.size());
  EXPECT_NO_THROW(validate(m));
  for (size_t c = 0; c < b.tets.size(); ++c)
    for (int k = 0; k < 4; ++k) {
      EXPECT_EQ(m.tets[a.tets.size() + c][k], b.tets[c][k] + a.points.size());
      EXPECT_EQ(m.points[m.tets[a.tets.size() + c][k]], b.points[b.tets[c][k]]);
    }
  for (size_t c = 0; c < a.tets.size(); ++c) EXPECT_EQ(m.cell_extinction[c], a.cell_extinction[c]);
  for (size_t c = 0; c < b.tets.size(); ++c) EXPECT_EQ(m.cell_extinction[a.tets.size() + c], 3.0);
  EXPECT_EQ(m.name, a.name + " + " + b.name);
}

// Per-point and per-cell fields together: the per-cell mesh's cells get their own points
// carrying the cell's value, so each field stays what it was in every cell.
TEST(SceneMerge, MixedPointAndCellFieldsKeepEachCellsValues) {
  TetMesh linear = make_default_volume();  // point scalars
  ASSERT_FALSE(linear.point_scalars.empty());
  linear.point_extinction.assign(linear.points.size(), 2.0);
  TetMesh constant = make_ball_mesh(glm::dvec3(4.0), 1.0, 1, 5.0);
  constant.cell_scalars.resize(constant.tets.size());
  for (size_t c = 0; c < constant.tets.size(); ++c) constant.cell_scalars[c] = double(c);
  const TetMesh m = app::merge_meshes({&linear, &constant});
  EXPECT_NO_THROW(validate(m));
  ASSERT_EQ(m.tets.size(), linear.tets.size() + constant.tets.size());
  ASSERT_EQ(m.points.size(), linear.points.size() + 4 * constant.tets.size());
  ASSERT_EQ(m.point_scalars.size(), m.points.size());
  ASSERT_EQ(m.point_extinction.size(), m.points.size());
  EXPECT_TRUE(m.cell_scalars.empty());
  for (size_t c = 0; c < constant.tets.size(); ++c) {
    const auto& t = m.tets[linear.tets.size() + c];
    for (int k = 0; k < 4; ++k) {
      EXPECT_EQ(m.points[t[k]], constant.points[constant.tets[c][k]]);
      EXPECT_EQ(m.point_scalars[t[k]], double(c));
      EXPECT_EQ(m.point_extinction[t[k]], 5.0);
    }
  }
  for (size_t p = 0; p < linear.points.size(); ++p) EXPECT_EQ(m.point_scalars[p], linear.point_scalars[p]);
  // Scalars in one mesh only: the union has none (colour needs every dataset's).
  const TetMesh plain = make_ball_mesh(glm::dvec3(0.0), 1.0, 0, 1.0);
  const TetMesh partial = app::merge_meshes({&linear, &plain});
  EXPECT_TRUE(partial.point_scalars.empty() && partial.cell_scalars.empty());
}

TEST(DatasetList, VisibleDatasetsAreDrawnAsOneAndTheModeFollows) {
  app::ViewState state;
  state.datasets.push_back(app::make_dataset(volume::make_field_mesh(volume::field_from_name("marschner-lobb"), 2, 1.0),
                                             volume::field_from_name("marschner-lobb")));
  app::rebuild_scene(state);
  ASSERT_TRUE(app::set_mode(state, "interval-march").empty());
  const size_t field_cells = state.drawn().mesh->tets.size();
  // A second dataset: both drawn, no field to march, so the mode falls back (with a note).
  const std::string note = app::add_dataset(state, app::make_dataset(make_ball_mesh(glm::dvec3(3.0), 1.0, 1, 1.0)));
  EXPECT_FALSE(note.empty());
  EXPECT_EQ(state.mode, "interval-sorted");
  EXPECT_EQ(state.active, 1u);
  EXPECT_EQ(state.drawn().mesh->tets.size(), field_cells + 80u);
  EXPECT_FALSE(state.drawn().field);
  // Hiding the ball draws the field alone again (the same mesh, shared), and it can march.
  EXPECT_TRUE(app::show_dataset(state, 1, false).empty());
  EXPECT_EQ(state.drawn().mesh, state.datasets[0].mesh);
  EXPECT_TRUE(app::set_mode(state, "interval-march").empty());
  EXPECT_FALSE(app::show_dataset(state, 0, false).empty()) << "the last visible dataset cannot be hidden";
  EXPECT_FALSE(app::show_dataset(state, 7, true).empty());
  // The active dataset gives the transfer function its range.
  EXPECT_TRUE(app::set_active(state, 0).empty());
  EXPECT_EQ(state.settings.resolve.transfer.range_lo, state.datasets[0].scalar_lo);
  EXPECT_EQ(state.settings.resolve.transfer.range_hi, state.datasets[0].scalar_hi);
}

}  // namespace
}  // namespace prismoid
