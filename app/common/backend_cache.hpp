#pragma once
// `--volume-backend auto` across runs: each device's calibration (frame/backend_choice.hpp) is
// measured once and kept in a small JSON file, so a command pays for it once per device and
// driver, not per run.
#include <filesystem>
#include <string>

#include "renderer/frame/backend_choice.hpp"

namespace prismoid::vk {
class Device;
}  // namespace prismoid::vk

namespace prismoid::app {

// $PRISMOID_BACKEND_CACHE if set, else $XDG_CACHE_HOME/prismoid/backends.json, else
// $HOME/.cache/prismoid/backends.json; empty when none of them is set (nothing is cached).
std::filesystem::path backend_cache_path();

// The backend `auto` picks on `device`: from the cache when it holds this device's calibration,
// else calibrated now and added to the cache. A cache that cannot be read or written is
// reported on stderr (naming the file and the problem) and otherwise ignored: it never stops a
// frame. `from_cache` says which it was.
frame::BackendChoice auto_backend(const vk::Device& device, const std::filesystem::path& cache, bool* from_cache = nullptr);

// Sets settings.backend and settings.backend_reason for --volume-backend auto: the mesh-shader
// backend where the settings use what only it has (tetlets), else auto_backend() with the
// cache at backend_cache_path().
void resolve_auto_backend(frame::FrameSettings& settings, const vk::Device& device);

}  // namespace prismoid::app
