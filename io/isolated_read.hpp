#pragma once
// Work on untrusted input in a child process, so that no file can take Prismoid down: a
// reader's crash (VTK's and TetGen's included), an allocation without end or a loop without end
// ends the child, and the caller gets an InputError naming the file and what happened.
//
// The child (fork) runs the work under a memory limit and sends its result back over a pipe as
// plain bytes; the parent reads them while it waits, forwards the child's progress reports,
// enforces a time limit, and kills the child when the caller cancels (io::Progress returning
// false, which is also how Ctrl-C arrives). The child dies with its parent
// (PR_SET_PDEATHSIG), so a parent ended by a signal leaves no reader running.
//
// fork() happens in a multithreaded process (the viewer's loader thread, the Vulkan driver's
// threads): the child does only the work, writes the pipe and _exit()s; it runs no destructors
// of the parent's objects, no atexit handlers, and flushes no stdio buffers.
#include <array>
#include <cstdint>
#include <functional>
#include <map>
#include <string>
#include <type_traits>
#include <vector>

#include "io/progress.hpp"
#include "scene/surface_mesh.hpp"
#include "scene/tet_mesh.hpp"

namespace prismoid::io {

struct ChildLimits {
  // Address space the child may map beyond what it inherited from the parent (a process with a
  // Vulkan device maps gigabytes it never touches); 0: no limit.
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

// The child's side of the pipe: values as bytes (trivially copyable ones as they are in memory,
// strings, vectors and maps with a count first, structs through their fields() overload). The
// work writes its result only once the result is complete: an exception after the first byte
// can no longer be reported.
class ResultWriter {
 public:
  explicit ResultWriter(int fd) : fd_(fd) {}
  void bytes(const void* data, size_t count);
  template <typename T>
  void operator()(const T& v);

 private:
  int fd_;
  bool started_ = false;
};

// The parent's side: the same values in the same order. It waits for the bytes while polling,
// so cancelling and the time limit work during the transfer too.
class ChildChannel;
class ResultReader {
 public:
  explicit ResultReader(ChildChannel& channel) : channel_(channel) {}
  void bytes(void* data, size_t count);
  template <typename T>
  void operator()(T& v);

 private:
  ChildChannel& channel_;
};

// Whether this process is an isolated child: work nested in it runs in place.
bool in_isolated_child();

// Runs `work` in a child under job.limits. `work` gets a Progress that forwards to the parent's
// `progress` (it always returns true: cancelling kills the child) and writes its result into the
// ResultWriter; `receive` reads it in the parent. An InputError, Cancelled or other exception
// from `work` is thrown again in the parent, with its source and text; a child that crashes, runs
// out of memory or time, or is cancelled is an InputError(job.source, ...) or Cancelled(job.source).
void run_in_child(const ChildJob& job, const Progress& progress, const std::function<void(ResultWriter&, const Progress&)>& work,
                  const std::function<void(ResultReader&)>& receive);

// The common case: a function returning a value that ResultWriter/ResultReader can carry.
template <typename T, typename Work>
T run_isolated(const ChildJob& job, const Progress& progress, Work&& work) {
  if (in_isolated_child()) return work(progress);
  T result{};
  run_in_child(
      job, progress, [&](ResultWriter& out, const Progress& p) { out(static_cast<const T&>(work(p))); },
      [&](ResultReader& in) { in(result); });
  return result;
}

// ---- carrying values --------------------------------------------------------------------------

template <typename T>
struct IsVector : std::false_type {};
template <typename T, typename A>
struct IsVector<std::vector<T, A>> : std::true_type {};
template <typename T>
struct IsMap : std::false_type {};
template <typename K, typename V, typename C, typename A>
struct IsMap<std::map<K, V, C, A>> : std::true_type {};

template <typename T>
void ResultWriter::operator()(const T& v) {
  if constexpr (std::is_same_v<T, std::string>) {
    (*this)(uint64_t(v.size()));
    bytes(v.data(), v.size());
  } else if constexpr (IsVector<T>::value) {
    (*this)(uint64_t(v.size()));
    if constexpr (std::is_trivially_copyable_v<typename T::value_type>) bytes(v.data(), v.size() * sizeof(typename T::value_type));
    else
      for (const auto& e : v) (*this)(e);
  } else if constexpr (IsMap<T>::value) {
    (*this)(uint64_t(v.size()));
    for (const auto& [key, value] : v) {
      (*this)(key);
      (*this)(value);
    }
  } else if constexpr (std::is_trivially_copyable_v<T>) {
    bytes(&v, sizeof v);
  } else {
    fields(*this, v);  // found by argument-dependent lookup beside the type
  }
}

template <typename T>
void ResultReader::operator()(T& v) {
  if constexpr (std::is_same_v<T, std::string>) {
    uint64_t n = 0;
    (*this)(n);
    v.resize(size_t(n));
    bytes(v.data(), v.size());
  } else if constexpr (IsVector<T>::value) {
    uint64_t n = 0;
    (*this)(n);
    v.resize(size_t(n));
    if constexpr (std::is_trivially_copyable_v<typename T::value_type>) bytes(v.data(), v.size() * sizeof(typename T::value_type));
    else
      for (auto& e : v) (*this)(e);
  } else if constexpr (IsMap<T>::value) {
    uint64_t n = 0;
    (*this)(n);
    v.clear();
    for (uint64_t i = 0; i < n; ++i) {
      typename T::key_type key{};
      typename T::mapped_type value{};
      (*this)(key);
      (*this)(value);
      v.emplace(std::move(key), std::move(value));
    }
  } else if constexpr (std::is_trivially_copyable_v<T>) {
    bytes(&v, sizeof v);
  } else {
    fields(*this, v);
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
