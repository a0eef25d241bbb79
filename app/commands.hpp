#pragma once
// The verbs of the command line, one file each (cmd_*.cpp), and their help texts.
#include <string>
#include <vector>

namespace prismoid::surface {
struct SurfaceMode;
}  // namespace prismoid::surface

namespace prismoid::app {

// args[0] is the verb; each returns an ExitCode (app/cli.hpp) or throws InputError.
int cmd_render(const std::vector<std::string>& args);
int cmd_view(const std::vector<std::string>& args);
int cmd_convert(const std::vector<std::string>& args);
int cmd_info(const std::vector<std::string>& args);
int cmd_devices(const std::vector<std::string>& args);
int cmd_bench(const std::vector<std::string>& args);

// Whether a window can open here (a display is set): then `view` is the default verb
// (app/cmd_view.cpp, the one verb that knows the window).
bool window_available();

// The surface mode `--mode` names (either --mode M or --mode=M), from the surface mode table;
// nullptr when it names none (then the volume modes apply).
const surface::SurfaceMode* surface_mode_named(const std::vector<std::string>& args);
// `render --mode M` for a surface mode, on the GPU or the CPU path tracer as the mode is
// (app/cmd_render_surface.cpp).
int cmd_render_surface(const std::vector<std::string>& args, const surface::SurfaceMode& mode);
// render's flags (options without a value): a word after one of them is a file, after any other
// option its value.
extern const std::vector<std::string> kRenderFlags;
// Whether render's arguments name a volume and surfaces together (app/cmd_render_mixed.cpp).
bool mixed_scene_named(const std::vector<std::string>& args);
// `render VOLUME SURFACE...`: the volume inside its opaque surfaces, through mixed::MixedRenderer.
int cmd_render_mixed(const std::vector<std::string>& args);
// render's help: its options with the volume modes from their table, then the surface modes'
// part (surface_render_help).
std::string render_help();
// The surface modes' part of render's help, from the table.
std::string surface_render_help();

struct ParsedArgs;
// `info --plan`: prints the frame plan the volume options give, or for a surface scene or a
// surface --mode the surface frame's (app/cmd_plan.cpp).
int info_plan(const ParsedArgs& a);

std::string view_help();
extern const char* const kConvertHelp;
extern const char* const kInfoHelp;
extern const char* const kDevicesHelp;
extern const char* const kBenchHelp;

}  // namespace prismoid::app
