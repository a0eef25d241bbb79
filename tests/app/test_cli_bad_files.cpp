// End-to-end: files that are truncated, corrupt or hostile, and signals during a long load, as a
// user meets them on the command line (issue 18). Each is refused with exit code 2 and a line
// naming the file (or the option), promptly, and leaves no process and no output behind.
#include <gtest/gtest.h>

#include <chrono>
#include <cmath>
#include <csignal>
#include <cstdint>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <map>
#include <random>
#include <sstream>
#include <string>
#include <thread>
#include <vector>

#include <fcntl.h>
#include <sys/prctl.h>
#include <sys/wait.h>
#include <unistd.h>

#include "scene/generators.hpp"
#include "support/cli_run.hpp"
#include "support/bad_files.hpp"
#include "support/cube_surface.hpp"
#include "support/processes.hpp"

namespace prismoid {
namespace {

namespace fs = std::filesystem;
using Clock = std::chrono::steady_clock;

using test::ball_legacy_vtk;
using test::cube_ply;
using test::kShortArrayVtu;
using test::slurp;
using test::cli::work_dir;

struct CliResult {
  int code = -1;    // exit status; -1: killed by a signal (see `signal`), -2: past the deadline
  int signal = 0;
  double seconds = 0.0;
  std::string err;
};

// `prismoid ARGS` with stderr captured, killed when it runs past `deadline` seconds (a hang or an
// allocation without end must fail the test, not stall it).
CliResult run_for(const std::vector<std::string>& args, double deadline = 60.0) {
  const fs::path err = work_dir() / "stderr.txt";
  const auto start = Clock::now();
  const pid_t pid = ::fork();
  if (pid == 0) {
    ::setpgid(0, 0);  // a group of its own: past the deadline, any process it started goes too
    const int fd = ::open(err.c_str(), O_WRONLY | O_CREAT | O_TRUNC, 0644);
    ::dup2(fd, 2);
    const int null = ::open("/dev/null", O_WRONLY);
    ::dup2(null, 1);
    std::vector<char*> argv{const_cast<char*>(PRISMOID_EXE)};
    for (const auto& a : args) argv.push_back(const_cast<char*>(a.c_str()));
    argv.push_back(nullptr);
    ::execv(PRISMOID_EXE, argv.data());
    ::_exit(127);
  }
  CliResult r;
  int status = 0;
  while (::waitpid(pid, &status, WNOHANG) == 0) {
    if (Clock::now() - start > std::chrono::duration<double>(deadline)) {
      ::kill(-pid, SIGKILL);
      ::waitpid(pid, &status, 0);
      r.code = -2;
      break;
    }
    std::this_thread::sleep_for(std::chrono::milliseconds(20));
  }
  r.seconds = std::chrono::duration<double>(Clock::now() - start).count();
  if (r.code != -2) {
    r.code = WIFEXITED(status) ? WEXITSTATUS(status) : -1;
    r.signal = WIFSIGNALED(status) ? WTERMSIG(status) : 0;
  }
  r.err = slurp(err);
  return r;
}

std::string describe(const std::vector<std::string>& args, const CliResult& r) {
  std::string line = "prismoid";
  for (const auto& a : args) line += " " + a;
  return line + "\n  exit " + std::to_string(r.code) + (r.signal ? " (signal " + std::to_string(r.signal) + ")" : "") + " after " +
         std::to_string(r.seconds) + " s, stderr: " + r.err;
}

// Refused as bad input: exit code 2, one message naming `names` and saying `says`, within `deadline`.
void expect_refused(const std::vector<std::string>& args, const std::string& names, const std::string& says, double deadline = 60.0) {
  const CliResult r = run_for(args, deadline);
  EXPECT_EQ(r.code, 2) << describe(args, r);
  EXPECT_NE(r.err.find("prismoid: " + names + ": "), std::string::npos) << describe(args, r);
  EXPECT_NE(r.err.find(says), std::string::npos) << describe(args, r);
}

void write_bytes(const fs::path& path, const std::string& bytes) {
  std::ofstream out(path, std::ios::binary);
  out << bytes;
}

std::string replaced(std::string text, const std::string& from, const std::string& to) {
  const auto at = text.find(from);
  EXPECT_NE(at, std::string::npos) << from;
  if (at != std::string::npos) text.replace(at, from.size(), to);
  return text;
}

// Item 4: VTK's PLY reader crashed (SIGSEGV, a double free) on truncated files in every verb.
TEST(CliBadFiles, TruncatedPlyIsRefusedInEveryVerb) {
  const std::string ply = cube_ply();
  const fs::path whole = work_dir() / "cube.ply", short7 = work_dir() / "short7.ply", half = work_dir() / "half.ply";
  write_bytes(whole, ply);
  write_bytes(short7, ply.substr(0, ply.size() - 7));
  write_bytes(half, ply.substr(0, ply.size() / 2));
  const fs::path out = work_dir() / "out.vtu";
  EXPECT_EQ(run_for({"info", whole.string()}).code, 0);
  for (const fs::path& bad : {short7, half}) {
    expect_refused({"info", bad.string()}, bad.string(), "");
    expect_refused({"render", bad.string(), "--size", "8x8", "--output", (work_dir() / "o.png").string()}, bad.string(), "");
    expect_refused({"convert", bad.string(), out.string()}, bad.string(), "");
    EXPECT_FALSE(fs::exists(out));
  }
  EXPECT_NE(run_for({"info", short7.string()}).err.find("the reader crashed (SIGSEGV): the file is corrupt or truncated"), std::string::npos)
      << "the crash is named";
}

// Item 4: byte-mutated PLY files (seeded): each reads or is refused, never a crash.
TEST(CliBadFiles, ByteMutatedPlyNeverCrashes) {
  const std::string ply = cube_ply();
  const size_t header = ply.find("end_header\n") + 11;
  std::mt19937 random(18);
  for (int variant = 0; variant < 15; ++variant) {
    std::string bytes = ply;
    for (int flip = 0; flip < 3; ++flip) bytes[header + random() % (bytes.size() - header)] = char(random() & 0xff);
    const fs::path path = work_dir() / ("mutated" + std::to_string(variant) + ".ply");
    write_bytes(path, bytes);
    const CliResult r = run_for({"info", path.string()});
    EXPECT_TRUE(r.code == 0 || r.code == 2) << describe({"info", path.string()}, r);
    if (r.code == 2) {
      EXPECT_NE(r.err.find(path.string()), std::string::npos) << r.err;
    }
  }
}

// Item 5: an ASCII .vtu whose data array is shorter than the cell count crashed VTK's XML reader.
TEST(CliBadFiles, AVtuWithAShortDataArrayIsRefused) {
  const fs::path vtu = work_dir() / "short-array.vtu";
  write_bytes(vtu, kShortArrayVtu);
  expect_refused({"info", vtu.string()}, vtu.string(), "");
  expect_refused({"render", vtu.string(), "--array", "extinction", "--size", "8x8", "--output", (work_dir() / "o.png").string()},
                 vtu.string(), "");
  expect_refused({"convert", vtu.string(), (work_dir() / "o.vtu").string()}, vtu.string(), "");
}

// Item 6: sizes a header declares are checked against the file before anything is allocated:
// refused at once, naming the count, where a PLY reader grew without end, the .vtu reader ended
// in a bare std::bad_alloc (exit 1) and the legacy reader took minutes.
TEST(CliBadFiles, DeclaredSizesBeyondTheFileAreRefusedAtOnce) {
  const fs::path ply = work_dir() / "huge.ply", vtu = work_dir() / "huge.vtu", vtk = work_dir() / "huge.vtk";
  write_bytes(ply, replaced(cube_ply(), "element vertex 8", "element vertex 2000000000"));
  write_bytes(vtu, replaced(kShortArrayVtu, "NumberOfPoints=\"5\"", "NumberOfPoints=\"2000000000\""));
  const std::string legacy = ball_legacy_vtk();
  write_bytes(vtk, replaced(legacy, legacy.substr(legacy.find("POINTS "), legacy.find(" double") - legacy.find("POINTS ")), "POINTS 2000000000"));
  for (const fs::path& file : {ply, vtu, vtk}) {
    const std::vector<std::string> args{"info", file.string()};
    const CliResult r = run_for(args, 30.0);
    EXPECT_EQ(r.code, 2) << describe(args, r);
    EXPECT_NE(r.err.find(file.string() + ": declares 2000000000"), std::string::npos) << describe(args, r);
    EXPECT_NE(r.err.find("the file is truncated or corrupt"), std::string::npos) << r.err;
    EXPECT_LT(r.seconds, 10.0) << describe(args, r);
  }
}

// Item 7: a volume bound that asks TetGen for more cells than the guard allows is refused before
// TetGen runs (it grew without end); so is a cell target beyond it, and a negative bound names
// its own option.
TEST(CliBadFiles, TetGenBoundsBeyondTheCellGuardAreRefusedBeforeItRuns) {
  const fs::path cube = work_dir() / "cube.off", out = work_dir() / "tetgen.vtu";
  test::write_cube_off(cube);
  ::setenv("XDG_CACHE_HOME", (work_dir() / "cache").c_str(), 1);
  expect_refused({"convert", cube.string(), out.string(), "--tetgen-max-volume", "1e-12"}, "--tetgen-max-volume",
                 "asks for at least 1000000000000 tetrahedra", 20.0);
  expect_refused({"convert", cube.string(), out.string(), "--tetgen-cells", "60000000"}, "--tetgen-cells", "more than the 50000000", 20.0);
  expect_refused({"convert", cube.string(), out.string(), "--tetgen-max-volume", "-1"}, "--tetgen-max-volume", "not negative");
  EXPECT_FALSE(fs::exists(out));
}

// The flags prismoid gives the processes it starts to read files, typed by hand (with nothing or a
// file where the socket to their parent would be): a clear refusal, exit 2, nothing read or hung.
TEST(CliBadFiles, TheReadersInternalFlagsTypedByHandAreRefused) {
  for (const std::string flags : {"--prismoid-reader-host", "--prismoid-isolated-child read-tet-mesh 0"}) {
    for (const std::string fd3 : {"3<&-", "3</dev/null"}) {
      const test::CliRun r = test::run_cli(flags + " " + fd3);
      EXPECT_EQ(r.code, 2) << flags << " " << fd3;
      EXPECT_NE(r.err.find(flags.substr(0, flags.find(' ')) + " is for the processes a running Prismoid starts to read files, not for use by hand"),
                std::string::npos)
          << r.err;
    }
  }
}

// The readers `prismoid` (pid) runs now: the children of its reader host (io/isolated_read.hpp).
std::vector<pid_t> readers_of(pid_t pid) {
  const std::map<pid_t, test::ProcessStat> table = test::process_table();
  std::vector<pid_t> readers;
  for (const pid_t host : test::children_in(table, pid))
    for (const pid_t reader : test::children_in(table, host)) readers.push_back(reader);
  return readers;
}

// Starts `convert cube.off OUT --tetgen-max-volume 5e-7` (tens of seconds of TetGen) and waits
// until TetGen's process runs (the reader after the surface's); returns prismoid's pid and TetGen's.
std::pair<pid_t, pid_t> start_tetgen(const fs::path& out) {
  const fs::path cube = work_dir() / "signal-cube.off";
  test::write_cube_off(cube);
  ::setenv("XDG_CACHE_HOME", (work_dir() / ("cache-" + out.stem().string())).c_str(), 1);  // no cached result
  const pid_t pid = ::fork();
  if (pid == 0) {
    const int null = ::open("/dev/null", O_WRONLY);
    ::dup2(null, 1);
    ::dup2(null, 2);
    ::signal(SIGINT, SIG_DFL);
    ::execl(PRISMOID_EXE, PRISMOID_EXE, "convert", cube.c_str(), out.c_str(), "--tetgen-max-volume", "5e-7", static_cast<char*>(nullptr));
    ::_exit(127);
  }
  const auto start = Clock::now();
  while (Clock::now() - start < std::chrono::seconds(30)) {
    if (!readers_of(pid).empty()) {
      std::this_thread::sleep_for(std::chrono::milliseconds(500));  // past the surface's read, well inside TetGen
      if (const std::vector<pid_t> readers = readers_of(pid); !readers.empty()) return {pid, readers.front()};
    }
    std::this_thread::sleep_for(std::chrono::milliseconds(20));
  }
  return {pid, 0};
}

// Whether `pid` ends within `seconds`: reaped here (this process is the subreaper that orphans
// come to) or gone already.
bool ends_within(pid_t pid, double seconds) {
  const auto start = Clock::now();
  while (Clock::now() - start < std::chrono::duration<double>(seconds)) {
    if (::waitpid(pid, nullptr, WNOHANG) == pid || !fs::exists("/proc/" + std::to_string(pid))) return true;
    std::this_thread::sleep_for(std::chrono::milliseconds(20));
  }
  return false;
}

// Item 8: Ctrl-C (SIGINT) cancels TetGen at once: exit 130, no TetGen process left, no output.
// (The interrupted poll() was taken for data, and the parent then blocked in read().)
TEST(CliBadFiles, CtrlCCancelsTetGenAndLeavesNoProcessOrFile) {
  ASSERT_EQ(::prctl(PR_SET_CHILD_SUBREAPER, 1), 0);
  const fs::path out = work_dir() / "sigint.vtu";
  const auto [pid, tetgen] = start_tetgen(out);
  ASSERT_GT(tetgen, 0) << "TetGen's child process never started";
  ASSERT_EQ(::kill(pid, SIGINT), 0);
  const auto sent = Clock::now();
  int status = 0;
  while (::waitpid(pid, &status, WNOHANG) == 0 && Clock::now() - sent < std::chrono::seconds(10))
    std::this_thread::sleep_for(std::chrono::milliseconds(10));
  const double seconds = std::chrono::duration<double>(Clock::now() - sent).count();
  if (seconds >= 10.0) {
    ::kill(pid, SIGKILL);
    ::kill(tetgen, SIGKILL);
    ::waitpid(pid, &status, 0);
    ::waitpid(tetgen, nullptr, 0);
    FAIL() << "prismoid convert did not end within 10 s of SIGINT";
  }
  ASSERT_TRUE(WIFEXITED(status)) << "killed by signal " << WTERMSIG(status);
  EXPECT_EQ(WEXITSTATUS(status), 130);
  EXPECT_LT(seconds, 2.0);
  EXPECT_TRUE(ends_within(tetgen, 1.0)) << "TetGen's process " << tetgen << " outlived the cancel";
  EXPECT_FALSE(fs::exists(out));
  if (!ends_within(tetgen, 0.0)) ::kill(tetgen, SIGKILL);
}

// Item 8: SIGTERM ends prismoid (default action) and its TetGen child with it, which kept
// running as an orphan and allocating.
TEST(CliBadFiles, SigtermTakesTheTetGenChildWithIt) {
  ASSERT_EQ(::prctl(PR_SET_CHILD_SUBREAPER, 1), 0);
  const fs::path out = work_dir() / "sigterm.vtu";
  const auto [pid, tetgen] = start_tetgen(out);
  ASSERT_GT(tetgen, 0) << "TetGen's child process never started";
  ASSERT_EQ(::kill(pid, SIGTERM), 0);
  int status = 0;
  ::waitpid(pid, &status, 0);
  EXPECT_TRUE(WIFSIGNALED(status) && WTERMSIG(status) == SIGTERM);
  const bool ended = ends_within(tetgen, 2.0);
  if (!ended) {
    ::kill(tetgen, SIGKILL);
    ::waitpid(tetgen, nullptr, 0);
  }
  EXPECT_TRUE(ended) << "TetGen's process " << tetgen << " kept running after its parent ended";
  EXPECT_FALSE(fs::exists(out));
}

// Item 10: a legacy .vtk cut short was read with the missing values as 0 (extinction [0, 1]);
// VTK said so only through its output window, and now that fails the read.
TEST(CliBadFiles, ATruncatedLegacyVtkIsRefusedWithVtksReason) {
  const std::string legacy = ball_legacy_vtk();
  const fs::path whole = work_dir() / "ball.vtk", cut = work_dir() / "cut.vtk";
  write_bytes(whole, legacy);
  write_bytes(cut, legacy.substr(0, legacy.size() - 300));
  const CliResult ok = run_for({"info", whole.string()});
  ASSERT_EQ(ok.code, 0) << ok.err;
  expect_refused({"info", cut.string()}, cut.string(), "Error reading ascii data");
  expect_refused({"render", cut.string(), "--array", "extinction", "--size", "8x8", "--output", (work_dir() / "o.png").string()},
                 cut.string(), "Error reading ascii data");
}

// The "Messages" that are reading problems: exit 2, naming the file or option.
TEST(CliBadFiles, ReadingProblemsNameTheFileOrOption) {
  const fs::path a = work_dir() / "loop-a.vtu", b = work_dir() / "loop-b.vtu";
  fs::remove(a);
  fs::remove(b);
  fs::create_symlink(b.filename(), a);
  fs::create_symlink(a.filename(), b);
  expect_refused({"info", a.string()}, a.string(), "is a loop of symbolic links");
  expect_refused({"render", a.string(), "--size", "8x8", "--output", (work_dir() / "o.png").string()}, a.string(), "is a loop of symbolic links");

  const fs::path folder = work_dir() / "colors.json";
  fs::create_directories(folder);
  const std::string png = (work_dir() / "tf.png").string();
  expect_refused({"render", "--tf", folder.string(), "--quantity", "color", "--size", "8x8", "--output", png}, folder.string(), "is not a regular file (it is a folder)");

  // A transfer function of more points than any colour map has is refused at once (2 million
  // points ran for minutes).
  const fs::path many = work_dir() / "many.json";
  {
    std::ofstream out(many);
    out << "[{\"Name\": \"many\", \"RGBPoints\": [";
    for (int i = 0; i < 200000; ++i) out << (i ? ", " : "") << i << ", 0.5, 0.5, 0.5";
    out << "]}]";
  }
  expect_refused({"render", "--tf", many.string(), "--quantity", "color", "--size", "8x8", "--output", png}, many.string(),
                 "\"RGBPoints\" holds 200000 points; at most 4096", 30.0);

  expect_refused({"info", "field:no-such"}, "field:no-such", "unknown analytic field (available: ");
  expect_refused({"info", "field:sphere"}, "field:sphere", "is an analytic field, not a file");

  const fs::path vtk = work_dir() / "scalar.vtk";
  write_bytes(vtk, ball_legacy_vtk());
  expect_refused({"render", vtk.string(), "--array", "extinction", "--component", "7", "--size", "8x8", "--output", png}, vtk.string(),
                 "array 'extinction' has 1 component (it is a scalar); --component 7 does not exist");
}

// --depth-limit: a file of another size than the frame, of three channels, with a depth that is
// not positive (or NaN), or truncated, is refused naming it. (What the limit does:
// EmissionAbsorptionTest.RaysEndAtTheDepthLimitAsInTheReference.)
TEST(CliBadFiles, DepthLimitFilesAreCheckedBeforeAnyFrame) {
  const fs::path dir = work_dir();
  auto pfm = [&](const std::string& name, uint32_t w, uint32_t h, const char* kind, const std::vector<float>& values) {
    const fs::path path = dir / name;
    std::ofstream out(path, std::ios::binary);
    out << kind << "\n" << w << " " << h << "\n-1.0\n";
    out.write(reinterpret_cast<const char*>(values.data()), std::streamsize(values.size() * sizeof(float)));
    return path.string();
  };
  const std::string good = pfm("limit.pfm", 8, 8, "Pf", std::vector<float>(64, 5.0f));
  const std::string wide = pfm("wide.pfm", 9, 8, "Pf", std::vector<float>(72, 5.0f));
  const std::string rgb = pfm("rgb.pfm", 8, 8, "PF", std::vector<float>(192, 5.0f));
  std::vector<float> zero(64, 5.0f);
  zero[17] = 0.0f;
  const std::string nonpositive = pfm("zero.pfm", 8, 8, "Pf", zero);
  std::vector<float> nan(64, 5.0f);
  nan[3] = std::nanf("");
  const std::string not_a_number = pfm("nan.pfm", 8, 8, "Pf", nan);
  const std::string truncated = pfm("short.pfm", 8, 8, "Pf", std::vector<float>(10, 5.0f));
  const std::string out = (dir / "o.png").string();
  auto render = [&](const std::string& limit, const std::string& backend) {
    return std::vector<std::string>{"render", "--size", "8x8", "--quantity", "color", "--volume-backend", backend, "--depth-limit", limit, "--output", out};
  };
  expect_refused(render(wide, "compute"), wide, "is 9x8; the frame (--size) is 8x8");
  expect_refused(render(rgb, "compute"), rgb, "one value per pixel");
  expect_refused(render(nonpositive, "compute"), nonpositive, "not positive");
  expect_refused(render(not_a_number, "compute"), not_a_number, "not positive");
  expect_refused(render(truncated, "compute"), truncated, "");
  // The good file draws, on both backends.
  for (const char* backend : {"mesh", "compute"}) {
    const CliResult r = run_for(render(good, backend), 120.0);
    EXPECT_EQ(r.code, 0) << describe(render(good, backend), r);
  }
}

}  // namespace
}  // namespace prismoid
