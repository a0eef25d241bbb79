#include "app/common/backend_cache.hpp"

#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <iostream>
#include <sstream>
#include <system_error>

#include <nlohmann/json.hpp>

#include "renderer/vk/device.hpp"

namespace prismoid::app {

namespace {

namespace fs = std::filesystem;

std::string env(const char* name) {
  const char* v = std::getenv(name);
  return v ? std::string(v) : std::string();
}

// The cache's calibrations by device key; empty (with a warning) when the file is unreadable.
nlohmann::json read_cache(const fs::path& path) {
  std::error_code ec;
  if (!fs::exists(path, ec)) return nlohmann::json::object();
  std::ifstream in(path, std::ios::binary);
  if (!in) {
    std::cerr << "prismoid: warning: cannot read the backend cache " << path.string() << "; calibrating again\n";
    return nlohmann::json::object();
  }
  std::stringstream text;
  text << in.rdbuf();
  nlohmann::json j = nlohmann::json::parse(text.str(), nullptr, /*allow_exceptions=*/false);
  if (!j.is_object()) {
    std::cerr << "prismoid: warning: the backend cache " << path.string()
              << " is not a JSON object of calibrations; calibrating again and replacing it\n";
    return nlohmann::json::object();
  }
  return j;
}

bool read_entry(const nlohmann::json& e, frame::BackendCalibration& c) {
  if (!e.is_object()) return false;
  for (const char* key : {"mesh_ms", "compute_ms", "cells", "width", "height"})
    if (!e.contains(key) || !e[key].is_number()) return false;
  c.mesh_ms = e["mesh_ms"].get<double>();
  c.compute_ms = e["compute_ms"].get<double>();
  c.cells = e["cells"].get<uint64_t>();
  c.width = e["width"].get<uint32_t>();
  c.height = e["height"].get<uint32_t>();
  return true;
}

// Written beside the target and renamed over it: a reader never sees half a file, and two
// processes calibrating at once leave one whole file.
void write_cache(const fs::path& path, const nlohmann::json& j) {
  std::error_code ec;
  fs::create_directories(path.parent_path(), ec);
  const fs::path tmp = path.string() + ".partial";
  {
    std::ofstream out(tmp, std::ios::binary | std::ios::trunc);
    out << j.dump(2) << "\n";
    if (!out) {
      fs::remove(tmp, ec);
      std::cerr << "prismoid: warning: cannot write the backend cache " << path.string() << "; the calibration is not kept\n";
      return;
    }
  }
  fs::rename(tmp, path, ec);
  if (ec) {
    fs::remove(tmp, ec);
    std::cerr << "prismoid: warning: cannot replace the backend cache " << path.string() << ": " << ec.message() << "\n";
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
  nlohmann::json all = cache.empty() ? nlohmann::json::object() : read_cache(cache);
  frame::BackendCalibration c;
  c.device_key = key;
  const bool listed = all.contains(key);
  if (listed && !read_entry(all[key], c))
    std::cerr << "prismoid: warning: the backend cache " << cache.string() << " holds no numbers for this device's entry; calibrating again\n";
  else if (listed) {
    if (from_cache) *from_cache = true;
    frame::BackendChoice choice = frame::choose_backend(c);
    choice.reason += ", calibrated earlier (" + cache.string() + ")";
    return choice;
  }
  if (from_cache) *from_cache = false;
  c = frame::calibrate_backends(device);
  if (!cache.empty()) {
    all[key] = {{"mesh_ms", c.mesh_ms}, {"compute_ms", c.compute_ms}, {"cells", c.cells}, {"width", c.width}, {"height", c.height}};
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
