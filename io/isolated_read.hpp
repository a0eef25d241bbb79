#pragma once
// Work on untrusted input in a child process, so that no file can take Prismoid down: a
// reader's crash (VTK's and TetGen's included), an allocation without end or a loop without end
// ends the child, and the caller gets an InputError naming the file and what happened.
//
// No reader is a bare fork() of the caller. The caller is multithreaded (the viewer's loader, the
// Vulkan driver, TBB's workers under VTK and OpenVDB), and a fork copies only the forking thread,
// so a lock or counter another thread held at that instant stays held in the copy for ever: a TBB
// worker winding down left VTK's first parallel loop in the child waiting without end (issue 40).
// Instead each calling thread starts one fresh copy of this same executable (fork, then at once
// exec of /proc/self/exe), the reader host, which is single-threaded and runs no work; each
// reader is a fork of the host. The reader finds its work by name in a table every ChildWork
// adds itself to when the program starts.
//
// So every executable that isolates work calls serve_isolated_child(argc, argv) first in main();
// run_in_child refuses to start a child in one that did not.
//
// The request (the path and options) goes to the reader and the result comes back over one
// socket, as plain bytes; the parent reads while it waits, forwards the reader's progress
// reports, enforces a time limit, and kills the reader when the caller cancels (io::Progress
// returning false, which is also how Ctrl-C arrives). Readers die with their host and the host
// with the thread that started it (PR_SET_PDEATHSIG), so a parent ended by a signal leaves no
// reader running.
#include <array>
#include <cstdint>
#include <functional>
#include <map>
#include <string>
#include <string_view>
#include <type_traits>
#include <vector>

#include "io/progress.hpp"
#include "scene/surface_mesh.hpp"
#include "scene/tet_mesh.hpp"

namespace prismoid::io {

struct ChildLimits {
  // Address space the reader may map beyond what it maps as it starts (the program and its
  // libraries; the caller's own mappings, gigabytes with a Vulkan device, never count); 0: no limit.
  uint64_t memory_bytes = 0;
  double seconds = 0.0;  // wall-clock time; 0: no limit
};

// The memory a child may add: three quarters of the machine's physical memory. An honest read
// that needs more would leave too little for the parent, which receives the result, and would
// push the machine into swap; a hostile one is stopped before the machine suffers.
uint64_t child_memory_budget();

// The limits of a reader child on `path`, from the bytes the file can expand to: its size, or
// 1032 times its size for formats that may be compressed (zlib's largest ratio; XML
// .vtu/.vtp/.vti/.vtm/.pvtu, .vdb, .mha/.mhd, .inr.gz), counting the files a .vtm, .pvtu or .mhd
// names.
// - Time: kReadBaseSeconds plus kReadSecondsPerMiB per MiB. VTK reads and converts far faster
//   than 1 MiB/s, so an honest file never comes near it; it ends a reader that loops.
// - Memory: kReadBaseMemory plus, per byte, kReadMemoryPerByte for meshes and surfaces or
//   kReadMemoryPerVoxelByte for image volumes and .vdb grids, at most child_memory_budget(). A
//   mesh's cells take a few times their bytes in VTK and as tetrahedra (a hexahedron of 73 bytes
//   becomes six tetrahedra, about 560 bytes in all); a voxel of one byte becomes a point and six
//   tetrahedra, about 200 bytes. More than that is a size in the file that should not be believed.
inline constexpr double kReadBaseSeconds = 60.0;
inline constexpr double kReadSecondsPerMiB = 1.0;
inline constexpr uint64_t kReadBaseMemory = uint64_t(512) << 20;
inline constexpr uint64_t kReadMemoryPerByte = 64;
inline constexpr uint64_t kReadMemoryPerVoxelByte = 256;
inline constexpr double kMaxCompressionRatio = 1032.0;
ChildLimits read_limits(const std::string& path);

// What the parent says about the child, for the caller's messages.
struct ChildJob {
  std::string source;                                   // named in every error (the file)
  std::string worker = "the reader";                    // "the reader crashed (SIGSEGV): ..."
  std::string crash_hint = "the file is corrupt or truncated";
  std::string memory_hint = "the file is corrupt, or too large for this machine";
  std::string stage = "reading";                        // reported while no progress came from the child
  double waiting_fraction = 0.0;                        // ... with this fraction (-1: unknown)
  ChildLimits limits;
};

// A job reading `path`: named in errors, under read_limits(path).
ChildJob read_job(const std::string& path);

// Values as bytes, both ways: trivially copyable ones as they are in memory, strings, vectors
// and maps with a count first, structs through their fields() overload (found beside the type).
// Derived supplies bytes(data, count).
template <typename Derived>
class Encoder {
 public:
  template <typename T>
  void operator()(const T& v);
};
template <typename Derived>
class Decoder {
 public:
  template <typename T>
  void operator()(T& v);
};

// The child's side of the result: written only once the result is complete (an exception after
// the first byte can no longer be reported).
class ResultWriter : public Encoder<ResultWriter> {
 public:
  explicit ResultWriter(int fd) : fd_(fd) {}
  void bytes(const void* data, size_t count);

 private:
  int fd_;
  bool started_ = false;
};

// The parent's side: the same values in the same order. It waits for the bytes while polling,
// so cancelling and the time limit work during the transfer too.
class ChildChannel;
class ResultReader : public Decoder<ResultReader> {
 public:
  explicit ResultReader(ChildChannel& channel) : channel_(channel) {}
  void bytes(void* data, size_t count);

 private:
  ChildChannel& channel_;
};

// The request, parent to child: written while polling as the reader is, read by the child
// before it works.
class RequestWriter : public Encoder<RequestWriter> {
 public:
  explicit RequestWriter(ChildChannel& channel) : channel_(channel) {}
  void bytes(const void* data, size_t count);

 private:
  ChildChannel& channel_;
};
class RequestReader : public Decoder<RequestReader> {
 public:
  explicit RequestReader(int fd) : fd_(fd) {}
  void bytes(void* data, size_t count);

 private:
  int fd_;
};

// How the child serves one kind of work: reads the request, does the work, writes the result.
using ChildServe = std::function<void(RequestReader&, ResultWriter&, const Progress&)>;

// Adds a kind of work to this program's table (ChildWork does it); a name used twice or longer
// than 63 characters is a programming error (std::logic_error, at start-up).
void register_child_work(std::string_view name, ChildServe serve);

// The first line of main() in every executable that isolates work: in a reader host or a reader
// started by run_in_child it does that job and exits the process; anywhere else it records that
// this executable can serve children and returns.
void serve_isolated_child(int argc, char** argv);

// Whether this process is an isolated child: work nested in it runs in place.
bool in_isolated_child();

// The largest peak resident memory of a reader this process has run, in bytes (the readers are
// not its children but its host's, so getrusage(RUSAGE_CHILDREN) does not see them).
uint64_t largest_reader_memory_bytes();

// Runs the registered work `name` in a reader under job.limits. `send` writes the request;
// the work gets a Progress that forwards to the parent's `progress` (it always returns true:
// cancelling kills the child) and writes its result; `receive` reads it in the parent. An
// InputError, Cancelled or other exception from the work is thrown again in the parent, with its
// source and text; a child that crashes, runs out of memory or time, or is cancelled is an
// InputError(job.source, ...) or Cancelled(job.source).
void run_in_child(const ChildJob& job, const Progress& progress, std::string_view name, const std::function<void(RequestWriter&)>& send,
                  const std::function<void(ResultReader&)>& receive);

// A kind of work a child can do: Result function(const Request&, const Progress&), where both
// types can be carried (above). Define it at namespace scope (static storage) so that it is in
// the table before main() runs, in the child as in the parent:
//   const ChildWork<ReadRequest, TetMesh> kReadMesh("read-mesh", [](const ReadRequest& r, const Progress& p) { ... });
//   TetMesh mesh = kReadMesh(read_job(path), progress, request);
// In an isolated child the function runs in place.
template <typename Request, typename Result>
class ChildWork {
 public:
  using Function = Result (*)(const Request&, const Progress&);
  ChildWork(std::string_view name, Function function) : name_(name), function_(function) {
    register_child_work(name, [function](RequestReader& in, ResultWriter& out, const Progress& progress) {
      Request request{};
      in(request);
      out(static_cast<const Result&>(function(request, progress)));
    });
  }
  ChildWork(const ChildWork&) = delete;
  ChildWork& operator=(const ChildWork&) = delete;

  Result operator()(const ChildJob& job, const Progress& progress, const Request& request) const {
    if (in_isolated_child()) return function_(request, progress);
    Result result{};
    run_in_child(
        job, progress, name_, [&](RequestWriter& out) { out(request); }, [&](ResultReader& in) { in(result); });
    return result;
  }

 private:
  std::string_view name_;
  Function function_;
};

// ---- carrying values --------------------------------------------------------------------------

template <typename T>
struct IsVector : std::false_type {};
template <typename T, typename A>
struct IsVector<std::vector<T, A>> : std::true_type {};
template <typename T>
struct IsMap : std::false_type {};
template <typename K, typename V, typename C, typename A>
struct IsMap<std::map<K, V, C, A>> : std::true_type {};

template <typename Derived>
template <typename T>
void Encoder<Derived>::operator()(const T& v) {
  auto& self = static_cast<Derived&>(*this);
  if constexpr (std::is_same_v<T, std::string>) {
    self(uint64_t(v.size()));
    self.bytes(v.data(), v.size());
  } else if constexpr (IsVector<T>::value) {
    self(uint64_t(v.size()));
    if constexpr (std::is_trivially_copyable_v<typename T::value_type>) self.bytes(v.data(), v.size() * sizeof(typename T::value_type));
    else
      for (const auto& e : v) self(e);
  } else if constexpr (IsMap<T>::value) {
    self(uint64_t(v.size()));
    for (const auto& [key, value] : v) {
      self(key);
      self(value);
    }
  } else if constexpr (std::is_trivially_copyable_v<T>) {
    self.bytes(&v, sizeof v);
  } else {
    fields(self, v);  // found by argument-dependent lookup beside the type
  }
}

template <typename Derived>
template <typename T>
void Decoder<Derived>::operator()(T& v) {
  auto& self = static_cast<Derived&>(*this);
  if constexpr (std::is_same_v<T, std::string>) {
    uint64_t n = 0;
    self(n);
    v.resize(size_t(n));
    self.bytes(v.data(), v.size());
  } else if constexpr (IsVector<T>::value) {
    uint64_t n = 0;
    self(n);
    v.resize(size_t(n));
    if constexpr (std::is_trivially_copyable_v<typename T::value_type>) self.bytes(v.data(), v.size() * sizeof(typename T::value_type));
    else
      for (auto& e : v) self(e);
  } else if constexpr (IsMap<T>::value) {
    uint64_t n = 0;
    self(n);
    v.clear();
    for (uint64_t i = 0; i < n; ++i) {
      typename T::key_type key{};
      typename T::mapped_type value{};
      self(key);
      self(value);
      v.emplace(std::move(key), std::move(value));
    }
  } else if constexpr (std::is_trivially_copyable_v<T>) {
    self.bytes(&v, sizeof v);
  } else {
    fields(self, v);
  }
}

// fields(s, v) lists a struct's members for both directions: M is T (reading) or const T (writing).
template <typename M, typename T>
concept Carries = std::is_same_v<std::remove_const_t<M>, T>;

template <typename S, Carries<TetMesh> M>
void fields(S& s, M& m) {
  s(m.name);
  s(m.points);
  s(m.tets);
  s(m.cell_extinction);
  s(m.point_extinction);
  s(m.point_scalars);
  s(m.cell_scalars);
}
template <typename S, Carries<SurfaceArray> M>
void fields(S& s, M& a) {
  s(a.name);
  s(a.components);
  s(a.values);
}
template <typename S, Carries<SurfaceMesh> M>
void fields(S& s, M& m) {
  s(m.name);
  s(m.points);
  s(m.triangles);
  s(m.point_arrays);
  s(m.cell_arrays);
}

}  // namespace prismoid::io
