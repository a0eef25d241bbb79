#include "app/common/backend_cache.hpp"

#include <cerrno>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <fcntl.h>
#include <iostream>
#include <sys/stat.h>
#include <system_error>
#include <unistd.h>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "io/file_write.hpp"
#include "renderer/vk/device.hpp"
#include "renderer/volume/volume_backends.hpp"
#include "scene/input_error.hpp"

namespace prismoid::app {

namespace {

namespace fs = std::filesystem;

std::string env(const char* name) {
  const char* v = std::getenv(name);
  return v ? std::string(v) : std::string();
}

// A cache holds a few hundred bytes per device; anything near this is not one.
constexpr off_t kMaxCacheBytes = 1 << 20;

// The cache's calibrations by device key; empty (with a warning) when the file is unreadable.
// `replaceable` is false when the path holds something other than a regular file (a folder, a
// FIFO, a device, a link to one): that is not ours to replace. Opened without blocking and
// checked before reading, so a FIFO neither hangs nor /dev/zero fills memory.
nlohmann::json read_cache(const fs::path& path, bool& replaceable) {
  replaceable = true;
  std::error_code ec;
  if (!fs::exists(fs::symlink_status(path, ec))) return nlohmann::json::object();
  const int fd = ::open(path.c_str(), O_RDONLY | O_NONBLOCK | O_CLOEXEC | O_NOCTTY);
  struct stat st {};
  if (fd < 0 || ::fstat(fd, &st) != 0 || !S_ISREG(st.st_mode)) {
    if (fd >= 0) ::close(fd);
    replaceable = fd < 0 && fs::is_regular_file(fs::status(path, ec));
    std::cerr << "prismoid: warning: the backend cache " << path.string()
              << (replaceable ? " cannot be read" : " is not a regular file (a folder, a FIFO or a device?)")
              << "; calibrating again" << (replaceable ? "" : ", and the calibration is not kept") << "\n";
    return nlohmann::json::object();
  }
  std::string text;
  if (st.st_size <= kMaxCacheBytes) {
    text.resize(size_t(st.st_size));
    size_t done = 0;
    while (done < text.size()) {
      const ssize_t n = ::read(fd, text.data() + done, text.size() - done);
      if (n <= 0 && !(n < 0 && errno == EINTR)) break;
      if (n > 0) done += size_t(n);
    }
    text.resize(done);
  }
  ::close(fd);
  if (st.st_size > kMaxCacheBytes) {
    std::cerr << "prismoid: warning: the backend cache " << path.string() << " is " << st.st_size
              << " bytes, too large to be one; calibrating again and replacing it\n";
    return nlohmann::json::object();
  }
  nlohmann::json j = nlohmann::json::parse(text, nullptr, /*allow_exceptions=*/false);
  if (!j.is_object()) {
    std::cerr << "prismoid: warning: the backend cache " << path.string()
              << " is not a JSON object of calibrations; calibrating again and replacing it\n";
    return nlohmann::json::object();
  }
  return j;
}

// A frame time a calibration can measure, in ms: a microsecond to 1000 s. The file is anyone's
// to edit; 1e-320 or 0 would otherwise decide every later run ("infx faster", or mesh for ever).
bool plausible_ms(double ms) { return std::isfinite(ms) && ms >= 1e-3 && ms <= 1e6; }

bool read_entry(const nlohmann::json& e, frame::BackendCalibration& c) {
  if (!e.is_object()) return false;
  // Every GPU backend the table has now: an entry from before a backend joined it is measured again.
  std::vector<std::string> keys;
  for (const volume::VolumeBackendInfo* b : volume::volume_backend_table())
    if (b->gpu()) keys.push_back(std::string(b->name) + "_ms");
  for (const std::string& key : keys)
    if (!e.contains(key) || !e[key].is_number() || !plausible_ms(e[key].get<double>())) return false;
  for (const char* key : {"cells", "width", "height"})
    if (!e.contains(key) || !e[key].is_number_unsigned() || e[key].get<uint64_t>() == 0 || e[key].get<uint64_t>() > (uint64_t(1) << 32))
      return false;
  for (const std::string& key : keys) c.ms[key.substr(0, key.size() - 3)] = e[key].get<double>();
  c.cells = e["cells"].get<uint64_t>();
  c.width = e["width"].get<uint32_t>();
  c.height = e["height"].get<uint32_t>();
  return true;
}

// Written beside the target under a fresh name (mkstemp: created, never followed, so a link
// planted where a fixed name would be cannot redirect the write) and renamed over it: a reader
// never sees half a file, and two processes calibrating at once leave one whole file.
void write_cache(const fs::path& path, const nlohmann::json& j) {
  std::error_code ec;
  fs::create_directories(path.parent_path(), ec);
  std::string tmp = path.string() + ".partial-XXXXXX";
  const int fd = ::mkstemp(tmp.data());
  if (fd < 0) {
    std::cerr << "prismoid: warning: cannot write the backend cache " << path.string() << ": " << std::strerror(errno)
              << "; the calibration is not kept\n";
    return;
  }
  ::close(fd);
  try {
    io::write_file(tmp, j.dump(2) + "\n");
  } catch (const InputError& e) {
    fs::remove(tmp, ec);
    std::cerr << "prismoid: warning: " << e.what() << "; the calibration is not kept\n";
    return;
  }
  if (std::rename(tmp.c_str(), path.c_str()) != 0) {
    const std::string reason = std::strerror(errno);
    fs::remove(tmp, ec);
    std::cerr << "prismoid: warning: cannot replace the backend cache " << path.string() << ": " << reason << "\n";
  }
}

}  // namespace

fs::path backend_cache_path() {
  if (const std::string p = env("PRISMOID_BACKEND_CACHE"); !p.empty()) return p;
  if (const std::string x = env("XDG_CACHE_HOME"); !x.empty()) return fs::path(x) / "prismoid" / "backends.json";
  if (const std::string h = env("HOME"); !h.empty()) return fs::path(h) / ".cache" / "prismoid" / "backends.json";
  return {};
}

frame::BackendChoice auto_backend(const vk::Device& device, const fs::path& cache, bool* from_cache) {
  const std::string key = frame::device_key(device);
  bool replaceable = true;
  nlohmann::json all = cache.empty() ? nlohmann::json::object() : read_cache(cache, replaceable);
  frame::BackendCalibration c;
  c.device_key = key;
  const bool listed = all.contains(key);
  if (listed && !read_entry(all[key], c))
    std::cerr << "prismoid: warning: the backend cache " << cache.string()
              << " holds no plausible numbers for this device's entry; calibrating again\n";
  else if (listed) {
    if (from_cache) *from_cache = true;
    frame::BackendChoice choice = frame::choose_backend(c);
    choice.reason += ", calibrated earlier (" + cache.string() + ")";
    return choice;
  }
  if (from_cache) *from_cache = false;
  c = frame::calibrate_backends(device);
  if (!cache.empty() && replaceable) {
    nlohmann::json entry = {{"cells", c.cells}, {"width", c.width}, {"height", c.height}};
    for (const auto& [name, ms] : c.ms) entry[name + "_ms"] = ms;
    all[key] = entry;
    write_cache(cache, all);
  }
  return frame::choose_backend(c);
}

void resolve_auto_backend(frame::FrameSettings& settings, const vk::Device& device) {
  if (settings.resolve.shared_vertices) {
    settings.backend = frame::IntervalBackend::Mesh;
    settings.backend_reason = "auto: mesh shaders, as --shared-vertices groups cells into mesh-shader workgroups";
    return;
  }
  const frame::BackendChoice choice = auto_backend(device, backend_cache_path());
  settings.backend = choice.backend;
  settings.backend_reason = choice.reason;
}

}  // namespace prismoid::app
