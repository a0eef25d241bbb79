#pragma once
// Running the prismoid executable from a test as a user would: one scratch folder per test
// process (removed when the suite ends), the exit code and both output streams. The test
// target defines PRISMOID_EXE as the executable's path.
#include <gtest/gtest.h>

#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <sys/wait.h>
#include <unistd.h>

namespace prismoid::test {

struct CliRun {
  int code = -1;
  std::string out, err;
};

// This process's scratch folder (created on first use).
inline std::filesystem::path cli_work_dir() {
  std::filesystem::path d = std::filesystem::temp_directory_path() / ("prismoid_cli_" + std::to_string(::getpid()));
  std::filesystem::create_directories(d);
  return d;
}

inline std::string slurp(const std::filesystem::path& p) {
  std::ifstream in(p);
  std::stringstream s;
  s << in.rdbuf();
  return s.str();
}

// `prismoid ARGS`, its streams captured in the scratch folder.
inline CliRun run_cli(const std::string& args) {
  const std::filesystem::path dir = cli_work_dir();
  const std::string cmd = std::string(PRISMOID_EXE) + " " + args + " >" + (dir / "out.txt").string() + " 2>" + (dir / "err.txt").string();
  CliRun r;
  const int status = std::system(cmd.c_str());
  r.code = WIFEXITED(status) ? WEXITSTATUS(status) : -1;
  r.out = slurp(dir / "out.txt");
  r.err = slurp(dir / "err.txt");
  return r;
}

// Removes the scratch folder when the suite ends; register once per test executable.
class CliScratchCleanup : public ::testing::Environment {
 public:
  void TearDown() override {
    std::error_code ignored;
    std::filesystem::remove_all(cli_work_dir(), ignored);
  }
};

// What a CLI test file uses (`using namespace prismoid::test::cli;`): the scratch folder, a
// run of the executable, and the scratch clean-up registered once per test executable.
namespace cli {
inline std::filesystem::path work_dir() { return cli_work_dir(); }
inline CliRun run(const std::string& args) { return run_cli(args); }
inline const ::testing::Environment* const kCleanup = ::testing::AddGlobalTestEnvironment(new CliScratchCleanup);
}  // namespace cli

}  // namespace prismoid::test
