#include "app/cli.hpp"

#include <iostream>
#include <string>
#include <string_view>

#include "app/commands.hpp"
#include "io/progress.hpp"
#include "renderer/vk/capabilities.hpp"
#include "renderer/vk/error.hpp"
#include "scene/input_error.hpp"
#include "scene/setting_names.hpp"

namespace prismoid::app {

namespace {

const char* kUsage =
    "Prismoid: interval-shaded tetrahedral volumes, object-space shaded surfaces, and what accuracy costs in time.\n"
    "\n"
    "usage: prismoid [VERB] [options]\n"
    "\n"
    "verbs:\n"
    "  view [FILE]        open the window (the default verb when a display is available)\n"
    "  render [FILE]      render an image headless (the default verb without a display)\n"
    "  devices            list Vulkan devices and the features each mode needs\n"
    "  convert [IN] OUT   write a tetrahedral mesh (or the default dataset) as .vtu\n"
    "  info FILE          cells by type, points, arrays and their ranges, bounds, GPU memory, conversion\n"
    "  bench [FILE...]    GPU time and error against the CPU reference of each mode and setting\n"
    "  help [VERB]        this text, or a verb's options\n"
    "\n"
    "With no FILE the embedded default dataset is shown. `prismoid VERB --help` for options.\n"
    "Exit codes: 0 ok, 2 bad input, 3 no suitable Vulkan device, 4 validation messages (--validate), 130 cancelled\n"
    "(Ctrl-C during a long load), 1 other failure.\n";

int dispatch(const std::vector<std::string>& args) {
  if (args.empty()) {
    if (window_available()) return cmd_view({"view"});
    std::cout << "no display: rendering the default dataset to prismoid-default.png\n";
    return cmd_render({"render", "--output", "prismoid-default.png"});
  }
  const std::string& verb = args.front();
  if (verb == "--help" || verb == "-h") { std::cout << kUsage; return kOk; }
  if (verb == "help") {
    if (args.size() > 1 && args[1] == "render") std::cout << render_help();
    else if (args.size() > 1 && args[1] == "view") std::cout << view_help();
    else if (args.size() > 1 && args[1] == "devices") std::cout << kDevicesHelp;
    else if (args.size() > 1 && args[1] == "convert") std::cout << kConvertHelp;
    else if (args.size() > 1 && args[1] == "info") std::cout << kInfoHelp;
    else if (args.size() > 1 && args[1] == "bench") std::cout << kBenchHelp;
    else std::cout << kUsage;
    return kOk;
  }
  if (verb == "devices") return cmd_devices(args);
  if (verb == "render") return cmd_render(args);
  if (verb == "view") return cmd_view(args);
  if (verb == "convert") return cmd_convert(args);
  if (verb == "info") return cmd_info(args);
  if (verb == "bench") return cmd_bench(args);
  if (verb.rfind("--", 0) == 0) {  // options without a verb: the default verb
    std::vector<std::string> with_verb{window_available() ? "view" : "render"};
    with_verb.insert(with_verb.end(), args.begin(), args.end());
    return with_verb.front() == "view" ? cmd_view(with_verb) : cmd_render(with_verb);
  }
  throw InputError(verb, "unknown verb (verbs: view, render, convert, info, devices, bench, help)");
}

// A setting as the command line spells it: its option ("--tetlet-size"), with the value after it.
std::string cli_spelling(std::string_view key, std::string_view value) {
  std::string s = "--";
  s.append(key);
  if (!value.empty()) s.append(" ").append(value);
  return s;
}

}  // namespace

int run_cli(const std::vector<std::string>& args) {
  set_setting_spelling(&cli_spelling);  // the renderer's messages name settings as this front end's flags
  try {
    return dispatch(args);
  } catch (const InputError& e) {
    std::cerr << "prismoid: " << e.what() << "\n";
    return kBadInput;
  } catch (const io::Cancelled& e) {
    std::cerr << "prismoid: " << e.what() << "\n";
    return kCancelled;
  } catch (const vk::NoSuitableDevice& e) {
    std::cerr << "prismoid: no suitable Vulkan device: " << e.what() << "\n";
    return kNoDevice;
  } catch (const std::exception& e) {
    std::cerr << "prismoid: " << e.what() << "\n";
    return kFailure;
  }
}

}  // namespace prismoid::app
