#include "app/viewer/viewer_script.hpp"

#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>

#include <cerrno>
#include <cstdint>
#include <cstring>
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
      {"compare-quantity", 1}, {"backend", 1}, {"compare-backend", 1}, {"wait-reference", -1},
      {"time-step", 1},  {"play", 1},          {"range-per-step", 1}, {"wait-step", -1},
      {"compare-step", 1}};
  return v;
}

// The last frame a script may name: 10^8 frames, 19 days at 60 frames a second. (A frame
// number near 2^32 wrapped round the window's frame counter and ran at frame 1.)
constexpr uint32_t kLastFrame = 100000000;

// A script file is small text; more than this is not a script (`--script /dev/zero` grew
// memory until bad_alloc).
constexpr size_t kMaxScriptBytes = size_t(1) << 20;

// The words of a line, shell-like: whitespace separates words; "..." and '...' group (a path
// with spaces: open "my data.vtu"), and inside double quotes \" and \\ stand for " and \. A
// # outside quotes starts a comment. `comment` gets where it starts (npos: none).
std::vector<std::string> split_words(const std::string& line, const std::string& where, size_t& comment) {
  std::vector<std::string> words;
  comment = std::string::npos;
  std::string word;
  bool in_word = false;
  for (size_t i = 0; i < line.size(); ++i) {
    const char ch = line[i];
    if (ch == '#') {
      comment = i;
      break;
    }
    if (ch == ' ' || ch == '\t' || ch == '\r') {
      if (in_word) words.push_back(std::move(word));
      word.clear();
      in_word = false;
      continue;
    }
    in_word = true;
    if (ch != '"' && ch != '\'') {
      word += ch;
      continue;
    }
    const size_t open = i;
    for (++i;; ++i) {
      if (i >= line.size()) throw InputError(where, "a quote opened at column " + std::to_string(open + 1) + " is not closed");
      if (line[i] == ch) break;
      if (ch == '"' && line[i] == '\\' && i + 1 < line.size() && (line[i + 1] == '"' || line[i + 1] == '\\')) ++i;
      word += line[i];
    }
  }
  if (in_word) words.push_back(std::move(word));
  return words;
}

}  // namespace

std::vector<ScriptCommand> parse_script(const std::string& text, const std::string& source) {
  std::vector<ScriptCommand> commands;
  std::istringstream lines(text);
  uint32_t frame = 0;
  int number = 0;
  for (std::string line; std::getline(lines, line);) {
    ++number;
    ScriptCommand c;
    c.where = source + ":" + std::to_string(number);
    size_t comment = std::string::npos;
    std::vector<std::string> words = split_words(line, c.where, comment);
    if (comment != std::string::npos) line.resize(comment);
    if (words.empty()) continue;
    c.verb = words.front();
    c.args.assign(words.begin() + 1, words.end());
    const auto verb_end = line.find(c.verb) + c.verb.size();
    c.rest = line.substr(verb_end);
    if (c.verb == "frame" || c.verb == "wait") {
      if (c.args.size() != 1) throw InputError(c.where, c.verb + " takes one whole number");
      uint64_t n = 0;
      try {
        n = parse_uint(c.verb, c.args[0]);
      } catch (const InputError& e) {
        throw InputError(c.where, e.what());  // "frame: ..." at its line
      }
      const uint64_t at = c.verb == "frame" ? n : frame + n;
      if (at > kLastFrame)
        throw InputError(c.where, c.verb + " " + c.args[0] + " names frame " + std::to_string(at) + ", beyond the last a script can name (" +
                                      std::to_string(kLastFrame) + ")");
      frame = uint32_t(at);
      continue;
    }
    const auto found = verbs().find(c.verb);
    if (found == verbs().end()) throw InputError(c.where, "unknown command '" + c.verb + "'");
    if (c.verb == "drag" && c.args.size() < 3) throw InputError(c.where, "drag takes DX DY and at least one button");
    if (c.verb == "open" && (c.args.empty() || c.args.size() > 2)) throw InputError(c.where, "open takes PATH and optionally an ARRAY");
    if (c.verb == "drop" && c.args.empty()) throw InputError(c.where, "drop takes one or more paths");
    if (c.verb == "wait-load" && c.args.size() > 1) throw InputError(c.where, "wait-load takes at most a timeout in seconds");
    if (c.verb == "wait-step" && (c.args.empty() || c.args.size() > 2))
      throw InputError(c.where, "wait-step takes a step and optionally a timeout in seconds");
    if (found->second >= 0 && c.args.size() != size_t(found->second))
      throw InputError(c.where, c.verb + " takes " + std::to_string(found->second) + " argument(s)");
    c.frame = frame;
    commands.push_back(std::move(c));
  }
  return commands;
}

std::vector<ScriptCommand> read_script(const std::string& path) {
  // Opened without blocking (a FIFO would wait for a writer) and checked before anything is read.
  const int fd = ::open(path.c_str(), O_RDONLY | O_NONBLOCK | O_CLOEXEC);
  if (fd < 0) throw InputError(path, std::string("cannot read the script: ") + std::strerror(errno));
  struct stat st{};
  const bool regular = ::fstat(fd, &st) == 0 && S_ISREG(st.st_mode);
  const bool small = regular && uint64_t(st.st_size) <= kMaxScriptBytes;
  std::string text;
  if (small) {
    text.resize(size_t(st.st_size));
    size_t got = 0;
    while (got < text.size()) {
      const ssize_t n = ::read(fd, text.data() + got, text.size() - got);
      if (n < 0 && errno == EINTR) continue;
      if (n <= 0) break;
      got += size_t(n);
    }
    text.resize(got);
  }
  ::close(fd);
  if (!regular) throw InputError(path, S_ISDIR(st.st_mode) ? "is a folder, not a script" : "is not a regular file, so not a script");
  if (!small)
    throw InputError(path, "holds " + std::to_string(st.st_size) + " bytes; a script is at most " + std::to_string(kMaxScriptBytes) +
                               " (1 MiB)");
  return parse_script(text, path);
}

}  // namespace prismoid::app
