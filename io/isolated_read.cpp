#include "io/isolated_read.hpp"

#include <algorithm>
#include <cerrno>
#include <chrono>
#include <cmath>
#include <csignal>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <atomic>
#include <memory>
#include <new>
#include <optional>
#include <map>
#include <stdexcept>
#include <utility>

#include <dlfcn.h>
#include <fcntl.h>
#include <poll.h>
#include <sys/prctl.h>
#include <sys/resource.h>
#include <sys/socket.h>
#include <sys/stat.h>
#include <sys/syscall.h>
#include <sys/types.h>
#include <sys/wait.h>
#include <unistd.h>

#include "io/path_util.hpp"
#include "scene/input_error.hpp"

namespace prismoid::io {

namespace {

bool g_in_child = false;
bool g_can_serve = false;  // serve_isolated_child ran: a child started from here finds its work

// How a process started by run_in_child knows what it is: argv[1]. A reader host (below) has
// nothing more; a reader started fresh has the work's name and its memory limit after it.
constexpr const char* kHostFlag = "--prismoid-reader-host";
constexpr const char* kChildFlag = "--prismoid-isolated-child";
// The socket to the parent: the host's control socket in the host, the reader's socket in a reader.
constexpr int kChildFd = 3;
// The exit status of a child that could not run this program again.
constexpr int kExecFailed = 127;
// The longest name of a kind of work (it travels in a fixed-size message).
constexpr size_t kMaxWorkName = 63;

// The largest peak resident memory of a reader so far, in KiB.
std::atomic<uint64_t> g_largest_reader_kib{0};

std::map<std::string, ChildServe, std::less<>>& work_table() {
  static std::map<std::string, ChildServe, std::less<>> table;
  return table;
}

// What the child sends: any number of progress frames, then one error or one result frame.
enum Frame : uint8_t { kProgressFrame = 'P', kErrorFrame = 'E', kResultFrame = 'R' };
enum ErrorKind : uint8_t { kInputError = 1, kCancelled = 2, kOutOfMemory = 3, kOtherError = 4 };

// How often the parent looks up from the pipe to ask the caller whether to go on.
constexpr int kPollMilliseconds = 100;

std::string signal_name(int sig) {
  const char* abbrev = ::sigabbrev_np(sig);
  return abbrev ? std::string("SIG") + abbrev : "signal " + std::to_string(sig);
}

std::string bytes_text(uint64_t bytes) {
  char text[32];
  if (bytes < (uint64_t(1) << 30)) std::snprintf(text, sizeof text, "%.0f MiB", double(bytes) / double(uint64_t(1) << 20));
  else std::snprintf(text, sizeof text, "%.1f GiB", double(bytes) / double(uint64_t(1) << 30));
  return text;
}

std::string seconds_text(double seconds) {
  char text[32];
  std::snprintf(text, sizeof text, seconds < 10.0 ? "%.1f s" : "%.0f s", seconds);
  return text;
}

// The process's mapped address space (the first field of /proc/self/statm, in pages).
uint64_t mapped_bytes() {
  const int fd = ::open("/proc/self/statm", O_RDONLY | O_CLOEXEC);
  if (fd < 0) return 0;
  char text[64] = {};
  const ssize_t n = ::read(fd, text, sizeof text - 1);
  ::close(fd);
  uint64_t pages = 0;
  for (ssize_t i = 0; i < n && text[i] >= '0' && text[i] <= '9'; ++i) pages = 10 * pages + uint64_t(text[i] - '0');
  return pages * uint64_t(::sysconf(_SC_PAGESIZE));
}

bool write_all(int fd, const void* data, size_t count) {
  const char* p = static_cast<const char*>(data);
  while (count > 0) {
    const ssize_t n = ::write(fd, p, count);
    if (n < 0 && errno == EINTR) continue;
    if (n <= 0) return false;
    p += n;
    count -= size_t(n);
  }
  return true;
}

// The text of an InputError without its "source: " prefix.
std::string problem_of(const InputError& e) {
  const std::string what = e.what();
  return what.size() >= e.source().size() + 2 ? what.substr(e.source().size() + 2) : what;
}

// The reader (a fork of the host, or a fresh process): limits first, then the request, then the
// work; every way out is _exit.
[[noreturn]] void child_main(const std::string& name, uint64_t memory_bytes) {
  g_in_child = true;
  const int fd = kChildFd;
  // Ctrl-C reaches the whole process group; the parent decides (it cancels and kills the child).
  struct sigaction ignore {};
  ignore.sa_handler = SIG_IGN;
  ::sigaction(SIGINT, &ignore, nullptr);
  // What this process maps now (the program and its libraries) plus what the work may add.
  if (const uint64_t mapped = mapped_bytes(); memory_bytes > 0 && mapped > 0) {  // (no /proc: no limit)
    const rlim_t limit = rlim_t(mapped + memory_bytes);
    const rlimit as{limit, limit};
    ::setrlimit(RLIMIT_AS, &as);
  }
  auto send = [fd](const void* data, size_t count) {
    if (!write_all(fd, data, count)) ::_exit(1);  // the parent is gone or stopped listening
  };
  auto send_text = [&](const std::string& text) {
    const uint64_t n = text.size();
    send(&n, sizeof n);
    send(text.data(), text.size());
  };
  auto send_error = [&](ErrorKind kind, const std::string& source, const std::string& text) {
    const uint8_t header[2] = {kErrorFrame, kind};
    send(header, sizeof header);
    send_text(source);
    send_text(text);
    ::_exit(0);
  };
  std::string source;
  try {
    RequestReader in(fd);
    in(source);
    const auto work = work_table().find(name);
    if (work == work_table().end()) send_error(kOtherError, source, "this program has no work named '" + name + "'");
    double last_fraction = -2.0;
    std::string last_stage;
    const Progress forward = [&](double fraction, const std::string& stage) {
      if (fraction != last_fraction || stage != last_stage) {
        last_fraction = fraction;
        last_stage = stage;
        const uint8_t tag = kProgressFrame;
        send(&tag, 1);
        send(&fraction, sizeof fraction);
        send_text(stage);
      }
      return true;
    };
    ResultWriter out(fd);
    work->second(in, out, forward);
  } catch (const InputError& e) {
    send_error(kInputError, e.source(), problem_of(e));
  } catch (const Cancelled& e) {
    send_error(kCancelled, source, e.what());
  } catch (const std::bad_alloc& e) {
    send_error(kOutOfMemory, source, e.what());
  } catch (const std::length_error& e) {  // a size beyond what a container can hold
    send_error(kOutOfMemory, source, e.what());
  } catch (const std::exception& e) {
    send_error(kOtherError, source, e.what());
  } catch (...) {
    send_error(kOtherError, source, "an unknown exception");
  }
  ::_exit(0);
}

// Between fork and exec, in the copy of a multithreaded process: system calls only (no
// allocation, no locks, no stdio). Sets up what the fresh child inherits: the socket as kChildFd,
// /dev/null as its standard streams (readers talk there when they fail: the PLY library, glibc's
// "double free detected"; the parent reports the failure in one line of its own), no other file
// (a concurrent child's socket held open here would keep its parent from seeing that child end),
// no core files, and death with the parent.
[[noreturn]] void exec_child(int socket, pid_t parent, char* const* argv) {
  ::prctl(PR_SET_PDEATHSIG, SIGKILL);     // dies with the parent (the thread that forked, which waits for it)
  if (::getppid() != parent) ::_exit(1);  // the parent ended before the line above
  if (socket == kChildFd) ::fcntl(kChildFd, F_SETFD, 0);  // keep it across exec
  else if (::dup2(socket, kChildFd) < 0) ::_exit(kExecFailed);
  const int null = ::open("/dev/null", O_RDWR);
  if (null < 0) ::_exit(kExecFailed);
  for (const int stream : {STDIN_FILENO, STDOUT_FILENO, STDERR_FILENO}) ::dup2(null, stream);
  ::close_range(kChildFd + 1, ~0U, 0);
  const rlimit no_core{0, 0};
  ::setrlimit(RLIMIT_CORE, &no_core);  // a crashing reader leaves no core file behind
  ::execv("/proc/self/exe", argv);
  ::_exit(kExecFailed);
}


// ---- the reader host -------------------------------------------------------------------------------
//
// Starting this program afresh costs 55-90 ms (the dynamic loader binding VTK's, OpenVDB's and
// Vulkan's libraries), about 100 times a fork. So each thread that reads starts one fresh copy of
// the program, the reader host, which runs no work of its own and forks a reader per request:
// every reader is a fork of a process that is single-threaded and has run nothing but the
// libraries' initializers, which is as clean as a fresh start. The one library that starts
// threads on loading (log4cplus, under OpenVDB: a pool for asynchronous logging that nothing here
// uses) has its pool shut down first; if the host still has another thread, its readers start
// afresh with exec instead, slower and as safe.
//
// The control socket (SOCK_SEQPACKET, one message per send) carries, per reader: the request to
// start it (StartMessage, with the reader's socket passed along), the answer (StartedMessage, with
// a pidfd the parent kills it through), and its end (EndedMessage). The host exits when the
// parent closes the socket; readers die with the host (PR_SET_PDEATHSIG), the host with the
// thread that started it.

struct StartMessage {
  uint64_t memory_bytes = 0;
  char name[kMaxWorkName + 1] = {};
};
struct StartedMessage {
  int32_t pid = -1;
  int32_t error = 0;  // errno of a failed fork
};
struct EndedMessage {
  int32_t status = 0;  // as waitpid reports it
  int32_t unused = 0;
  uint64_t peak_kib = 0;  // the reader's peak resident memory
};

// Sends `size` bytes as one message, with `fd` (when >= 0) passed along.
bool send_message(int socket, const void* data, size_t size, int fd) {
  iovec part{const_cast<void*>(data), size};
  msghdr message{};
  message.msg_iov = &part;
  message.msg_iovlen = 1;
  alignas(cmsghdr) char control[CMSG_SPACE(sizeof(int))] = {};
  if (fd >= 0) {
    message.msg_control = control;
    message.msg_controllen = sizeof control;
    cmsghdr* header = CMSG_FIRSTHDR(&message);
    header->cmsg_level = SOL_SOCKET;
    header->cmsg_type = SCM_RIGHTS;
    header->cmsg_len = CMSG_LEN(sizeof(int));
    std::memcpy(CMSG_DATA(header), &fd, sizeof fd);
  }
  for (;;) {
    const ssize_t n = ::sendmsg(socket, &message, MSG_NOSIGNAL);
    if (n < 0 && errno == EINTR) continue;
    return n == ssize_t(size);
  }
}

// Receives one message of exactly `size` bytes and the descriptor passed with it (-1: none).
bool receive_message(int socket, void* data, size_t size, int* fd) {
  iovec part{data, size};
  msghdr message{};
  message.msg_iov = &part;
  message.msg_iovlen = 1;
  alignas(cmsghdr) char control[CMSG_SPACE(sizeof(int))] = {};
  message.msg_control = control;
  message.msg_controllen = sizeof control;
  ssize_t n = 0;
  do n = ::recvmsg(socket, &message, MSG_CMSG_CLOEXEC);
  while (n < 0 && errno == EINTR);
  int passed = -1;
  for (cmsghdr* header = CMSG_FIRSTHDR(&message); header; header = CMSG_NXTHDR(&message, header))
    if (header->cmsg_level == SOL_SOCKET && header->cmsg_type == SCM_RIGHTS) std::memcpy(&passed, CMSG_DATA(header), sizeof passed);
  if (fd) *fd = passed;
  else if (passed >= 0) ::close(passed);
  return n == ssize_t(size);
}

int thread_count() {
  std::ifstream status("/proc/self/status");
  std::string line;
  while (std::getline(status, line))
    if (line.rfind("Threads:", 0) == 0) return std::atoi(line.c_str() + 8);
  return -1;
}

// log4cplus::shutdownThreadPool(), looked up rather than linked: it is there only where OpenVDB
// brought log4cplus in.
void shut_down_library_threads() {
  using Shutdown = void (*)();
  if (void* symbol = ::dlsym(RTLD_DEFAULT, "_ZN9log4cplus18shutdownThreadPoolEv")) reinterpret_cast<Shutdown>(symbol)();
}

[[noreturn]] void host_main() {
  g_in_child = true;
  // Ctrl-C reaches the whole process group; the parent decides (it cancels and kills the reader).
  struct sigaction ignore {};
  ignore.sa_handler = SIG_IGN;
  ::sigaction(SIGINT, &ignore, nullptr);
  shut_down_library_threads();  // (its threads may take a moment to end: counted before each fork)
  const pid_t host = ::getpid();
  for (;;) {
    StartMessage start;
    int socket = -1;
    if (!receive_message(kChildFd, &start, sizeof start, &socket)) ::_exit(0);  // the parent closed the socket, or is gone
    if (socket < 0) ::_exit(1);
    start.name[kMaxWorkName] = '\0';
    const std::string memory = std::to_string(start.memory_bytes);
    std::string program = "prismoid-reader";
    char* const argv[] = {program.data(), const_cast<char*>(kChildFlag), start.name, const_cast<char*>(memory.c_str()), nullptr};
    const bool single_threaded = thread_count() == 1;
    StartedMessage started;
    started.pid = ::fork();
    if (started.pid == 0) {
      if (single_threaded) {
        ::prctl(PR_SET_PDEATHSIG, SIGKILL);
        if (::getppid() != host) ::_exit(1);
        if (::dup2(socket, kChildFd) < 0) ::_exit(1);  // (closes this copy of the control socket)
        ::close(socket);
        child_main(start.name, start.memory_bytes);
      }
      exec_child(socket, host, argv);
    }
    started.error = started.pid < 0 ? errno : 0;
    ::close(socket);
    const int pidfd = started.pid > 0 ? int(::syscall(SYS_pidfd_open, started.pid, 0)) : -1;
    const bool told = send_message(kChildFd, &started, sizeof started, pidfd);
    if (pidfd >= 0) ::close(pidfd);
    if (!told) ::_exit(0);
    if (started.pid < 0) continue;
    EndedMessage ended;
    int status = 0;
    rusage usage{};
    while (::wait4(started.pid, &status, 0, &usage) < 0 && errno == EINTR) {
    }
    ended.status = status;
    ended.peak_kib = uint64_t(usage.ru_maxrss);
    if (!send_message(kChildFd, &ended, sizeof ended, -1)) ::_exit(0);
  }
}

// The parent's handle on its thread's reader host.
class ReaderHost {
 public:
  ReaderHost() {
    int fds[2];
    if (::socketpair(AF_UNIX, SOCK_SEQPACKET | SOCK_CLOEXEC, 0, fds) != 0)
      throw std::runtime_error(std::string("cannot make a socket for the reader host: ") + std::strerror(errno));
    std::string program = "prismoid-reader-host";
    char* const argv[] = {program.data(), const_cast<char*>(kHostFlag), nullptr};
    const pid_t parent = ::getpid();
    pid_ = ::fork();
    if (pid_ < 0) {
      const int error = errno;
      ::close(fds[0]);
      ::close(fds[1]);
      throw std::runtime_error(std::string("cannot start the reader host: ") + std::strerror(error));
    }
    if (pid_ == 0) exec_child(fds[1], parent, argv);
    ::close(fds[1]);
    control_ = fds[0];
    owner_ = parent;
  }
  ~ReaderHost() {
    ::close(control_);  // the host exits, and its readers with it
    if (::getpid() != owner_) return;  // a fork of the owner (a death test's child) leaves the owner's host alone
    ::kill(pid_, SIGKILL);
    while (::waitpid(pid_, nullptr, 0) < 0 && errno == EINTR) {
    }
  }
  ReaderHost(const ReaderHost&) = delete;
  ReaderHost& operator=(const ReaderHost&) = delete;

  bool alive() const { return alive_; }

  // Starts the work `name` in a reader talking on `socket`; the reader's pid and a pidfd for it
  // (-1 where the system has none). A host that cannot start it is a runtime_error.
  std::pair<pid_t, int> start(std::string_view name, uint64_t memory_bytes, int socket) {
    StartMessage message;
    message.memory_bytes = memory_bytes;
    name.copy(message.name, kMaxWorkName);
    StartedMessage started;
    int pidfd = -1;
    if (!send_message(control_, &message, sizeof message, socket) || !receive_message(control_, &started, sizeof started, &pidfd)) {
      alive_ = false;
      throw std::runtime_error("the reader host ended (this program could not run itself again)");
    }
    if (started.pid < 0) throw std::runtime_error(std::string("cannot start a reader: ") + std::strerror(started.error));
    return {pid_t(started.pid), pidfd};
  }

  // The reader's end (after it exited or was killed): its wait status; nullopt if the host ended.
  std::optional<EndedMessage> ended() {
    EndedMessage message;
    if (receive_message(control_, &message, sizeof message, nullptr)) return message;
    alive_ = false;
    return std::nullopt;
  }

 private:
  pid_t pid_ = -1;
  pid_t owner_ = -1;
  int control_ = -1;
  bool alive_ = true;
};

// The calling thread's host, started on first use and again after it ended. It is per thread
// because a reader host dies with the thread that started it (PR_SET_PDEATHSIG follows threads).
ReaderHost& host_for_this_thread() {
  thread_local std::unique_ptr<ReaderHost> host;
  if (!host || !host->alive()) {
    host.reset();
    host = std::make_unique<ReaderHost>();
  }
  return *host;
}

}  // namespace

// The parent's end of the pipe and the child itself: whatever way the parent leaves (a result,
// an error, the caller's exception), the child is killed if still running and reaped.
class ChildChannel {
 public:
  ChildChannel(const ChildJob& job, const Progress& progress, ReaderHost& host, pid_t pid, int pidfd, int fd)
      : job_(job), progress_(progress), host_(host), pid_(pid), pidfd_(pidfd), fd_(fd), fraction_(job.waiting_fraction), stage_(job.stage) {
    if (job.limits.seconds > 0.0)
      deadline_ = std::chrono::steady_clock::now() + std::chrono::duration_cast<std::chrono::steady_clock::duration>(
                                                          std::chrono::duration<double>(job.limits.seconds));
  }
  ~ChildChannel() {
    if (pid_ > 0) {
      kill_child();
      reap();
    }
    ::close(fd_);
  }
  ChildChannel(const ChildChannel&) = delete;
  ChildChannel& operator=(const ChildChannel&) = delete;

  void read(void* data, size_t count) {
    char* p = static_cast<char*>(data);
    while (count > 0) {
      wait_ready(POLLIN);
      const ssize_t n = ::read(fd_, p, count);
      if (n < 0 && (errno == EINTR || errno == EAGAIN)) continue;
      if (n <= 0) ended_without_result();
      p += n;
      count -= size_t(n);
    }
  }

  void write(const void* data, size_t count) {
    const char* p = static_cast<const char*>(data);
    while (count > 0) {
      wait_ready(POLLOUT);
      const ssize_t n = ::send(fd_, p, count, MSG_NOSIGNAL | MSG_DONTWAIT);
      if (n < 0 && (errno == EINTR || errno == EAGAIN)) continue;
      if (n <= 0) ended_without_result();  // it stopped reading: it ended
      p += n;
      count -= size_t(n);
    }
  }

  // A progress report from the child, passed on.
  void progress(double fraction, const std::string& stage) {
    fraction_ = fraction;
    stage_ = stage;
    ask_caller();
  }

  // After the result: the child exits on its own.
  void finish() { reap(); }

  // The reader's wait status, from the host (once it has exited or been killed).
  int reap() {
    if (pid_ <= 0) return 0;
    pid_ = -1;
    if (pidfd_ >= 0) ::close(pidfd_);
    pidfd_ = -1;
    const std::optional<EndedMessage> ended = host_.ended();
    if (!ended) {
      host_gone_ = true;
      return 0;
    }
    uint64_t largest = g_largest_reader_kib.load();
    while (ended->peak_kib > largest && !g_largest_reader_kib.compare_exchange_weak(largest, ended->peak_kib)) {
    }
    return ended->status;
  }

  [[noreturn]] void ended_without_result() {
    const int status = reap();
    if (host_gone_)  // the machine's problem (the host was killed), not the file's
      throw std::runtime_error(job_.source + ": the process hosting " + job_.worker + " ended while it worked");
    if (WIFSIGNALED(status)) {
      const int sig = WTERMSIG(status);
      if (sig == SIGKILL)  // not ours (we reap our own kills elsewhere): the system's out-of-memory killer, or a user
        throw InputError(job_.source, job_.worker + " was killed (SIGKILL), most likely for lack of memory: " + job_.memory_hint);
      throw InputError(job_.source, job_.worker + " crashed (" + signal_name(sig) + "): " + job_.crash_hint);
    }
    if (WIFEXITED(status) && WEXITSTATUS(status) == kExecFailed)  // the machine's problem, not the file's
      throw std::runtime_error(job_.source + ": cannot start a process for " + job_.worker + " (this program could not run itself again)");
    throw InputError(job_.source, job_.worker + " ended without a result (exit status " +
                                      std::to_string(WIFEXITED(status) ? WEXITSTATUS(status) : -1) + "): " + job_.crash_hint);
  }

  const ChildJob& job() const { return job_; }

 private:
  void wait_ready(short events) {
    for (;;) {
      check_deadline();
      pollfd ready{fd_, events, 0};
      const int rc = ::poll(&ready, 1, kPollMilliseconds);
      if (rc > 0) return;                     // ready, the end of the socket, or an error: read()/send() tell
      if (rc < 0 && errno != EINTR) return;   // read()/send() report it
      // Nothing yet, or a signal interrupted the wait (Ctrl-C's handler sets the flag the
      // caller's progress callback reads): ask the caller whether to go on.
      ask_caller();
    }
  }

  void kill_child() {
    if (pidfd_ < 0 || ::syscall(SYS_pidfd_send_signal, pidfd_, SIGKILL, nullptr, 0) != 0) ::kill(pid_, SIGKILL);
  }

  void ask_caller() {
    if (progress_ && !progress_(fraction_, stage_)) {
      kill_child();
      reap();
      throw Cancelled(job_.source);
    }
  }

  void check_deadline() {
    if (job_.limits.seconds <= 0.0 || std::chrono::steady_clock::now() < deadline_) return;
    kill_child();
    reap();
    throw InputError(job_.source, job_.worker + " did not finish within " + seconds_text(job_.limits.seconds) +
                                      " (the limit for a file of this size): " + job_.crash_hint);
  }

  const ChildJob& job_;
  const Progress& progress_;
  ReaderHost& host_;
  pid_t pid_;
  int pidfd_;  // -1: none (the reader is killed by pid; it stays a zombie of the host until reaped, so the pid is still its)
  int fd_;
  bool host_gone_ = false;
  double fraction_;
  std::string stage_;
  std::chrono::steady_clock::time_point deadline_{};
};

void ResultWriter::bytes(const void* data, size_t count) {
  if (!started_) {  // the result frame's tag goes before its first byte
    started_ = true;
    const uint8_t tag = kResultFrame;
    if (!write_all(fd_, &tag, 1)) ::_exit(1);
  }
  if (!write_all(fd_, data, count)) ::_exit(1);
}

void ResultReader::bytes(void* data, size_t count) { channel_.read(data, count); }

void RequestWriter::bytes(const void* data, size_t count) { channel_.write(data, count); }

void RequestReader::bytes(void* data, size_t count) {
  char* p = static_cast<char*>(data);
  while (count > 0) {
    const ssize_t n = ::read(fd_, p, count);
    if (n < 0 && errno == EINTR) continue;
    if (n <= 0) ::_exit(1);  // the parent is gone
    p += n;
    count -= size_t(n);
  }
}

void register_child_work(std::string_view name, ChildServe serve) {
  if (name.size() > kMaxWorkName) throw std::logic_error("register_child_work: the name '" + std::string(name) + "' is too long");
  if (!work_table().emplace(std::string(name), std::move(serve)).second)
    throw std::logic_error("register_child_work: two kinds of work are named '" + std::string(name) + "'");
}

void serve_isolated_child(int argc, char** argv) {
  const bool host = argc >= 2 && std::strcmp(argv[1], kHostFlag) == 0;
  if (host || (argc >= 2 && std::strcmp(argv[1], kChildFlag) == 0)) {
    // Started by run_in_child, the socket to the parent is kChildFd; typed by hand, it is not.
    struct stat about {};
    if (::fstat(kChildFd, &about) != 0 || !S_ISSOCK(about.st_mode)) {
      std::fprintf(stderr, "%s: %s is for the processes a running Prismoid starts to read files, not for use by hand\n", argv[0], argv[1]);
      std::exit(2);
    }
  }
  if (host) host_main();
  if (argc >= 4 && std::strcmp(argv[1], kChildFlag) == 0) child_main(argv[2], std::strtoull(argv[3], nullptr, 10));
  g_can_serve = true;
}

bool in_isolated_child() { return g_in_child; }

uint64_t largest_reader_memory_bytes() { return g_largest_reader_kib.load() * 1024; }

uint64_t child_memory_budget() {
  const long pages = ::sysconf(_SC_PHYS_PAGES);
  const long page = ::sysconf(_SC_PAGESIZE);
  if (pages <= 0 || page <= 0) return uint64_t(8) << 30;
  return uint64_t(pages) * uint64_t(page) / 4 * 3;
}

namespace {

uint64_t file_size_or_zero(const std::filesystem::path& p) {
  std::error_code ec;
  const uintmax_t size = std::filesystem::file_size(p, ec);
  return ec ? 0 : uint64_t(size);
}

// The files a .vtm (file="..."), .pvtu (Source="...") or .mhd (ElementDataFile = ...) names,
// relative to its folder: their bytes count towards the time a read may take.
uint64_t referenced_bytes(const std::string& path, const std::string& ext) {
  std::ifstream in(path, std::ios::binary);
  std::string text(size_t(1) << 20, '\0');
  in.read(text.data(), std::streamsize(text.size()));
  text.resize(size_t(in.gcount()));
  const std::filesystem::path folder = std::filesystem::path(path).parent_path();
  uint64_t total = 0;
  if (ext == ".mhd") {
    const auto at = text.find("ElementDataFile");
    if (at == std::string::npos) return 0;
    const auto eq = text.find('=', at);
    const auto end = text.find('\n', eq);
    if (eq == std::string::npos) return 0;
    std::string name = text.substr(eq + 1, end == std::string::npos ? std::string::npos : end - eq - 1);
    name.erase(0, name.find_first_not_of(" \t"));
    name.erase(name.find_last_not_of(" \t\r") + 1);
    return name.empty() || name == "LOCAL" ? 0 : file_size_or_zero(folder / name);
  }
  const std::string key = ext == ".vtm" ? "file=\"" : "Source=\"";
  for (size_t at = text.find(key); at != std::string::npos; at = text.find(key, at + 1)) {
    const size_t start = at + key.size(), end = text.find('"', start);
    if (end == std::string::npos) break;
    total += file_size_or_zero(folder / text.substr(start, end - start));
  }
  return total;
}

}  // namespace

ChildLimits read_limits(const std::string& path) {
  const std::string ext = detail::lower_extension(path);
  uint64_t bytes = file_size_or_zero(path);
  if (ext == ".vtm" || ext == ".pvtu" || ext == ".mhd") bytes += referenced_bytes(path, ext);
  const bool may_be_compressed = ext == ".vtu" || ext == ".vtp" || ext == ".vti" || ext == ".vtm" || ext == ".pvtu" || ext == ".vdb" ||
                                 ext == ".mha" || ext == ".mhd" || ext == ".gz";
  const double expanded = double(bytes) * (may_be_compressed ? kMaxCompressionRatio : 1.0);
  ChildLimits limits;
  const bool voxels = ext == ".vti" || ext == ".mhd" || ext == ".mha" || ext == ".inr" || ext == ".gz" || ext == ".vdb";
  const double per_byte = double(voxels ? kReadMemoryPerVoxelByte : kReadMemoryPerByte);
  limits.memory_bytes = uint64_t(std::min(double(child_memory_budget()), double(kReadBaseMemory) + per_byte * expanded));
  limits.seconds = kReadBaseSeconds + kReadSecondsPerMiB * expanded / 1048576.0;
  return limits;
}

ChildJob read_job(const std::string& path) {
  ChildJob job;
  job.source = path;
  job.limits = read_limits(path);
  return job;
}

void run_in_child(const ChildJob& job, const Progress& progress, std::string_view name, const std::function<void(RequestWriter&)>& send,
                  const std::function<void(ResultReader&)>& receive) {
  if (g_in_child) throw std::logic_error("run_in_child: nested isolation; call the work directly");
  if (!g_can_serve) throw std::logic_error("run_in_child: this program's main() does not call io::serve_isolated_child first");
  report(progress, job.waiting_fraction, job.stage, job.source);  // the caller hears of the work, and may stop it, before it starts
  int fds[2];
  if (::socketpair(AF_UNIX, SOCK_STREAM | SOCK_CLOEXEC, 0, fds) != 0)
    throw std::runtime_error(job.source + ": cannot make a socket for " + job.worker + ": " + std::strerror(errno));
  ReaderHost* host = nullptr;
  std::pair<pid_t, int> started;
  for (int attempt = 0;; ++attempt) {  // a host that ended since the last read (killed by someone) is started again once
    try {
      host = &host_for_this_thread();
      started = host->start(name, job.limits.memory_bytes, fds[1]);
      break;
    } catch (const std::exception& e) {
      if (attempt == 0 && host && !host->alive()) continue;
      ::close(fds[0]);
      ::close(fds[1]);
      throw std::runtime_error(job.source + ": " + e.what());
    }
  }
  ::close(fds[1]);
  ChildChannel channel(job, progress, *host, started.first, started.second, fds[0]);
  {
    RequestWriter out(channel);
    out(job.source);
    send(out);
  }
  ResultReader in(channel);
  for (;;) {
    uint8_t tag = 0;
    channel.read(&tag, 1);
    if (tag == kProgressFrame) {
      double fraction = 0.0;
      std::string stage;
      in(fraction);
      in(stage);
      channel.progress(fraction, stage);
    } else if (tag == kErrorFrame) {
      uint8_t kind = 0;
      std::string source, text;
      in(kind);
      in(source);
      in(text);
      channel.finish();
      if (kind == kInputError) throw InputError(source, text);
      if (kind == kCancelled) throw Cancelled(job.source);
      if (kind == kOutOfMemory)
        throw InputError(job.source, job.worker + " needs more than " + bytes_text(job.limits.memory_bytes) + " of memory (" + text +
                                         "): " + job.memory_hint);
      throw InputError(job.source, job.worker + " failed: " + text);
    } else if (tag == kResultFrame) {
      receive(in);
      channel.finish();
      return;
    } else {
      channel.ended_without_result();
    }
  }
}

}  // namespace prismoid::io
