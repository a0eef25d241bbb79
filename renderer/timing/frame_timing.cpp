#include "renderer/timing/frame_timing.hpp"

#include <algorithm>
#include <atomic>
#include <cctype>
#include <cerrno>
#include <chrono>
#include <cmath>
#include <csignal>
#include <cstdlib>
#include <fcntl.h>
#include <map>
#include <mutex>
#include <poll.h>
#include <spawn.h>
#include <sys/wait.h>
#include <thread>
#include <unistd.h>

extern char** environ;

namespace prismoid::timing {

double median_of(std::vector<double> values) {
  values.erase(std::remove_if(values.begin(), values.end(), [](double v) { return !std::isfinite(v); }), values.end());
  if (values.empty()) return std::nan("");
  std::sort(values.begin(), values.end());
  const size_t n = values.size();
  return n % 2 ? values[n / 2] : 0.5 * (values[n / 2 - 1] + values[n / 2]);
}

Spread spread_of(const std::vector<double>& values) {
  Spread s;
  s.median = median_of(values);
  s.best = s.worst = std::nan("");
  for (const double v : values) {
    if (!std::isfinite(v)) continue;
    s.best = std::isnan(s.best) ? v : std::min(s.best, v);
    s.worst = std::isnan(s.worst) ? v : std::max(s.worst, v);
  }
  return s;
}

std::vector<vk::PassTiming> FrameTiming::medians() const {
  std::vector<vk::PassTiming> out;
  for (const PassSpread& p : passes) out.push_back({p.name, p.ms.median});
  return out;
}

FrameTiming summarize_frames(const std::vector<std::vector<vk::PassTiming>>& frames) {
  FrameTiming t;
  t.frames = uint32_t(frames.size());
  if (frames.empty()) return t;
  // The k-th occurrence of each name in a frame, for every frame.
  const auto occurrences = [](const std::vector<vk::PassTiming>& frame) {
    std::map<std::string, std::vector<double>> by_name;
    for (const vk::PassTiming& p : frame) by_name[p.name].push_back(p.gpu_ms);
    return by_name;
  };
  std::vector<std::map<std::string, std::vector<double>>> by_frame;
  for (const auto& f : frames) by_frame.push_back(occurrences(f));
  std::map<std::string, size_t> seen;
  for (const vk::PassTiming& p : frames.front()) {
    const size_t k = seen[p.name]++;
    std::vector<double> ms;
    for (const auto& f : by_frame)
      if (const auto it = f.find(p.name); it != f.end() && k < it->second.size()) ms.push_back(it->second[k]);
    t.passes.push_back({p.name, spread_of(ms)});
  }
  std::vector<double> totals;
  for (const auto& f : frames) totals.push_back(vk::total_gpu_ms(f));
  t.total_ms = spread_of(totals);
  return t;
}

struct SmClockSampler::State {
  pid_t child = -1;
  int fd = -1;
  std::thread reader;
  std::atomic<bool> stopping{false};
  std::mutex mutex;
  std::vector<double> mhz;  // every sample so far
  std::vector<SmClockSampler::Clock::time_point> at;  // when each arrived

  // Reads the child's lines until it ends, or until stopping and nothing more comes.
  void read_lines() {
    std::string line;
    char buffer[256];
    for (;;) {
      pollfd p{fd, POLLIN, 0};
      const int ready = poll(&p, 1, 50);
      if (ready < 0 && errno != EINTR) return;
      if (ready <= 0) {
        if (stopping) return;
        continue;
      }
      const ssize_t n = read(fd, buffer, sizeof buffer);
      if (n < 0 && errno == EINTR) continue;
      if (n <= 0) return;  // the child ended
      for (ssize_t i = 0; i < n; ++i) {
        if (buffer[i] != '\n') { line += buffer[i]; continue; }
        char* end = nullptr;
        const double v = std::strtod(line.c_str(), &end);
        const char* rest = end;
        // A number alone on its line ("1980"); anything else ("[N/A]", an error) is no sample.
        const bool number = rest != line.c_str() && std::all_of(rest, line.c_str() + line.size(), [](char c) {
          return std::isspace(static_cast<unsigned char>(c)) != 0;
        });
        if (number && std::isfinite(v) && v > 0.0) {
          std::lock_guard lock(mutex);
          mhz.push_back(v);
          at.push_back(SmClockSampler::Clock::now());
        }
        line.clear();
      }
    }
  }

  // Ends the child (unless it ended by itself) and the reader; then mhz holds every sample.
  void end() {
    if (child > 0) {
      kill(child, SIGTERM);
      int status = 0;
      while (waitpid(child, &status, 0) < 0 && errno == EINTR) {}
      child = -1;
    }
    stopping = true;
    if (reader.joinable()) reader.join();
    if (fd >= 0) close(fd);
    fd = -1;
  }
};

SmClockSampler::SmClockSampler() : state_(std::make_unique<State>()) {
  int pipe_fds[2];
  if (pipe2(pipe_fds, O_CLOEXEC) != 0) return;
  posix_spawn_file_actions_t actions;
  posix_spawn_file_actions_init(&actions);
  posix_spawn_file_actions_adddup2(&actions, pipe_fds[1], STDOUT_FILENO);
  posix_spawn_file_actions_addopen(&actions, STDERR_FILENO, "/dev/null", O_WRONLY, 0);
  posix_spawnattr_t attributes;
  posix_spawnattr_init(&attributes);
  // The child starts with no signal blocked and SIGTERM at its default, whatever this process
  // holds meanwhile (OutputFiles blocks signals around its renames). It stays in this process
  // group, so a Ctrl-C ends it with us; should we end otherwise, its next write finds no reader
  // and SIGPIPE ends it.
  sigset_t none, term;
  sigemptyset(&none);
  sigemptyset(&term);
  sigaddset(&term, SIGTERM);
  posix_spawnattr_setsigmask(&attributes, &none);
  posix_spawnattr_setsigdefault(&attributes, &term);
  posix_spawnattr_setflags(&attributes, POSIX_SPAWN_SETSIGMASK | POSIX_SPAWN_SETSIGDEF);
  char* argv[] = {const_cast<char*>("nvidia-smi"), const_cast<char*>("--query-gpu=clocks.sm"),
                  const_cast<char*>("--format=csv,noheader,nounits"), const_cast<char*>("-lms"), const_cast<char*>("100"), nullptr};
  pid_t pid = -1;
  const int spawned = posix_spawnp(&pid, "nvidia-smi", &actions, &attributes, argv, environ);
  posix_spawn_file_actions_destroy(&actions);
  posix_spawnattr_destroy(&attributes);
  close(pipe_fds[1]);
  if (spawned != 0) {  // not on PATH: nothing to sample
    close(pipe_fds[0]);
    return;
  }
  state_->child = pid;
  state_->fd = pipe_fds[0];
  state_->reader = std::thread([s = state_.get()] { s->read_lines(); });
}

std::optional<ClockSpread> SmClockSampler::stop() {
  State& s = *state_;
  if (s.fd < 0) return std::nullopt;  // nvidia-smi did not start, or stop() ran already
  {
    // Where nothing came while the frames ran (nvidia-smi was still starting), wait for its first sample.
    const auto deadline = std::chrono::steady_clock::now() + std::chrono::seconds(1);
    bool any = false;
    for (;;) {
      {
        std::lock_guard lock(s.mutex);
        any = !s.mhz.empty();
      }
      if (any || std::chrono::steady_clock::now() >= deadline) break;
      int status = 0;
      if (waitpid(s.child, &status, WNOHANG) == s.child) {  // it ended by itself (no driver): nothing will come
        s.child = -1;
        break;
      }
      std::this_thread::sleep_for(std::chrono::milliseconds(10));
    }
  }
  s.end();
  std::vector<double> mhz;
  {
    std::lock_guard lock(s.mutex);
    mhz = s.mhz;
  }
  if (mhz.empty()) return std::nullopt;
  const Spread spread = spread_of(mhz);
  return ClockSpread{spread.best, spread.median, spread.worst, mhz.size()};
}

bool SmClockSampler::running() {
  State& s = *state_;
  if (s.child <= 0 || s.fd < 0) return false;
  int status = 0;
  if (waitpid(s.child, &status, WNOHANG) == s.child) {
    s.child = -1;
    return false;
  }
  return true;
}

std::optional<ClockSpread> SmClockSampler::during(Clock::time_point from, Clock::time_point to) {
  State& s = *state_;
  std::vector<double> inside, before;
  {
    std::lock_guard lock(s.mutex);
    for (size_t i = 0; i < s.mhz.size(); ++i) {
      if (s.at[i] >= from && s.at[i] <= to) inside.push_back(s.mhz[i]);
      else if (s.at[i] < from && s.at[i] >= from - std::chrono::milliseconds(500)) before.push_back(s.mhz[i]);
    }
  }
  if (inside.empty()) inside = before;
  if (inside.empty()) {
    const auto deadline = Clock::now() + std::chrono::seconds(1);
    while (inside.empty() && Clock::now() < deadline && running()) {
      {
        std::lock_guard lock(s.mutex);
        for (size_t i = 0; i < s.mhz.size(); ++i)
          if (s.at[i] > to) {
            inside.push_back(s.mhz[i]);
            break;
          }
      }
      if (inside.empty()) std::this_thread::sleep_for(std::chrono::milliseconds(10));
    }
  }
  if (inside.empty()) return std::nullopt;
  const Spread spread = spread_of(inside);
  return ClockSpread{spread.best, spread.median, spread.worst, inside.size()};
}

namespace {
// One sampler for the process, restarted where its child has ended (or never started). Its
// destructor ends the child at exit.
std::mutex process_clock_mutex;
std::unique_ptr<SmClockSampler> process_clock;
}  // namespace

SmClockSampler* process_sm_clock() {
  std::lock_guard lock(process_clock_mutex);
  if (!process_clock || !process_clock->running()) process_clock = std::make_unique<SmClockSampler>();
  return process_clock->running() ? process_clock.get() : nullptr;
}

void stop_process_sm_clock() {
  std::lock_guard lock(process_clock_mutex);
  process_clock.reset();
}

SmClockSampler::~SmClockSampler() {
  if (state_) state_->end();
}

FrameTiming time_frames(uint32_t frames, const std::function<std::vector<vk::PassTiming>()>& frame) {
  std::vector<std::vector<vk::PassTiming>> timings;
  SmClockSampler* clock = process_sm_clock();
  const auto from = SmClockSampler::Clock::now();
  for (uint32_t i = 0; i < frames; ++i) timings.push_back(frame());
  const auto to = SmClockSampler::Clock::now();
  FrameTiming t = summarize_frames(timings);
  if (clock) t.sm_clock = clock->during(from, to);
  return t;
}

}  // namespace prismoid::timing
