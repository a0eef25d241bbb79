#include "app/viewer/viewer_script.hpp"

#include <fstream>
#include <map>
#include <sstream>

#include "app/common/cli_args.hpp"
#include "scene/input_error.hpp"

namespace prismoid::app {

namespace {

// Verbs and their argument counts (-1: any, the rest of the line).
const std::map<std::string, int>& verbs() {
  static const std::map<std::string, int> v = {
      {"key", 1},        {"mode", 1}, {"shadows", 1}, {"quantity", 1},     {"tf", 1},
      {"tf-range", -1},  {"tf-export", 1},     {"tetlet-size", 1},  {"shared-vertices", 1},
      {"preintegration-size", 1}, {"march-step", 1}, {"density-scale", 1}, {"camera", -1},
      {"view", 1},       {"reset", 0},         {"rotate", 2},       {"pan", 2},
      {"zoom", 1},       {"fly", 1},           {"fly-move", 4},     {"fly-look", 2},
      {"ui", 1},         {"screenshot", 1},    {"render", 3},       {"print-camera", 0},
      {"resize", 2},     {"iconify", 0},       {"restore", 0},      {"close", 0},
      {"rss", 0},        {"drag", -1},         {"open", -1},        {"wait-load", -1},
      {"cancel-load", 0}, {"show", 2},         {"active", 1},       {"drop", -1},
      {"compare", 1},    {"compare-mode", 1},
      {"compare-quantity", 1}, {"backend", 1}, {"compare-backend", 1}, {"wait-reference", -1}};
  return v;
}

}  // namespace

std::vector<ScriptCommand> parse_script(const std::string& text, const std::string& source) {
  std::vector<ScriptCommand> commands;
  std::istringstream lines(text);
  uint32_t frame = 0;
  int number = 0;
  for (std::string line; std::getline(lines, line);) {
    ++number;
    if (const auto hash = line.find('#'); hash != std::string::npos) line.resize(hash);
    std::istringstream words(line);
    ScriptCommand c;
    if (!(words >> c.verb)) continue;
    c.where = source + ":" + std::to_string(number);
    for (std::string w; words >> w;) c.args.push_back(w);
    const auto verb_end = line.find(c.verb) + c.verb.size();
    c.rest = line.substr(verb_end);
    if (c.verb == "frame" || c.verb == "wait") {
      if (c.args.size() != 1) throw InputError(c.where, c.verb + " takes one whole number");
      const uint32_t n = parse_uint(c.verb, c.args[0]);
      frame = c.verb == "frame" ? n : frame + n;
      continue;
    }
    const auto found = verbs().find(c.verb);
    if (found == verbs().end()) throw InputError(c.where, "unknown command '" + c.verb + "'");
    if (c.verb == "drag" && c.args.size() < 3) throw InputError(c.where, "drag takes DX DY and at least one button");
    if (c.verb == "open" && (c.args.empty() || c.args.size() > 2)) throw InputError(c.where, "open takes PATH and optionally an ARRAY");
    if (c.verb == "drop" && c.args.empty()) throw InputError(c.where, "drop takes one or more paths");
    if (c.verb == "wait-load" && c.args.size() > 1) throw InputError(c.where, "wait-load takes at most a timeout in seconds");
    if (found->second >= 0 && c.args.size() != size_t(found->second))
      throw InputError(c.where, c.verb + " takes " + std::to_string(found->second) + " argument(s)");
    c.frame = frame;
    commands.push_back(std::move(c));
  }
  return commands;
}

std::vector<ScriptCommand> read_script(const std::string& path) {
  std::ifstream in(path);
  if (!in) throw InputError(path, "cannot read the script");
  std::ostringstream text;
  text << in.rdbuf();
  return parse_script(text.str(), path);
}

}  // namespace prismoid::app
