// The isolated child (io/isolated_read.hpp): whatever the work in it does (crash, allocate
// without end, loop, throw), the caller gets an InputError naming the source, or Cancelled, and
// no reader is left behind; requests and results larger than the socket's buffer arrive whole; and
// readers start from a fresh, single-threaded host, so a caller busy with parallel loops cannot
// leave one deadlocked.
#include <gtest/gtest.h>

#include <algorithm>
#include <atomic>
#include <chrono>
#include <csignal>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <map>
#include <new>
#include <random>
#include <stdexcept>
#include <string>
#include <thread>
#include <vector>

#include <pthread.h>
#include <sys/mman.h>
#include <unistd.h>

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include "io/isolated_read.hpp"
#include "scene/input_error.hpp"
#include "support/processes.hpp"

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

// Whether a reader is still running (or unreaped): the isolation must leave none.
bool readers_left() { return !test::running_readers().empty(); }

// ---- the works these tests run in children (in the table before main(), as the readers' are) ----

uint32_t filled(size_t i) { return uint32_t(i * 2654435761u); }

// n words, reporting progress while filling.
const io::ChildWork<uint64_t, std::vector<uint32_t>> kFill("test-fill", [](const uint64_t& n, const io::Progress& progress) {
  std::vector<uint32_t> v(n);
  for (size_t i = 0; i < v.size(); ++i) {
    v[i] = filled(i);
    if (i % 500'000 == 0) progress(double(i) / double(v.size()), "filling");
  }
  progress(1.0, "filling");
  return v;
});

// The sum of what was sent: the request arrived whole.
const io::ChildWork<std::vector<uint32_t>, uint64_t> kSum("test-sum", [](const std::vector<uint32_t>& v, const io::Progress&) {
  uint64_t sum = 0;
  for (const uint32_t x : v) sum += x;
  return sum;
});

const io::ChildWork<TetMesh, TetMesh> kEcho("test-echo-mesh", [](const TetMesh& mesh, const io::Progress&) { return mesh; });

const io::ChildWork<int, int> kRaise("test-raise", [](const int& sig, const io::Progress&) -> int {
  if (sig == SIGABRT) std::abort();
  std::raise(sig);
  return 0;
});

const io::ChildWork<int, int> kThrow("test-throw", [](const int& kind, const io::Progress&) -> int {
  if (kind == 0) throw InputError("--array", "has no array 'x'");
  throw std::runtime_error("IoError: bad header");
});

// Touches `mib` MiB; 0: grows without end, as a reader believing a declared size does.
const io::ChildWork<uint64_t, size_t> kAllocate("test-allocate", [](const uint64_t& mib, const io::Progress&) {
  if (mib == 0) {
    std::vector<std::vector<char>> chunks;
    for (;;) chunks.emplace_back(size_t(16) << 20, 1);
  }
  std::vector<char> used(size_t(mib) << 20, 1);
  size_t s = 0;
  for (size_t i = 0; i < used.size(); i += 4096) s += size_t(used[i]);
  return s;
});

const io::ChildWork<int, int> kNeverReturn("test-never-return", [](const int&, const io::Progress&) -> int {
  for (;;) ::pause();  // a reader that never returns
});

// A parallel loop on TBB, as VTK's filters (vtkSMPTools, on TBB in Debian's VTK) and OpenVDB run them.
uint64_t parallel_sum(uint64_t n) {
  std::vector<uint64_t> partial(64, 0);
  tbb::parallel_for(tbb::blocked_range<uint64_t>(0, n, 1024), [&](const tbb::blocked_range<uint64_t>& range) {
    uint64_t s = 0;
    for (uint64_t i = range.begin(); i < range.end(); ++i) s += i;
    std::atomic_ref<uint64_t>(partial[size_t(range.begin() / 1024) % partial.size()]).fetch_add(s);
  });
  uint64_t total = 0;
  for (const uint64_t s : partial) total += s;
  return total;
}
const io::ChildWork<uint64_t, uint64_t> kParallelSum("test-parallel-sum", [](const uint64_t& n, const io::Progress&) { return parallel_sum(n); });

// The second word of this process's command line: how it was started.
const io::ChildWork<int, std::string> kStartedAs("test-started-as", [](const int&, const io::Progress&) {
  std::ifstream command("/proc/self/cmdline");
  std::string argv0, argv1;
  std::getline(command, argv0, '\0');
  std::getline(command, argv1, '\0');
  return argv1;
});

// ---- the tests --------------------------------------------------------------------------------------

TEST(IsolatedRead, AResultLargerThanTheSocketArrivesWholeWithTheChildsProgress) {
  std::vector<double> reported;
  const std::vector<uint32_t> result =
      kFill(job_named("big"), [&](double f, const std::string&) { reported.push_back(f); return true; }, 3'000'000);  // 12 MB
  ASSERT_EQ(result.size(), 3'000'000u);
  for (size_t i = 0; i < result.size(); i += 9973) ASSERT_EQ(result[i], filled(i)) << i;
  ASSERT_GE(reported.size(), 7u);
  EXPECT_EQ(reported.back(), 1.0);
  EXPECT_FALSE(readers_left());
}

TEST(IsolatedRead, ARequestLargerThanTheSocketArrivesWhole) {
  std::vector<uint32_t> words(3'000'000);  // 12 MB: the child must read while the parent writes
  uint64_t expected = 0;
  for (size_t i = 0; i < words.size(); ++i) expected += (words[i] = filled(i));
  EXPECT_EQ(kSum(job_named("request"), {}, words), expected);
  EXPECT_FALSE(readers_left());
}

TEST(IsolatedRead, AStructArrivesFieldByField) {
  TetMesh mesh;
  mesh.name = "two tets";
  mesh.points = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {0, 0, 1}, {1, 1, 1}};
  mesh.tets = {{0, 1, 2, 3}, {1, 2, 3, 4}};
  mesh.cell_extinction = {0.5, 2.0};
  mesh.point_scalars = {1, 2, 3, 4, 5};
  const TetMesh back = kEcho(job_named("mesh"), {}, mesh);
  EXPECT_EQ(back.name, mesh.name);
  EXPECT_EQ(back.points, mesh.points);
  EXPECT_EQ(back.tets, mesh.tets);
  EXPECT_EQ(back.cell_extinction, mesh.cell_extinction);
  EXPECT_TRUE(back.point_extinction.empty());
  EXPECT_EQ(back.point_scalars, mesh.point_scalars);
}

TEST(IsolatedRead, ACrashIsAnInputErrorNamingTheSourceAndTheSignal) {
  const std::string text = input_error_of([] { kRaise(job_named("bad.ply"), {}, SIGSEGV); });
  EXPECT_EQ(text, "bad.ply: the reader crashed (SIGSEGV): the file is corrupt or truncated");
  const std::string aborted = input_error_of([] { kRaise(job_named("bad.vtu"), {}, SIGABRT); });
  EXPECT_NE(aborted.find("bad.vtu: the reader crashed (SIGABRT)"), std::string::npos) << aborted;
  EXPECT_FALSE(readers_left());
}

TEST(IsolatedRead, ErrorsThrownInTheChildKeepTheirSourceAndText) {
  EXPECT_EQ(input_error_of([] { kThrow(job_named("file.vtu"), {}, 0); }), "--array: has no array 'x'");
  EXPECT_EQ(input_error_of([] { kThrow(job_named("file.vdb"), {}, 1); }), "file.vdb: the reader failed: IoError: bad header");
}

// The memory limit counts what the child adds to the program it starts as: a parent that has
// mapped far more than the budget (as one with a Vulkan device does) still reads, and a child
// asking for more than the budget is refused with the budget named.
TEST(IsolatedRead, TheMemoryLimitCountsWhatTheChildAddsNotWhatTheParentHolds) {
  const size_t reserved = size_t(4) << 30;  // address space only: never touched
  void* held = ::mmap(nullptr, reserved, PROT_NONE, MAP_PRIVATE | MAP_ANONYMOUS | MAP_NORESERVE, -1, 0);
  ASSERT_NE(held, MAP_FAILED);
  const uint64_t budget = uint64_t(256) << 20;
  EXPECT_EQ(kAllocate(job_named("fits.vtu", budget), {}, 100), (size_t(100) << 20) / 4096);  // 100 MiB of the 256 MiB budget
  EXPECT_EQ(input_error_of([&] { kAllocate(job_named("huge.vtu", budget), {}, 0); }),
            "huge.vtu: the reader needs more than 256 MiB of memory (std::bad_alloc): the file is corrupt, or too large for this machine");
  ::munmap(held, reserved);
  EXPECT_FALSE(readers_left());
}

TEST(IsolatedRead, AChildPastItsTimeLimitIsKilledAndNamed) {
  const auto start = Clock::now();
  EXPECT_EQ(input_error_of([] { kNeverReturn(job_named("loop.obj", 0, 0.5), {}, 0); }),
            "loop.obj: the reader did not finish within 0.5 s (the limit for a file of this size): the file is corrupt or truncated");
  EXPECT_LT(std::chrono::duration<double>(Clock::now() - start).count(), 5.0);
  EXPECT_FALSE(readers_left());
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
    kNeverReturn(job, [&](double, const std::string&) {
      if (g_interrupted && interrupted_at == Clock::time_point{}) interrupted_at = Clock::now();
      return !g_interrupted;
    }, 0);
  } catch (const io::Cancelled& e) {
    cancelled = true;
    EXPECT_EQ(std::string(e.what()), "slow.off: cancelled");
  }
  interrupter.join();
  ::sigaction(SIGUSR1, &previous, nullptr);
  EXPECT_TRUE(cancelled);
  ASSERT_NE(interrupted_at, Clock::time_point{});
  EXPECT_LT(std::chrono::duration<double>(Clock::now() - interrupted_at).count(), 1.0);
  EXPECT_FALSE(readers_left());
}

TEST(IsolatedRead, ACallerThatStopsBeforeTheStartStartsNothing) {
  EXPECT_THROW(kFill(job_named("x.vtu"), [](double, const std::string&) { return false; }, 10), io::Cancelled);
  EXPECT_FALSE(readers_left());
}

// Issue 40's hang: the readers ran in a bare fork() of this multithreaded process, and a fork
// that landed while one of TBB's workers was winding down left the child waiting for ever in its
// first parallel loop (VTK's vtkSMPTools runs on TBB in Debian). Here a thread of the caller keeps
// TBB's workers waking and winding down while 300 children that run a parallel loop start one
// after another; each must finish (a deadlocked child would hit its 30 s limit and fail the read).
// With bare forks, 1.5 % of such children deadlocked on the 2-core machine (6 runs of 6 failed,
// 2 to 8 children each); a fresh process inherits no thread's state.
TEST(IsolatedRead, ChildrenStartCleanWhileTheCallerRunsParallelLoops) {
  constexpr uint64_t kCount = 1 << 16;
  const uint64_t expected = kCount * (kCount - 1) / 2;
  ASSERT_EQ(parallel_sum(kCount), expected);
  std::atomic<bool> stop{false};
  std::thread churn([&] {
    std::mt19937 random(40);
    while (!stop) {
      parallel_sum(1 << 14);
      std::this_thread::sleep_for(std::chrono::microseconds(random() % 50));
    }
  });
  constexpr int kChildren = 300;
  int finished = 0;
  for (int i = 0; i < kChildren; ++i) {
    try {
      EXPECT_EQ(kParallelSum(job_named("parallel-" + std::to_string(i), 0, 30.0), {}, kCount), expected);
      ++finished;
    } catch (const InputError& e) {
      ADD_FAILURE() << e.what();
    }
  }
  stop = true;
  churn.join();
  EXPECT_EQ(finished, kChildren);
  EXPECT_FALSE(readers_left());
}

// Readers are forks of the host, which is safe only while the host has one thread: OpenVDB's
// log4cplus starts a pool of threads as the program loads, which the host shuts down (until it
// has, readers start afresh with exec).
TEST(IsolatedRead, TheReaderHostIsOneThreadThatHasRunNoWork) {
  EXPECT_EQ(kParallelSum(job_named("start the host"), {}, 1000), uint64_t(1000 * 999 / 2));
  // Once log4cplus's threads have ended (they take a moment), readers are forks of the host.
  std::string started_as;
  for (const auto start = Clock::now(); Clock::now() - start < std::chrono::seconds(10);) {
    started_as = kStartedAs(job_named("a reader"), {}, 0);
    if (started_as == "--prismoid-reader-host") break;
    std::this_thread::sleep_for(std::chrono::milliseconds(20));
  }
  EXPECT_EQ(started_as, "--prismoid-reader-host") << "a fork of the host, not a fresh start";
  const std::map<pid_t, test::ProcessStat> table = test::process_table();
  const std::vector<pid_t> hosts = test::children_in(table, ::getpid());
  ASSERT_EQ(hosts.size(), 1u) << "one host for this thread";
  EXPECT_EQ(table.at(hosts[0]).threads, 1);
  std::ifstream command(std::filesystem::path("/proc") / std::to_string(hosts[0]) / "cmdline");
  std::string argv0, argv1;
  std::getline(command, argv0, '\0');
  std::getline(command, argv1, '\0');
  EXPECT_EQ(argv1, "--prismoid-reader-host");
  EXPECT_GT(io::largest_reader_memory_bytes(), uint64_t(0));
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
