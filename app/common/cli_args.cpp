#include "app/common/cli_args.hpp"

#include <algorithm>
#include <array>
#include <charconv>
#include <cmath>
#include <iostream>
#include <limits>
#include <sstream>

#include <glm/geometric.hpp>

#include "app/common/exit_code.hpp"
#include "app/common/output_files.hpp"
#include "scene/bounds.hpp"
#include "scene/input_error.hpp"

namespace prismoid::app {

ParsedArgs parse(const std::vector<std::string>& args, size_t first, const std::vector<std::string>& value_options,
                 const std::vector<std::string>& flag_options) {
  ParsedArgs parsed;
  for (size_t i = first; i < args.size(); ++i) {
    const std::string& a = args[i];
    if (a == "--") {  // the end of the options: what follows are files, even those that start with --
      parsed.files.insert(parsed.files.end(), args.begin() + std::ptrdiff_t(i) + 1, args.end());
      break;
    }
    if (a.rfind("--", 0) == 0) {
      std::string name = a.substr(2), value;
      bool inline_value = false;
      if (auto eq = name.find('='); eq != std::string::npos) {
        value = name.substr(eq + 1);
        name = name.substr(0, eq);
        inline_value = true;
      }
      if (std::find(flag_options.begin(), flag_options.end(), name) != flag_options.end()) {
        parsed.flags[name] = true;
      } else if (std::find(value_options.begin(), value_options.end(), name) != value_options.end()) {
        if (!inline_value) {
          if (i + 1 >= args.size()) throw InputError("--" + name, "needs a value");
          value = args[++i];
        }
        parsed.values[name] = value;
      } else {
        throw InputError(a, "unknown option (see --help)");
      }
    } else {
      parsed.files.push_back(a);
    }
  }
  return parsed;
}

double parse_double(const std::string& option, const std::string& text) {
  double v = 0.0;
  auto [ptr, ec] = std::from_chars(text.data(), text.data() + text.size(), v);
  if (ec != std::errc() || ptr != text.data() + text.size() || !std::isfinite(v))
    throw InputError("--" + option, "'" + text + "' is not a finite number");
  return v;
}

uint32_t parse_uint(const std::string& option, const std::string& text) {
  uint32_t v = 0;
  auto [ptr, ec] = std::from_chars(text.data(), text.data() + text.size(), v);
  if (ec == std::errc::result_out_of_range && ptr == text.data() + text.size())
    throw InputError("--" + option, "'" + text + "' is too large (at most " + std::to_string(UINT32_MAX) + ")");
  if (ec != std::errc() || ptr != text.data() + text.size()) throw InputError("--" + option, "'" + text + "' is not a whole number");
  return v;
}

glm::dvec3 parse_vec3(const std::string& option, const std::string& text) {
  std::array<double, 3> v{};
  size_t start = 0;
  for (int i = 0; i < 3; ++i) {
    size_t end = text.find(',', start);
    if ((i < 2) != (end != std::string::npos)) throw InputError("--" + option, "expects three numbers x,y,z, got '" + text + "'");
    v[i] = parse_double(option, text.substr(start, end == std::string::npos ? std::string::npos : end - start));
    start = end + 1;
  }
  return {v[0], v[1], v[2]};
}

VkExtent2D parse_size(const std::string& text) {
  const auto x = text.find('x');
  if (x == std::string::npos) throw InputError("--size", "expects WxH, e.g. 800x600, got '" + text + "'");
  const uint32_t w = parse_uint("size", text.substr(0, x)), h = parse_uint("size", text.substr(x + 1));
  if (w == 0 || h == 0 || w > 16384 || h > 16384) throw InputError("--size", "each side must be between 1 and 16384 pixels");
  return {w, h};
}

std::optional<uint32_t> parse_device(const ParsedArgs& a) {
  if (!a.has("device")) return std::nullopt;
  return parse_uint("device", a.values.at("device"));
}

double parse_fovy(const ParsedArgs& a, double otherwise) {
  if (!a.has("fovy")) return otherwise;
  const double fovy = parse_double("fovy", a.values.at("fovy"));
  // Checked before the camera is framed with it: at 0 degrees the framing distance is infinite.
  if (!(fovy > 0.0 && fovy < 180.0))
    throw InputError("--fovy", "'" + a.values.at("fovy") + "' degrees: the vertical field of view must lie strictly between 0 and 180 degrees");
  return fovy;
}

Camera camera_from(const ParsedArgs& a, const Bounds& bounds) {
  Camera c = fit_camera(bounds, parse_fovy(a, 40.0));
  if (a.has("eye")) c.eye = parse_vec3("eye", a.values.at("eye"));
  if (a.has("target")) c.target = parse_vec3("target", a.values.at("target"));
  if (a.has("up")) c.up = parse_vec3("up", a.values.at("up"));
  if (a.has("near")) c.near_distance = parse_double("near", a.values.at("near"));
  else if (a.has("eye") || a.has("target")) c.near_distance = near_plane_for(c, bounds);
  validate(c);
  return c;
}

double near_plane_for(const Camera& camera, const Bounds& bounds) {
  const glm::dvec3 forward = glm::normalize(camera.target - camera.eye);
  double nearest = std::numeric_limits<double>::infinity();
  for (int corner = 0; corner < 8; ++corner) {
    const glm::dvec3 p{corner & 1 ? bounds.max.x : bounds.min.x, corner & 2 ? bounds.max.y : bounds.min.y,
                       corner & 4 ? bounds.max.z : bounds.min.z};
    nearest = std::min(nearest, glm::dot(p - camera.eye, forward));
  }
  const double r = bounds.radius();
  const double floor = (r > 0.0 && std::isfinite(r) ? r : 1.0) * 1e-3;
  const double near = 0.5 * std::max(nearest, floor);
  // Finite and positive whatever the input (validate() then checks the rest of the camera).
  return std::isfinite(near) && near > 0.0 ? near : camera.near_distance;
}

const std::vector<std::string> kCameraOptions = {"eye", "target", "up", "fovy", "near"};

std::vector<std::string> with_camera(std::vector<std::string> v) {
  v.insert(v.end(), kCameraOptions.begin(), kCameraOptions.end());
  return v;
}

std::string json_number(double v) {
  if (!std::isfinite(v)) return "null";
  std::ostringstream s;
  s.precision(9);
  s << v;
  return s.str();
}

double print_pass_times(std::ostream& out, const std::vector<vk::PassTiming>& passes) {
  double total = 0.0;
  for (const auto& p : passes) {
    out << "  " << p.name << ": " << (std::isfinite(p.gpu_ms) ? json_number(p.gpu_ms) + " ms" : "no timestamps") << " GPU\n";
    total += p.gpu_ms;
  }
  return total;
}

void declare_render_files(OutputFiles& files, const ParsedArgs& a) {
  for (const std::string& file : a.files) files.input(file);
  if (a.has("tf")) files.input(a.values.at("tf"));
  if (a.has("depth-limit")) files.input(a.values.at("depth-limit"));
  if (a.has("output")) files.output(a.values.at("output"), "--output", kImageExtensions);
  if (a.has("stats")) files.output(a.values.at("stats"), "--stats", {".json"});
  if (a.has("variance")) files.output(a.values.at("variance"), "--variance", {".pfm"});
}

int validation_exit(const vk::Instance& instance) {
  const size_t n = instance.validation_log().count();
  if (n == 0) return kOk;
  std::cerr << "prismoid: the validation layer reported " << n << " message(s)\n";
  return kValidationMessages;
}

void print_sm_clock(std::ostream& out, const timing::FrameTiming& timing) {
  if (!timing.sm_clock) return;
  const timing::ClockSpread& c = *timing.sm_clock;
  out << "  SM clock: " << json_number(c.min_mhz) << " / " << json_number(c.median_mhz) << " / " << json_number(c.max_mhz)
      << " MHz (min / median / max of " << c.samples << (c.samples == 1 ? " sample" : " samples") << ", nvidia-smi)\n";
}

std::string help_table(std::string_view lead, size_t indent, const std::vector<std::pair<std::string, std::string>>& rows,
                       size_t width) {
  // The texts start after the longest name, but no further than kLongestName in: a longer name
  // has its text start on the next line.
  constexpr size_t kLongestName = 28;
  size_t name_width = 0;
  for (const auto& [name, text] : rows)
    if (name.size() <= kLongestName) name_width = std::max(name_width, name.size());
  std::string out;
  const size_t margin = indent + name_width + 2;
  for (const auto& [name, text] : rows) {
    // (append, not +: GCC 12 warns falsely about the + of two temporaries, -Warray-bounds)
    std::string line = out.empty() ? std::string("  ").append(lead).append(indent - 2 - lead.size(), ' ') : std::string(indent, ' ');
    line.append(name);
    if (name.size() > name_width) line.append("\n").append(margin, ' ');
    else line.append(name_width + 2 - name.size(), ' ');
    out.append(wrap_words(std::move(line), text, margin, width));
  }
  return out;
}

std::string wrap_words(std::string line, std::string_view text, size_t indent, size_t width) {
  const size_t last_break = line.rfind('\n');
  size_t column = last_break == std::string::npos ? line.size() : line.size() - last_break - 1;
  std::istringstream words{std::string(text)};
  bool first = true;
  for (std::string word; words >> word; first = false) {
    if (!first && column + 1 + word.size() > width) {
      line.append("\n").append(indent, ' ');
      column = indent;
    } else if (!first) {
      line += ' ';
      ++column;
    }
    line += word;
    column += word.size();
  }
  return line + "\n";
}

}  // namespace prismoid::app
