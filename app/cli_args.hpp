#pragma once
// The command line's vocabulary, shared by every verb: `--name value` and `--flag` options,
// numbers, vectors, sizes, the camera options, and JSON output helpers. Parse errors throw
// InputError naming the option.
#include <cstdint>
#include <map>
#include <optional>
#include <string>
#include <vector>

#include <glm/vec3.hpp>
#include <vulkan/vulkan.h>

#include "renderer/vk/instance.hpp"
#include "scene/camera.hpp"
#include "scene/tet_mesh.hpp"

namespace prismoid::app {

// --name value options and --flag options of a verb, in order of appearance.
struct ParsedArgs {
  std::vector<std::string> files;
  std::map<std::string, std::string> values;
  std::map<std::string, bool> flags;
  bool has(const std::string& k) const { return values.count(k) > 0; }
};

// Parses args[first...]: options not listed in value_options or flag_options are errors.
ParsedArgs parse(const std::vector<std::string>& args, size_t first, const std::vector<std::string>& value_options,
                 const std::vector<std::string>& flag_options);

double parse_double(const std::string& option, const std::string& text);
uint32_t parse_uint(const std::string& option, const std::string& text);
glm::dvec3 parse_vec3(const std::string& option, const std::string& text);
VkExtent2D parse_size(const std::string& text);
std::optional<uint32_t> parse_device(const ParsedArgs& a);

// The camera of --eye/--target/--up/--fovy/--near, framing `bounds` where they are silent.
Camera camera_from(const ParsedArgs& a, const Bounds& bounds);
extern const std::vector<std::string> kCameraOptions;
std::vector<std::string> with_camera(std::vector<std::string> v);

std::string json_escape(const std::string& s);
std::string json_number(double v);  // null for NaN and infinities

// kValidationMessages (with a line on stderr) when the validation layer reported anything.
int validation_exit(const vk::Instance& instance);

}  // namespace prismoid::app
