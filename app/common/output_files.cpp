#include "app/common/output_files.hpp"

#include <algorithm>
#include <array>
#include <atomic>
#include <cctype>
#include <cerrno>
#include <csignal>
#include <cstring>
#include <fcntl.h>
#include <filesystem>
#include <fstream>
#include <pthread.h>
#include <random>
#include <stdexcept>
#include <unistd.h>

#include "io/file_write.hpp"
#include "io/time_series.hpp"
#include "scene/input_error.hpp"

namespace prismoid::app {

namespace fs = std::filesystem;

namespace {

// What the signal handler removes: the temporaries and created folders of every live
// OutputFiles. Fixed slots of atomic pointers, since a handler may neither allocate nor lock.
constexpr size_t kSlots = 1024;
std::array<std::atomic<const char*>, kSlots> g_temporaries{};
std::array<std::atomic<const char*>, kSlots> g_folders{};

void enroll(std::array<std::atomic<const char*>, kSlots>& slots, const char* path) {
  for (auto& slot : slots) {
    const char* empty = nullptr;
    if (slot.compare_exchange_strong(empty, path)) return;
  }
  throw std::runtime_error("more than 1024 output files at once");
}

void withdraw(std::array<std::atomic<const char*>, kSlots>& slots, const char* path) {
  for (auto& slot : slots) {
    const char* expected = path;
    if (slot.compare_exchange_strong(expected, nullptr)) return;
  }
}

// Every signal whose default ends the process and that a user or a session sends: Ctrl-C, kill,
// a closed terminal (SIGHUP), Ctrl-\ (SIGQUIT).
constexpr std::array<int, 4> kSignals = {SIGINT, SIGTERM, SIGHUP, SIGQUIT};
std::array<struct sigaction, kSignals.size()> g_previous{};
std::array<bool, kSignals.size()> g_installed{};

size_t signal_index(int sig) {
  for (size_t i = 0; i < kSignals.size(); ++i)
    if (kSignals[i] == sig) return i;
  return 0;
}
int g_live = 0;  // OutputFiles alive (the main thread's; the handler stays while any is)

// A plain handler (no SA_SIGINFO): the progress bar and the window save and restore handlers
// through std::signal, which knows only this kind.
extern "C" void remove_outputs_on_signal(int sig) {
  for (auto& slot : g_temporaries)
    if (const char* p = slot.load()) ::unlink(p);
  // Folders inner first: a pass removes those that became empty; nested ones need more passes.
  for (int pass = 0; pass < 8; ++pass)
    for (size_t i = kSlots; i-- > 0;)
      if (const char* p = g_folders[i].load()) ::rmdir(p);
  const struct sigaction& previous = g_previous[signal_index(sig)];
  if (previous.sa_flags & SA_SIGINFO) {
    previous.sa_sigaction(sig, nullptr, nullptr);
  } else if (previous.sa_handler == SIG_DFL) {
    std::signal(sig, SIG_DFL);
    std::raise(sig);  // delivered when this handler returns: the process ends as it would have
  } else if (previous.sa_handler != SIG_IGN) {
    previous.sa_handler(sig);
  }
}

void install_handler() {
  if (g_live++ > 0) return;
  for (size_t i = 0; i < kSignals.size(); ++i) {
    g_installed[i] = false;
    if (sigaction(kSignals[i], nullptr, &g_previous[i]) != 0) continue;
    if (!(g_previous[i].sa_flags & SA_SIGINFO) && g_previous[i].sa_handler == SIG_IGN) continue;  // a background job's: not ours
    struct sigaction action{};
    action.sa_handler = remove_outputs_on_signal;
    action.sa_flags = SA_RESTART;
    sigemptyset(&action.sa_mask);
    g_installed[i] = sigaction(kSignals[i], &action, nullptr) == 0;
  }
}

void restore_handler() {
  if (--g_live > 0) return;
  for (size_t i = 0; i < kSignals.size(); ++i)
    if (g_installed[i]) sigaction(kSignals[i], &g_previous[i], nullptr);
}

// Holds those signals in this thread while alive.
class HeldSignals {
 public:
  HeldSignals() {
    sigset_t set;
    sigemptyset(&set);
    for (int s : kSignals) sigaddset(&set, s);
    pthread_sigmask(SIG_BLOCK, &set, &previous_);
  }
  ~HeldSignals() { pthread_sigmask(SIG_SETMASK, &previous_, nullptr); }
  HeldSignals(const HeldSignals&) = delete;
  HeldSignals& operator=(const HeldSignals&) = delete;

 private:
  sigset_t previous_;
};

// An error about a temporary, said of the output the user named (the temporary's name means
// nothing to them).
InputError of_output(const InputError& e, const std::string& output) {
  const std::string what = e.what();
  return InputError(output, what.substr(std::min(what.size(), e.source().size() + 2)));
}

std::string lower_extension(const std::string& path) {
  std::string ext = fs::path(path).extension().string();
  std::transform(ext.begin(), ext.end(), ext.begin(), [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
  return ext;
}

// Absolute, with symlinks resolved as far as the path exists: two spellings of one file agree.
std::string resolved_path(const std::string& path) {
  std::error_code ec;
  fs::path p = fs::weakly_canonical(fs::absolute(path, ec), ec);
  if (ec) p = fs::absolute(path, ec).lexically_normal();
  return p.string();
}

bool same_file(const std::string& a, const std::string& b) {
  if (a == b) return true;
  std::error_code ec;
  return fs::equivalent(a, b, ec) && !ec;  // both exist and are one file (hard links too)
}

// The files a .pvtu (Source="..."), .vtm or .pvd (file="...") or .mhd (ElementDataFile = ...) names
// beside it, so that an output cannot replace a piece the command reads through them.
std::vector<std::string> referenced_files(const std::string& path) {
  const std::string ext = lower_extension(path);
  if (ext != ".pvtu" && ext != ".vtm" && ext != ".mhd" && ext != ".pvd") return {};
  std::ifstream in(path, std::ios::binary);
  std::string text(size_t(1) << 20, '\0');  // the references sit in the header
  in.read(text.data(), std::streamsize(text.size()));
  text.resize(size_t(std::max<std::streamsize>(in.gcount(), 0)));
  const fs::path dir = fs::path(path).parent_path();
  std::vector<std::string> files;
  auto add = [&](const std::string& name) {
    if (!name.empty() && name != "LOCAL") files.push_back((dir / name).string());
  };
  if (ext == ".mhd") {
    const size_t key = text.find("ElementDataFile");
    const size_t eq = key == std::string::npos ? key : text.find('=', key);
    if (eq != std::string::npos) {
      const size_t begin = text.find_first_not_of(" \t", eq + 1);
      const size_t end = begin == std::string::npos ? begin : text.find_first_of("\r\n", begin);
      if (begin != std::string::npos) {
        std::string name = text.substr(begin, end == std::string::npos ? std::string::npos : end - begin);
        while (!name.empty() && std::isspace(static_cast<unsigned char>(name.back()))) name.pop_back();
        add(name);
      }
    }
    return files;
  }
  const std::string attribute = ext == ".pvtu" ? "Source=\"" : "file=\"";
  for (size_t at = text.find(attribute); at != std::string::npos; at = text.find(attribute, at + 1)) {
    const size_t begin = at + attribute.size(), end = text.find('"', begin);
    if (end == std::string::npos) break;
    add(text.substr(begin, end - begin));
  }
  return files;
}

std::string folder_of(const std::string& path) {
  const std::string dir = fs::path(path).parent_path().string();
  return dir.empty() ? "." : dir;
}

// A new empty file beside `resolved` (the name's stem, ".partial-", six random letters, the
// name's extension, which writers choose their format by), created exclusively with the usual
// permissions (0666 less the umask), into `temporary`. The name is enrolled for the signal
// handler before the file exists: a signal between creating and enrolling left the file behind
// (CliOutputs.SignalsMidRunLeaveNoPartialFile caught it under load). Unlinking a name not yet
// created is harmless.
void create_temporary(const std::string& path, const std::string& resolved, std::string& temporary) {
  static std::mt19937_64 generator{std::random_device{}()};
  const fs::path target(resolved), name(path);
  const std::string stem = name.stem().string(), ext = name.extension().string();
  static const char kLetters[] = "abcdefghijklmnopqrstuvwxyz0123456789";
  for (int attempt = 0; attempt < 100; ++attempt) {
    std::string tag;
    for (int i = 0; i < 6; ++i) tag += kLetters[generator() % (sizeof kLetters - 1)];
    temporary = (target.parent_path() / (stem + ".partial-" + tag + ext)).string();
    enroll(g_temporaries, temporary.c_str());
    const int fd = ::open(temporary.c_str(), O_WRONLY | O_CREAT | O_EXCL | O_CLOEXEC, 0666);
    if (fd >= 0) {
      ::close(fd);
      return;
    }
    const int error = errno;
    withdraw(g_temporaries, temporary.c_str());  // not ours: someone else's file, or none
    temporary.clear();
    if (error == EEXIST) continue;
    // The folder exists (checked before): ENOENT here is a folder that refuses new files (/proc).
    if (error == EACCES || error == EPERM || error == EROFS || error == ENOENT)
      throw InputError(path, "the folder '" + folder_of(path) + "' is not writable");
    throw InputError(path, "cannot create a file in the folder '" + folder_of(path) + "': " + std::strerror(error));
  }
  throw InputError(path, "cannot find a free temporary name beside it");
}

}  // namespace

OutputFiles::OutputFiles() { install_handler(); }

OutputFiles::~OutputFiles() {
  for (Output& out : outputs_) {
    if (out.temporary.empty()) continue;
    ::unlink(out.temporary.c_str());
    withdraw(g_temporaries, out.temporary.c_str());
  }
  for (auto it = folders_.rbegin(); it != folders_.rend(); ++it) {
    if (!committed_) ::rmdir(it->c_str());  // only if empty: never what someone else put there
    withdraw(g_folders, it->c_str());
  }
  restore_handler();
}

void OutputFiles::check_not_input(const Output& out, const Input& in) const {
  if (!same_file(out.resolved, in.resolved)) return;
  throw InputError(out.path, out.option + " would write over " +
                                 (in.path == out.path ? std::string("a file") : "'" + in.path + "', a file") +
                                 " this command reads: name another file");
}

void OutputFiles::input(const std::string& path) {
  std::error_code ec;
  if (!path.empty() && io::is_file_series_pattern(path)) {  // a numbered series: each of its steps is read
    try {
      for (const io::TimeStep& step : io::read_time_series(path).steps) input(step.file);
    } catch (const InputError&) {  // a series that cannot be listed is refused when it is loaded
    }
    return;
  }
  if (path.empty() || !fs::exists(path, ec)) return;
  Input in{path, resolved_path(path)};
  // Once each: a collection may name itself or a file already read (it would recurse without end).
  for (const Input& known : inputs_)
    if (same_file(known.resolved, in.resolved)) return;
  for (const Output& out : outputs_) check_not_input(out, in);
  inputs_.push_back(in);
  for (const std::string& file : referenced_files(path)) input(file);
}

void OutputFiles::output(const std::string& path, const std::string& option, const std::vector<std::string>& extensions) {
  // What would be lost first: an input, or another output.
  Output out{path, option, resolved_path(path), {}, false};
  for (const Input& in : inputs_) check_not_input(out, in);
  for (const Output& other : outputs_)
    if (same_file(out.resolved, other.resolved)) throw InputError(path, option + " and " + other.option + " name the same file");
  const std::string ext = lower_extension(path);
  if (std::find(extensions.begin(), extensions.end(), ext) == extensions.end()) {
    std::string list;
    for (size_t i = 0; i < extensions.size(); ++i) list += (i == 0 ? "" : i + 1 == extensions.size() ? " or " : ", ") + extensions[i];
    throw InputError(path, option + " writes " + list + " files" + (ext.empty() ? std::string(" (this name has no extension)") : ", not " + ext));
  }
  std::error_code ec;
  const fs::file_status status = fs::status(path, ec);
  if (fs::is_directory(status)) throw InputError(path, "is a folder: " + option + " needs a file name");
  if (fs::exists(status) && !fs::is_regular_file(status))
    throw InputError(path, "is not a regular file: " + option + " replaces regular files only");
  // By the permission bits, not access(): root may write anything, but a file its owner made
  // read-only is one they meant to keep.
  if (fs::exists(status) && (status.permissions() & (fs::perms::owner_write | fs::perms::group_write | fs::perms::others_write)) == fs::perms::none)
    throw InputError(path, "is read-only: " + option + " does not replace it (make it writable, or choose another name)");
  const fs::path dir = fs::path(out.resolved).parent_path();
  const fs::file_status dir_status = fs::status(dir, ec);
  if (!fs::exists(dir_status)) throw InputError(path, "the folder '" + folder_of(path) + "' does not exist");
  if (!fs::is_directory(dir_status)) throw InputError(path, "'" + folder_of(path) + "' is not a folder");
  Output& added = outputs_.emplace_back(std::move(out));
  try {
    create_temporary(path, added.resolved, added.temporary);
  } catch (...) {
    if (!added.temporary.empty()) {
      ::unlink(added.temporary.c_str());
      withdraw(g_temporaries, added.temporary.c_str());
    }
    outputs_.pop_back();
    throw;
  }
}

void OutputFiles::folder(const std::string& path, const std::string& option) {
  std::error_code ec;
  fs::path dir = fs::absolute(path, ec).lexically_normal();
  if (dir.filename().empty()) dir = dir.parent_path();  // "out/" -> "out"
  if (fs::exists(dir, ec)) {
    if (!fs::is_directory(dir, ec)) throw InputError(path, "is not a folder: " + option + " names the folder to write into");
    return;
  }
  std::vector<fs::path> missing;  // innermost first
  for (fs::path q = dir; !q.empty() && !fs::exists(q, ec); q = q.parent_path()) {
    missing.push_back(q);
    if (q == q.parent_path()) break;
  }
  for (auto it = missing.rbegin(); it != missing.rend(); ++it) {
    if (!fs::create_directory(*it, ec) || ec) {
      const bool denied = ec == std::errc::permission_denied || ec == std::errc::operation_not_permitted || ec == std::errc::read_only_file_system;
      throw InputError(path, denied ? "cannot create the folder: its parent is not writable" : "cannot create the folder: " + ec.message());
    }
    folders_.push_back(it->string());
    enroll(g_folders, folders_.back().c_str());
  }
}

void OutputFiles::write(const std::string& path, const std::function<void(const std::string& temporary)>& writer) {
  const auto it = std::find_if(outputs_.begin(), outputs_.end(), [&](const Output& o) { return o.path == path; });
  if (it == outputs_.end()) throw std::logic_error("OutputFiles::write: '" + path + "' was not declared");
  try {
    writer(it->temporary);
  } catch (const InputError& e) {  // the writer names the file it was given: name the user's
    if (e.source() != it->temporary) throw;
    throw of_output(e, it->path);
  }
  it->written = true;
}

void OutputFiles::discard(const std::string& path) {
  const auto it = std::find_if(outputs_.begin(), outputs_.end(), [&](const Output& o) { return o.path == path; });
  if (it == outputs_.end()) return;
  ::unlink(it->temporary.c_str());
  withdraw(g_temporaries, it->temporary.c_str());
  outputs_.erase(it);
}

void OutputFiles::commit() {
  for (const Output& out : outputs_)
    if (!out.written) throw std::logic_error("OutputFiles::commit: " + out.option + " '" + out.path + "' was declared but not written");
  // On the disk before in place: a disk that took the bytes into its cache may still refuse
  // them, and a rename must not put an output whose data are lost over the user's file.
  for (const Output& out : outputs_) {
    try {
      io::sync_file(out.temporary);
    } catch (const InputError& e) {
      throw of_output(e, out.path);
    }
  }
  const HeldSignals held;
  for (Output& out : outputs_) {
    if (std::rename(out.temporary.c_str(), out.resolved.c_str()) != 0)
      throw InputError(out.path, std::string("cannot be written: ") + std::strerror(errno));
    withdraw(g_temporaries, out.temporary.c_str());
    out.temporary.clear();
  }
  committed_ = true;
}

void check_output(const std::string& path, const std::string& option, const std::vector<std::string>& extensions,
                  const std::vector<std::string>& inputs) {
  OutputFiles files;
  for (const std::string& in : inputs) files.input(in);
  files.output(path, option, extensions);
}

}  // namespace prismoid::app
