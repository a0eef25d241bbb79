// The isolated child (io/isolated_read.hpp): whatever the work in it does (crash, allocate
// without end, loop, throw), the caller gets an InputError naming the source, or Cancelled, and
// no child is left behind; results larger than a pipe's buffer arrive whole.
#include <gtest/gtest.h>

#include <algorithm>
#include <chrono>
#include <csignal>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <new>
#include <stdexcept>
#include <thread>
#include <vector>

#include <pthread.h>
#include <sys/mman.h>
#include <sys/wait.h>
#include <unistd.h>

#include "io/isolated_read.hpp"
#include "scene/input_error.hpp"

namespace prismoid {
namespace {

using Clock = std::chrono::steady_clock;

io::ChildJob job_named(const std::string& source, uint64_t memory = uint64_t(512) << 20, double seconds = 0.0) {
  io::ChildJob job;
  job.source = source;
  job.limits.memory_bytes = memory;
  job.limits.seconds = seconds;
  return job;
}

std::string input_error_of(const std::function<void()>& run) {
  try {
    run();
  } catch (const InputError& e) {
    return e.what();
  }
  return "(no InputError)";
}

// Whether this process has a child (reaped or not): the isolation must leave none.
bool has_children() {
  errno = 0;
  return ::waitpid(-1, nullptr, WNOHANG) != -1 || errno != ECHILD;
}

TEST(IsolatedRead, AResultLargerThanThePipeArrivesWholeWithTheChildsProgress) {
  std::vector<double> reported;
  const std::vector<uint32_t> result = io::run_isolated<std::vector<uint32_t>>(
      job_named("big"), [&](double f, const std::string&) { reported.push_back(f); return true; },
      [](const io::Progress& progress) {
        std::vector<uint32_t> v(3'000'000);  // 12 MB: the parent must read while the child writes
        for (size_t i = 0; i < v.size(); ++i) {
          v[i] = uint32_t(i * 2654435761u);
          if (i % 500'000 == 0) progress(double(i) / double(v.size()), "filling");
        }
        progress(1.0, "filling");
        return v;
      });
  ASSERT_EQ(result.size(), 3'000'000u);
  for (size_t i = 0; i < result.size(); i += 9973) ASSERT_EQ(result[i], uint32_t(i * 2654435761u)) << i;
  ASSERT_GE(reported.size(), 7u);
  EXPECT_EQ(reported.back(), 1.0);
  EXPECT_FALSE(has_children());
}

TEST(IsolatedRead, AStructArrivesFieldByField) {
  TetMesh mesh;
  mesh.name = "two tets";
  mesh.points = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {0, 0, 1}, {1, 1, 1}};
  mesh.tets = {{0, 1, 2, 3}, {1, 2, 3, 4}};
  mesh.cell_extinction = {0.5, 2.0};
  mesh.point_scalars = {1, 2, 3, 4, 5};
  const TetMesh back = io::run_isolated<TetMesh>(job_named("mesh"), {}, [&](const io::Progress&) { return mesh; });
  EXPECT_EQ(back.name, mesh.name);
  EXPECT_EQ(back.points, mesh.points);
  EXPECT_EQ(back.tets, mesh.tets);
  EXPECT_EQ(back.cell_extinction, mesh.cell_extinction);
  EXPECT_TRUE(back.point_extinction.empty());
  EXPECT_EQ(back.point_scalars, mesh.point_scalars);
}

TEST(IsolatedRead, ACrashIsAnInputErrorNamingTheSourceAndTheSignal) {
  const std::string text = input_error_of([] {
    io::run_isolated<int>(job_named("bad.ply"), {}, [](const io::Progress&) -> int {
      std::raise(SIGSEGV);
      return 0;
    });
  });
  EXPECT_EQ(text, "bad.ply: the reader crashed (SIGSEGV): the file is corrupt or truncated");
  const std::string aborted = input_error_of([] {
    io::run_isolated<int>(job_named("bad.vtu"), {}, [](const io::Progress&) -> int { std::abort(); });
  });
  EXPECT_NE(aborted.find("bad.vtu: the reader crashed (SIGABRT)"), std::string::npos) << aborted;
  EXPECT_FALSE(has_children());
}

TEST(IsolatedRead, ErrorsThrownInTheChildKeepTheirSourceAndText) {
  const std::string input = input_error_of([] {
    io::run_isolated<int>(job_named("file.vtu"), {}, [](const io::Progress&) -> int { throw InputError("--array", "has no array 'x'"); });
  });
  EXPECT_EQ(input, "--array: has no array 'x'");
  const std::string other = input_error_of([] {
    io::run_isolated<int>(job_named("file.vdb"), {}, [](const io::Progress&) -> int { throw std::runtime_error("IoError: bad header"); });
  });
  EXPECT_EQ(other, "file.vdb: the reader failed: IoError: bad header");
}

// The memory limit counts what the child adds, not the address space it inherits: a parent that
// has mapped far more than the budget (as one with a Vulkan device does) still reads, and a
// child asking for more than the budget is refused with the budget named.
TEST(IsolatedRead, TheMemoryLimitCountsWhatTheChildAddsNotWhatItInherits) {
  const size_t reserved = size_t(4) << 30;  // address space only: never touched
  void* inherited = ::mmap(nullptr, reserved, PROT_NONE, MAP_PRIVATE | MAP_ANONYMOUS | MAP_NORESERVE, -1, 0);
  ASSERT_NE(inherited, MAP_FAILED);
  const uint64_t budget = uint64_t(256) << 20;
  const size_t sum = io::run_isolated<size_t>(job_named("fits.vtu", budget), {}, [](const io::Progress&) {
    std::vector<char> used(size_t(100) << 20, 1);  // 100 MiB of the 256 MiB budget
    size_t s = 0;
    for (size_t i = 0; i < used.size(); i += 4096) s += size_t(used[i]);
    return s;
  });
  EXPECT_EQ(sum, (size_t(100) << 20) / 4096);
  const std::string text = input_error_of([&] {
    io::run_isolated<size_t>(job_named("huge.vtu", budget), {}, [](const io::Progress&) {
      std::vector<std::vector<char>> chunks;  // grows without end, as a reader believing a declared size does
      for (;;) chunks.emplace_back(size_t(16) << 20, 1);
      return chunks.size();
    });
  });
  EXPECT_EQ(text, "huge.vtu: the reader needs more than 256 MiB of memory (std::bad_alloc): the file is corrupt, or too large for this machine");
  ::munmap(inherited, reserved);
  EXPECT_FALSE(has_children());
}

TEST(IsolatedRead, AChildPastItsTimeLimitIsKilledAndNamed) {
  const auto start = Clock::now();
  const std::string text = input_error_of([] {
    io::run_isolated<int>(job_named("loop.obj", 0, 0.5), {}, [](const io::Progress&) -> int {
      for (;;) ::pause();  // a reader that never returns
    });
  });
  EXPECT_EQ(text, "loop.obj: the reader did not finish within 0.5 s (the limit for a file of this size): the file is corrupt or truncated");
  EXPECT_LT(std::chrono::duration<double>(Clock::now() - start).count(), 5.0);
  EXPECT_FALSE(has_children());
}

// A signal (Ctrl-C's SIGINT) interrupts the parent's wait; that is no data, and the caller's
// progress callback, which the signal's handler tells to stop, cancels: the child is killed at
// once. This is TetGen's case from issue 18, where the interrupted poll() was read as data ready.
volatile std::sig_atomic_t g_interrupted = 0;
void on_signal(int) { g_interrupted = 1; }

TEST(IsolatedRead, AnInterruptedWaitAsksTheCallerAndCancelKillsTheChild) {
  struct sigaction action {}, previous{};
  action.sa_handler = on_signal;  // no SA_RESTART: poll() and read() return EINTR
  ASSERT_EQ(::sigaction(SIGUSR1, &action, &previous), 0);
  g_interrupted = 0;
  const pthread_t waiting = ::pthread_self();  // the signal must interrupt this thread's wait
  std::thread interrupter([waiting] {
    std::this_thread::sleep_for(std::chrono::milliseconds(300));
    ::pthread_kill(waiting, SIGUSR1);
  });
  io::ChildJob job = job_named("slow.off");
  job.stage = "TetGen";
  job.waiting_fraction = -1.0;
  Clock::time_point interrupted_at{};
  bool cancelled = false;
  try {
    io::run_isolated<int>(job, [&](double, const std::string&) {
      if (g_interrupted && interrupted_at == Clock::time_point{}) interrupted_at = Clock::now();
      return !g_interrupted;
    }, [](const io::Progress&) -> int {
      for (;;) ::pause();
    });
  } catch (const io::Cancelled& e) {
    cancelled = true;
    EXPECT_EQ(std::string(e.what()), "slow.off: cancelled");
  }
  interrupter.join();
  ::sigaction(SIGUSR1, &previous, nullptr);
  EXPECT_TRUE(cancelled);
  ASSERT_NE(interrupted_at, Clock::time_point{});
  EXPECT_LT(std::chrono::duration<double>(Clock::now() - interrupted_at).count(), 1.0);
  EXPECT_FALSE(has_children());
}

TEST(IsolatedRead, ACallerThatStopsBeforeTheStartStartsNothing) {
  bool ran = false;
  EXPECT_THROW(io::run_isolated<int>(job_named("x.vtu"), [](double, const std::string&) { return false; },
                                     [&](const io::Progress&) { ran = true; return 1; }),
               io::Cancelled);
  EXPECT_FALSE(ran);
  EXPECT_FALSE(has_children());
}

TEST(IsolatedRead, ReadLimitsGrowWithTheFileAndItsPossibleCompression) {
  const std::filesystem::path dir = std::filesystem::temp_directory_path() / ("prismoid_limits_" + std::to_string(::getpid()));
  std::filesystem::create_directories(dir);
  const std::string text(size_t(4) << 20, 'x');  // 4 MiB
  std::ofstream(dir / "a.vtk") << text;
  std::ofstream(dir / "a.vtu") << text;
  std::ofstream(dir / "tiny.ply") << "ply";
  std::ofstream(dir / "a.inr") << text;
  std::ofstream(dir / "two.vtm") << "<VTKFile type=\"vtkMultiBlockDataSet\"><DataSet index=\"0\" file=\"a.vtk\"/></VTKFile>";
  const io::ChildLimits legacy = io::read_limits((dir / "a.vtk").string());
  EXPECT_NEAR(legacy.seconds, io::kReadBaseSeconds + 4.0 * io::kReadSecondsPerMiB, 1e-9);
  EXPECT_NEAR(io::read_limits((dir / "a.vtu").string()).seconds, io::kReadBaseSeconds + 4.0 * 1032.0 * io::kReadSecondsPerMiB, 1e-6);
  EXPECT_GT(io::read_limits((dir / "two.vtm").string()).seconds, io::kReadBaseSeconds + 4.0 * 1032.0 * io::kReadSecondsPerMiB)
      << "a .vtm's time counts the files it names";
  EXPECT_NEAR(io::read_limits((dir / "tiny.ply").string()).seconds, io::kReadBaseSeconds, 1e-3);
  EXPECT_EQ(legacy.memory_bytes, std::min(io::child_memory_budget(), io::kReadBaseMemory + io::kReadMemoryPerByte * (uint64_t(4) << 20)));
  EXPECT_EQ(io::read_limits((dir / "a.inr").string()).memory_bytes,
            std::min(io::child_memory_budget(), io::kReadBaseMemory + io::kReadMemoryPerVoxelByte * (uint64_t(4) << 20)));
  EXPECT_EQ(io::read_limits((dir / "a.vtu").string()).memory_bytes, io::child_memory_budget()) << "4 MiB compressed may be 4 GiB of data";
  EXPECT_GT(io::child_memory_budget(), uint64_t(0));
  std::filesystem::remove_all(dir);
}

}  // namespace
}  // namespace prismoid
