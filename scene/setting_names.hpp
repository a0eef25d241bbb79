#pragma once
// How a setting is named to the user. The renderer's and the scene's messages name a setting by
// its key in the option table ("tetlet-size", "shadows" with "off"), never by one front end's
// spelling of it: each front end spells the keys its own way once, at start-up (the command line
// as its flags, "--tetlet-size", "--shadows off"); without one, the key itself is shown
// ("tetlet-size", "shadows off"), which reads as the setting in any front end (the ParaView
// plugin's properties carry the same names).
#include <string>
#include <string_view>

namespace prismoid {

// A front end's spelling of setting `key`, with `value` where one is named ("" for none).
using SettingSpelling = std::string (*)(std::string_view key, std::string_view value);

// Installs `spelling` for the whole process (nullptr: the keys themselves). Called once by a
// front end before any work, so every thread reads the same one.
void set_setting_spelling(SettingSpelling spelling);

// Setting `key` as the user knows it, e.g. "--tetlet-size" on the command line.
std::string setting(std::string_view key);
// Setting `key` with a value, e.g. "--shadows off" on the command line.
std::string setting(std::string_view key, std::string_view value);

}  // namespace prismoid
