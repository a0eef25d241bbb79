// Files that crashed VTK's readers, opened from the window (issue 18, item 9): the window shows
// the error naming the file and keeps running, and the next file opens. Before the readers ran in
// a child process, the PLY file took the window down.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>

#include "app/viewer/viewer.hpp"
#include "app/viewer/viewer_script.hpp"
#include "scene/generators.hpp"
#include "support/bad_files.hpp"

namespace prismoid {
namespace {

namespace fs = std::filesystem;

TEST(ViewerBadFiles, FilesThatCrashAReaderGiveTheErrorAndTheWindowKeepsRunning) {
  ASSERT_TRUE(app::display_available()) << "this test needs a display: run it through scripts/test.sh, which starts Xvfb";
  const fs::path dir = fs::temp_directory_path() / "prismoid-viewer-bad-files";
  fs::remove_all(dir);
  fs::create_directories(dir);
  const std::string ply = test::cube_ply();
  const fs::path truncated = dir / "truncated.ply", short_array = dir / "short-array.vtu", huge = dir / "huge.ply";
  std::ofstream(truncated, std::ios::binary) << ply.substr(0, ply.size() - 7);
  std::ofstream(short_array) << test::kShortArrayVtu;
  std::string declared = ply;
  declared.replace(declared.find("element vertex 8"), 16, "element vertex 2000000000");
  std::ofstream(huge, std::ios::binary) << declared;

  std::ostringstream script;
  script << "frame 1\nopen " << truncated.string() << "\nwait-load\nopen " << short_array.string() << "\nwait-load\n"
         << "drop " << huge.string() << "\nwait-load\ndrop ball:1\nwait-load\nframe 3\nclose\n";
  app::ViewerOptions options;
  options.width = 200;
  options.height = 150;
  options.validation = true;
  options.print_timings = false;
  options.script = app::parse_script(script.str(), "test script");
  options.max_frames = 2000;
  const app::ViewerReport report = app::run_viewer(make_default_volume(), options);

  EXPECT_EQ(report.validation_messages, 0u);
  ASSERT_EQ(report.loads.size(), 4u);
  // Whether VTK's readers crash on the first two or notice the problem depends on their heap; the
  // window shows what came back either way.
  const struct {
    fs::path file;
    const char* says;
  } refused[] = {{truncated, ""}, {short_array, ""}, {huge, "declares 2000000000"}};
  for (size_t i = 0; i < 3; ++i) {
    const app::LoadRecord& load = report.loads[i];
    EXPECT_FALSE(load.loaded) << refused[i].file;
    EXPECT_EQ(load.error.rfind(refused[i].file.string() + ": ", 0), 0u) << load.error;
    EXPECT_NE(load.error.find(refused[i].says), std::string::npos) << load.error;
  }
  EXPECT_EQ(report.last_load_error, report.loads[2].error);
  EXPECT_TRUE(report.loads[3].loaded) << report.loads[3].error;
  EXPECT_EQ(report.datasets, 2u);
  EXPECT_GE(report.frames_presented, 3u);
  fs::remove_all(dir);
}

}  // namespace
}  // namespace prismoid
