// Refused outputs and options: each refused command is checked for its exit code and message
// and for leaving its folder exactly as it was, byte for byte.
#include <gtest/gtest.h>

#include <chrono>
#include <csignal>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <map>
#include <sstream>
#include <string>
#include <sys/stat.h>
#include <sys/wait.h>
#include <thread>
#include <unistd.h>
#include <vector>

#include "support/cli_run.hpp"

namespace prismoid {
namespace {

namespace fs = std::filesystem;

using test::CliRun;
using test::cli::run;
using test::cli::work_dir;

fs::path fresh_dir(const std::string& name) {
  const fs::path dir = work_dir() / name;
  fs::remove_all(dir);
  fs::create_directories(dir);
  return dir;
}

std::string bytes_of(const fs::path& p) {
  std::ifstream in(p, std::ios::binary);
  std::stringstream s;
  s << in.rdbuf();
  return s.str();
}

// Everything under `dir`: each file's bytes, each folder and link by kind.
std::map<std::string, std::string> snapshot(const fs::path& dir) {
  std::map<std::string, std::string> entries;
  for (const auto& e : fs::recursive_directory_iterator(dir)) {
    const std::string name = fs::relative(e.path(), dir).string();
    if (e.is_symlink()) entries[name] = "link to " + fs::read_symlink(e.path()).string();
    else if (e.is_directory()) entries[name] = "folder";
    else entries[name] = bytes_of(e.path());
  }
  return entries;
}

// The names whose entries differ between two snapshots (added, removed or changed).
std::string changes(const std::map<std::string, std::string>& before, const std::map<std::string, std::string>& after) {
  std::string list;
  for (const auto& [name, content] : after)
    if (!before.count(name)) list += " added " + name;
    else if (before.at(name) != content) list += " changed " + name;
  for (const auto& [name, content] : before)
    if (!after.count(name)) list += " removed " + name;
  return list;
}

// The command is refused as bad input (exit code 2) with a message holding `says`, and `dir`
// is left exactly as it was: no output, no temporary, the inputs' bytes unchanged.
void expect_refused_leaving(const fs::path& dir, const std::string& command, const std::string& says) {
  const auto before = snapshot(dir);
  const CliRun r = run(command);
  EXPECT_EQ(r.code, 2) << command << "\n" << r.err;
  EXPECT_NE(r.err.find(says), std::string::npos) << command << "\nprinted: " << r.err;
  EXPECT_EQ(changes(before, snapshot(dir)), "") << command;
}

// A voxel size the grid cannot hold the inside at is refused before OpenVDB runs, saying why
// and what size would do; one too fine for the voxel budget says how many voxels it makes.
TEST(CliOutputs, ConvertRefusesAVoxelSizeTheGridCannotHoldUpFront) {
  const fs::path d = fresh_dir("voxel-size");
  const std::string x = (d / "x.vdb").string();
  expect_refused_leaving(d, "convert ball:1 " + x + " --voxel-size 1e30",
                         "ball:1: a voxel size of 1e+30 is over half the bounding box's thinnest side (2), too coarse for the grid "
                         "to hold the inside; use at most 1");
  expect_refused_leaving(d, "convert ball:1 " + x + " --voxel-size 1e-9",
                         "ball:1: a voxel size of 1e-09 makes about 8e+27 voxels in the bounding box, more than 1073741824; try a "
                         "voxel size of 0.00205");
  // The largest size allowed makes a grid that render takes.
  ASSERT_EQ(run("convert ball:1 " + x + " --voxel-size 1").code, 0);
  const CliRun r = run("render " + x + " --size 8x8 --output " + (d / "x.png").string());
  EXPECT_EQ(r.code, 0) << r.err;
}

TEST(CliOutputs, AFieldOfViewOutsideItsRangeIsSaidToBe) {
  const std::string says = "--fovy: '0' degrees: the vertical field of view must lie strictly between 0 and 180 degrees";
  const fs::path d = fresh_dir("fovy");
  expect_refused_leaving(d, "render --size 8x8 --fovy 0 --output " + (d / "o.png").string(), says);
  expect_refused_leaving(d, "render cornell-box --mode path-reference --size 4x4 --fovy 0 --output " + (d / "o.pfm").string(), says);
  expect_refused_leaving(d, "render --size 8x8 --fovy 180 --output " + (d / "o.png").string(), "--fovy: '180' degrees");
  expect_refused_leaving(d, "render --size 8x8 --fovy -5 --output " + (d / "o.png").string(), "--fovy: '-5' degrees");
}

}  // namespace
}  // namespace prismoid
