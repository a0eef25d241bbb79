// Nothing a user owns is lost and nothing half-written is left behind: every file a command
// writes is declared and checked before the command's work and put in place whole, together
// with the command's other outputs (app/common/output_files.hpp). Each refused command is checked for
// its exit code and message and for leaving its folder exactly as it was, byte for byte.
#include <gtest/gtest.h>

#include <chrono>
#include <csignal>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <map>
#include <sstream>
#include <string>
#include <sys/resource.h>
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

// `prismoid ARGS` under a file size limit of 100 blocks (51 or 102 KB, by the shell's unit), with
// SIGXFSZ ignored: each write past it fails with EFBIG, as a full disk fails one with ENOSPC.
CliRun run_with_small_disk(const std::string& args) {
  const fs::path dir = work_dir();
  const std::string cmd = "trap '' XFSZ; ulimit -f 100; " + std::string(PRISMOID_EXE) + " " + args + " >" + (dir / "out.txt").string() +
                          " 2>" + (dir / "err.txt").string();
  const int status = std::system(cmd.c_str());
  return {WIFEXITED(status) ? WEXITSTATUS(status) : -1, test::slurp(dir / "out.txt"), test::slurp(dir / "err.txt")};
}

// A closed cube of side 2 as OFF: a surface for path-reference and TetGen.
void write_cube_off(const fs::path& off) {
  std::ofstream(off) << "OFF\n8 12 0\n0 0 0\n2 0 0\n2 2 0\n0 2 0\n0 0 2\n2 0 2\n2 2 2\n0 2 2\n"
                        "3 0 2 1\n3 0 3 2\n3 4 5 6\n3 4 6 7\n3 0 1 5\n3 0 5 4\n3 1 2 6\n3 1 6 5\n3 2 3 7\n3 2 7 6\n3 3 0 4\n3 3 4 7\n";
}

TEST(CliOutputs, AnOutputThatIsAnInputIsRefusedAndTheInputKeptByteForByte) {
  const fs::path d = fresh_dir("output-is-input");
  const std::string v = (d / "v.vtu").string(), vdb = (d / "v.vdb").string(), off = (d / "cube.off").string();
  ASSERT_EQ(run("convert ball:1 " + v).code, 0);
  ASSERT_EQ(run("convert ball:1 " + vdb + " --vdb levelset --voxel-size 0.25").code, 0);
  write_cube_off(off);
  fs::create_symlink("v.vtu", d / "link.json");  // a symlink to an input counts as the input
  fs::create_hard_link(v, d / "hard.vtu");        // so does a hard link
  std::ofstream(d / "t.json") << "[]";            // a --tf file (read before the render would refuse it)
  // A parallel .vtu whose piece is v.vtu: converting it into its own piece would destroy the piece.
  std::ofstream(d / "p.pvtu") << "<?xml version=\"1.0\"?>\n<VTKFile type=\"PUnstructuredGrid\" version=\"0.1\">\n"
                                 "  <PUnstructuredGrid GhostLevel=\"0\">\n    <PPoints><PDataArray type=\"Float64\" NumberOfComponents=\"3\"/></PPoints>\n"
                                 "    <Piece Source=\"v.vtu\"/>\n  </PUnstructuredGrid>\n</VTKFile>\n";
  const std::string o = " --size 8x8 --output " + (d / "o.png").string();
  expect_refused_leaving(d, "render " + v + o + " --stats " + v, v + ": --stats would write over a file this command reads");
  expect_refused_leaving(d, "render " + v + " --size 8x8 --stats " + (d / "o.pfm").string() + " --output " + (d / "o.pfm").string(),
                         "o.pfm: --stats and --output name the same file");
  expect_refused_leaving(d, "render " + v + o + " --stats " + (d / "link.json").string(), "link.json: --stats would write over '" + v + "'");
  expect_refused_leaving(d, "render " + v + o + " --quantity color --tf " + (d / "t.json").string() + " --stats " + (d / "t.json").string(),
                         "t.json: --stats would write over");
  const std::string path_ref = "render " + off + " --mode path-reference --size 4x4 --spp 1 --output " + (d / "o.pfm").string();
  expect_refused_leaving(d, path_ref + " --variance " + off, off + ": --variance would write over a file this command reads");
  expect_refused_leaving(d, path_ref + " --variance " + (d / "var.png").string(), "var.png: --variance writes .pfm files, not .png");
  expect_refused_leaving(d, "convert " + v + " " + v, v + ": convert would write over a file this command reads");
  expect_refused_leaving(d, "convert " + v + " " + (d / "hard.vtu").string(), "hard.vtu: convert would write over '" + v + "'");
  expect_refused_leaving(d, "convert " + vdb + " " + vdb, vdb + ": convert would write over a file this command reads");
  expect_refused_leaving(d, "convert " + (d / "p.pvtu").string() + " " + v, v + ": convert would write over");
  // OUT forgotten: `convert mine.vtu` alone would write the default dataset over the user's mesh.
  expect_refused_leaving(d, "convert " + v, v + ": exists, and convert with one file writes the embedded default dataset");
}

// A file its owner made read-only is refused, not replaced (root may write it, so the refusal
// reads the permission bits); its bytes and its mode stay.
TEST(CliOutputs, AReadOnlyOutputIsRefusedAndKept) {
  const fs::path d = fresh_dir("read-only");
  const std::string v = (d / "v.vtu").string(), stats = (d / "s.json").string();
  ASSERT_EQ(run("convert ball:1 " + v).code, 0);
  std::ofstream(stats) << "{\"mine\": 1}";
  fs::permissions(stats, fs::perms::owner_read | fs::perms::group_read | fs::perms::others_read);
  const std::string out = (d / "out.vtu").string();
  std::ofstream(out) << "the user's";
  fs::permissions(out, fs::perms::owner_read);
  expect_refused_leaving(d, "render " + v + " --size 8x8 --output " + (d / "o.png").string() + " --stats " + stats,
                         stats + ": is read-only: --stats does not replace it");
  expect_refused_leaving(d, "convert " + v + " " + out, out + ": is read-only: convert does not replace it");
  EXPECT_EQ(fs::status(stats).permissions() & fs::perms::all, fs::perms::owner_read | fs::perms::group_read | fs::perms::others_read);
  EXPECT_EQ(fs::status(out).permissions() & fs::perms::all, fs::perms::owner_read);
}

TEST(CliOutputs, AFolderInAnOutputsPlaceLeavesNoPartialFile) {
  const fs::path d = fresh_dir("folder-in-place");
  const std::string v = (d / "v.vtu").string();
  ASSERT_EQ(run("convert ball:1 " + v).code, 0);
  for (const char* name : {"img.png", "img.pfm", "out.vtu", "out.vdb", "stats.json"}) fs::create_directory(d / name);
  expect_refused_leaving(d, "render " + v + " --size 8x8 --output " + (d / "img.png").string(), "img.png: is a folder: --output needs a file name");
  expect_refused_leaving(d, "render " + v + " --size 8x8 --output " + (d / "img.pfm").string(), "img.pfm: is a folder");
  expect_refused_leaving(d, "render " + v + " --size 8x8 --output " + (d / "o.png").string() + " --stats " + (d / "stats.json").string(),
                         "stats.json: is a folder: --stats needs a file name");
  expect_refused_leaving(d, "convert " + v + " " + (d / "out.vtu").string(), "out.vtu: is a folder: convert needs a file name");
  expect_refused_leaving(d, "convert " + v + " " + (d / "out.vdb").string(), "out.vdb: is a folder: convert needs a file name");
}

// All outputs of a command are written, or none: a --stats or --variance that cannot be written
// is refused before the image is rendered, and a command that succeeds leaves exactly its files.
TEST(CliOutputs, EveryOutputOfACommandIsWrittenOrNone) {
  const fs::path d = fresh_dir("all-or-none");
  const std::string v = (d / "v.vtu").string(), off = (d / "cube.off").string();
  ASSERT_EQ(run("convert ball:1 " + v).code, 0);
  write_cube_off(off);
  const std::string missing = (d / "no-such-folder").string();
  expect_refused_leaving(d, "render " + v + " --size 8x8 --output " + (d / "o.png").string() + " --stats " + missing + "/s.json",
                         missing + "/s.json: the folder '" + missing + "' does not exist");
  expect_refused_leaving(d, "render " + off + " --mode path-reference --size 4x4 --spp 1 --output " + (d / "o.pfm").string() + " --variance " +
                                missing + "/v.pfm",
                         "v.pfm: the folder '" + missing + "' does not exist");
  std::ofstream(d / "o.png") << "an older image";  // replaced whole
  const auto before = snapshot(d);
  const CliRun r = run("render " + v + " --size 8x8 --output " + (d / "o.png").string() + " --stats " + (d / "s.json").string());
  ASSERT_EQ(r.code, 0) << r.err;
  auto after = snapshot(d);
  EXPECT_EQ(after.size(), before.size() + 1) << changes(before, after);  // s.json added, o.png replaced, nothing else
  EXPECT_EQ(after.at("o.png").substr(1, 3), "PNG");
  EXPECT_NE(after.at("s.json").find("\"validation_messages\""), std::string::npos);
}

// A folder that takes no new file is said to be so. /proc refuses new files even to root (with
// ENOENT); a folder without write permission does so for other users.
TEST(CliOutputs, AnUnwritableFolderIsSaidToBe) {
  const CliRun r = run("render --size 8x8 --output /proc/prismoid-test.png");
  EXPECT_EQ(r.code, 2);
  EXPECT_NE(r.err.find("/proc/prismoid-test.png: the folder '/proc' is not writable"), std::string::npos) << r.err;
  const CliRun vdb = run("convert ball:1 /proc/prismoid-test.vdb");
  EXPECT_EQ(vdb.code, 2);
  EXPECT_NE(vdb.err.find("/proc/prismoid-test.vdb: the folder '/proc' is not writable"), std::string::npos) << vdb.err;
  if (::geteuid() != 0) {  // root writes into a read-only folder regardless
    const fs::path d = fresh_dir("read-only");
    fs::permissions(d, fs::perms::owner_read | fs::perms::owner_exec);
    expect_refused_leaving(d, "render --size 8x8 --output " + (d / "x.png").string(), "x.png: the folder '" + d.string() + "' is not writable");
    fs::permissions(d, fs::perms::owner_all);
  }
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

// A bench that fails removes the folders it made for --out, and never what it did not make.
TEST(CliOutputs, AFailedBenchRemovesOnlyTheFoldersItCreated) {
  const fs::path d = fresh_dir("bench-out");
  const std::string bench = "bench " + (d / "missing.vtu").string() + " --quick --no-peers --no-plots --sweeps modes --out ";
  const CliRun r = run(bench + (d / "new" / "deeper").string());
  EXPECT_EQ(r.code, 2) << r.err;
  EXPECT_NE(r.err.find("missing.vtu: file does not exist"), std::string::npos) << r.err;
  EXPECT_FALSE(fs::exists(d / "new"));
  fs::create_directories(d / "mine");
  std::ofstream(d / "mine" / "keep.txt") << "the user's";
  expect_refused_leaving(d, bench + (d / "mine").string(), "missing.vtu: file does not exist");
  std::ofstream(d / "taken") << "a file where the folder would go";
  // An earlier run's results are not replaced unless asked to.
  fs::create_directories(d / "earlier");
  std::ofstream(d / "earlier" / "report.md") << "committed results";
  expect_refused_leaving(d, bench + (d / "earlier").string(), "report.md: exists: bench does not replace an earlier run's results");
  expect_refused_leaving(d, bench + (d / "taken").string(), "taken: is not a folder: --out names the folder to write into");
}

// A disk that fills up mid-write: every writer notices (VTK's, OpenVDB's and stb's own file
// writing did not, and left a truncated file with exit 0), the command fails naming the file and
// the reason, and the file it would have replaced keeps its bytes.
TEST(CliOutputs, AWriteThatFailsMidwayFailsTheCommandAndKeepsTheOldFile) {
  const fs::path d = fresh_dir("small-disk");
  for (const char* name : {"z.vtu", "z.vdb", "z.pfm", "z.json"}) std::ofstream(d / name) << "the user's";
  const std::string z = (d / "z").string();
  const std::vector<std::pair<std::string, std::string>> commands = {
      {"convert field:marschner-lobb:24 " + z + ".vtu", z + ".vtu: cannot be written: File too large"},
      {"convert ball:2 " + z + ".vdb", z + ".vdb: cannot be written: what reached the disk is incomplete"},
      // The CPU reference: lavapipe maps memory files, which the size limit would cut short.
      {"render --mode reference --size 300x300 --output " + z + ".pfm", z + ".pfm: cannot be written: File too large"},
  };
  for (const auto& [command, says] : commands) {
    const auto before = snapshot(d);
    const CliRun r = run_with_small_disk(command);
    EXPECT_EQ(r.code, 2) << command << "\n" << r.err;
    EXPECT_NE(r.err.find(says), std::string::npos) << command << "\nprinted: " << r.err;
    EXPECT_EQ(r.out.find("wrote"), std::string::npos) << command << "\nprinted: " << r.out;
    EXPECT_EQ(changes(before, snapshot(d)), "") << command;
  }
  // The same commands without the limit write their files: the limit, not the command, failed.
  EXPECT_EQ(run("convert ball:2 " + z + ".vdb").code, 0);
  EXPECT_GT(fs::file_size(z + ".vdb"), 100u * 1024u);
}

// Runs prismoid with `args` in the background, sends `sig` as soon as a temporary output file
// appears in `dir` (the command is then mid-run), and returns the wait status.
int signal_mid_run(const fs::path& dir, const std::vector<std::string>& args, int sig) {
  const pid_t pid = fork();
  if (pid == 0) {
    std::freopen("/dev/null", "w", stdout);
    std::freopen("/dev/null", "w", stderr);
    const struct rlimit no_core{0, 0};  // SIGQUIT's default dumps core
    setrlimit(RLIMIT_CORE, &no_core);
    std::vector<char*> argv{const_cast<char*>(PRISMOID_EXE)};
    for (const auto& a : args) argv.push_back(const_cast<char*>(a.c_str()));
    argv.push_back(nullptr);
    execv(PRISMOID_EXE, argv.data());
    _exit(127);
  }
  bool seen = false;
  const auto start = std::chrono::steady_clock::now();
  while (!seen && std::chrono::steady_clock::now() - start < std::chrono::seconds(60)) {
    for (const auto& e : fs::directory_iterator(dir)) seen = seen || e.path().filename().string().find("partial") != std::string::npos;
    if (!seen) std::this_thread::sleep_for(std::chrono::milliseconds(5));
  }
  EXPECT_TRUE(seen) << "no temporary output appeared while the command ran";
  kill(pid, sig);
  int status = 0;
  waitpid(pid, &status, 0);
  return status;
}

// Ctrl-C, SIGTERM, a closed terminal (SIGHUP) or Ctrl-\ (SIGQUIT) during a render or a convert
// leaves no partial or temporary file: the command's temporaries exist from its start, so the
// signal lands while they do.
TEST(CliOutputs, SignalsMidRunLeaveNoPartialFile) {
  for (const int sig : {SIGTERM, SIGINT, SIGHUP, SIGQUIT}) {
    for (const std::string verb : {"convert", "render"}) {
      const fs::path d = fresh_dir("signal-" + verb + "-" + std::to_string(sig));
      const std::vector<std::string> args =
          verb == "convert" ? std::vector<std::string>{"convert", "field:marschner-lobb:48", (d / "big.vtu").string()}
                            : std::vector<std::string>{"render", "field:marschner-lobb:8", "--mode", "reference", "--size", "200x200",
                                                       "--output", (d / "r.pfm").string(), "--stats", (d / "r.json").string()};
      const int status = signal_mid_run(d, args, sig);
      // Ended by the signal, or (Ctrl-C during a load with its progress bar) cancelled: 130.
      EXPECT_TRUE((WIFSIGNALED(status) && WTERMSIG(status) == sig) || (WIFEXITED(status) && WEXITSTATUS(status) == 130))
          << verb << " signal " << sig << ": status " << status;
      EXPECT_EQ(changes({}, snapshot(d)), "") << verb << " signal " << sig;
    }
  }
}

// The window's script commands that name a bad file or size are reported and the window goes
// on to its next commands; none writes over the dataset it opened.
TEST(CliOutputs, TheWindowReportsBadScriptCommandsAndGoesOn) {
  ASSERT_NE(std::getenv("DISPLAY"), nullptr) << "needs a display: run through scripts/test.sh (Xvfb)";
  const fs::path d = fresh_dir("window");
  const std::string v = (d / "v.vtu").string();
  ASSERT_EQ(run("convert field:blobs:3 " + v).code, 0);
  fs::create_directory(d / "folder.json");
  std::ofstream(d / "s.txt") << "frame 2\n"
                                "tf " << (d / "folder.json").string() << "\n"
                                "tf-export " << (d / "folder.json").string() << "\n"
                                "render 100000 100000 " << (d / "r.pfm").string() << "\n"
                                "resize 0 0\n"
                                "screenshot " << v << "\n"
                                "render 16 16 " << v << "\n"
                                "frame 6\n"
                                "screenshot " << (d / "shot.png").string() << "\n"
                                "frame 10\n"
                                "close\n";
  const auto before = snapshot(d);
  const CliRun r = run("view " + v + " --quantity color --array scalars --size 160x120 --script " + (d / "s.txt").string());
  EXPECT_EQ(r.code, 0) << r.err;
  for (const std::string& says : std::vector<std::string>{"s.txt:2: " + (d / "folder.json").string() + ": is a folder, not a ParaView colour-map file",
                                 "s.txt:3: " + (d / "folder.json").string() + ": is a folder: tf-export needs a file name",
                                 "s.txt:4: render: each side must be between 1 and 16384 pixels",
                                 "s.txt:5: resize: each side must be between 1 and 16384 pixels",
                                 "s.txt:6: " + v + ": screenshot would write over a file this command reads",
                                 "s.txt:7: " + v + ": render would write over a file this command reads"})
    EXPECT_NE(r.err.find(says), std::string::npos) << says << "\nprinted: " << r.err;
  const auto after = snapshot(d);
  EXPECT_EQ(changes(before, after), " added shot.png");  // the dataset untouched, no temporary left
}

}  // namespace
}  // namespace prismoid
