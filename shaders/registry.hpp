#pragma once
// Compiled SPIR-V of every shader under shaders/, embedded at build time.
#include <cstdint>
#include <span>
#include <string_view>

namespace prismoid::shaders {
// `name` is the source path relative to shaders/, e.g. "volume/interval.mesh".
// Throws std::invalid_argument for an unknown name.
std::span<const uint32_t> spirv(std::string_view name);
}
