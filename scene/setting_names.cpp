#include "scene/setting_names.hpp"

#include <atomic>

namespace prismoid {

namespace {

std::string bare(std::string_view key, std::string_view value) {
  std::string s(key);
  if (!value.empty()) s.append(" ").append(value);
  return s;
}

std::atomic<SettingSpelling> g_spelling{&bare};

}  // namespace

void set_setting_spelling(SettingSpelling spelling) { g_spelling.store(spelling ? spelling : &bare); }

std::string setting(std::string_view key) { return g_spelling.load()(key, {}); }

std::string setting(std::string_view key, std::string_view value) { return g_spelling.load()(key, value); }

}  // namespace prismoid
