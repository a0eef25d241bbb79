#pragma once
// The command line's vocabulary, shared by every verb: `--name value` and `--flag` options,
// numbers, vectors, sizes, the camera options, and JSON output helpers. Parse errors throw
// InputError naming the option.
#include <cstdint>
#include <iosfwd>
#include <map>
#include <optional>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

#include <glm/vec3.hpp>
#include <vulkan/vulkan.h>

#include "renderer/timing/frame_timing.hpp"
#include "renderer/vk/instance.hpp"
#include "renderer/vk/timer.hpp"
#include "scene/bounds.hpp"
#include "scene/camera.hpp"

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

// --fovy in degrees, checked to lie in (0, 180); `otherwise` without it.
double parse_fovy(const ParsedArgs& a, double otherwise);
// The camera of --eye/--target/--up/--fovy/--near, framing `bounds` where they are silent.
Camera camera_from(const ParsedArgs& a, const Bounds& bounds);
// The near plane of a camera placed by hand (--eye or --target without --near), from where its
// eye stands: half the nearest depth of the bounds' corners along the viewing axis, at least
// 1/2000 of the bounds' radius (the eye inside or beside the data). The default framing's near
// plane, half its distance to the data's sphere, would cut away what lies nearer to the new eye.
double near_plane_for(const Camera& camera, const Bounds& bounds);
extern const std::vector<std::string> kCameraOptions;
std::vector<std::string> with_camera(std::vector<std::string> v);

// A number as the terminal and the stats files show it: 9 significant digits, null for NaN and
// infinities.
std::string json_number(double v);

// kValidationMessages (with a line on stderr) when the validation layer reported anything.
int validation_exit(const vk::Instance& instance);

// Prints each pass's GPU time ("  NAME: X ms GPU", or "no timestamps") and returns their sum.
double print_pass_times(std::ostream& out, const std::vector<vk::PassTiming>& passes);

// "  SM clock: MIN / MEDIAN / MAX MHz (N samples)" where the clock was sampled; nothing otherwise.
void print_sm_clock(std::ostream& out, const timing::FrameTiming& timing);

// `line` (a help line so far, its text to start where it ends) followed by `text`'s words,
// wrapped at `width` columns, each further line `indent` spaces in; ends in a newline. The one
// word-wrapping of every help text.
std::string wrap_words(std::string line, std::string_view text, size_t indent, size_t width = 100);

// Help lines listing a table: each row's name padded to the longest (of at most 28 characters; a
// longer one has its text on the next line), its text wrapped at `width` under itself. The first line starts two spaces in with `lead` (an option, or empty), padded to
// `indent`; the other rows start at `indent`.
std::string help_table(std::string_view lead, size_t indent, const std::vector<std::pair<std::string, std::string>>& rows,
                       size_t width = 100);

class OutputFiles;
// What every render verb reads and writes, declared before its work (app/common/output_files.hpp):
// reads FILE and a --tf file; writes --output (.png or .pfm), and --stats (.json) and
// --variance (.pfm) where given.
void declare_render_files(OutputFiles& files, const ParsedArgs& a);

}  // namespace prismoid::app
