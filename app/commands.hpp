#pragma once
// The verbs of the command line, one file each (cmd_*.cpp), and their help texts.
#include <string>
#include <vector>

namespace prismoid::app {

// args[0] is the verb; each returns an ExitCode (app/cli.hpp) or throws InputError.
int cmd_render(const std::vector<std::string>& args);
int cmd_view(const std::vector<std::string>& args);
int cmd_convert(const std::vector<std::string>& args);
int cmd_info(const std::vector<std::string>& args);
int cmd_devices(const std::vector<std::string>& args);
int cmd_bench(const std::vector<std::string>& args);

// `render --mode path-reference`: a surface scene through the CPU path tracer (app/cmd_render_path.cpp).
bool wants_path_reference(const std::vector<std::string>& args);
int cmd_render_path_reference(const std::vector<std::string>& args);
// `render --mode forward`: a surface scene through the forward GPU backend (app/cmd_render_forward.cpp).
bool wants_forward(const std::vector<std::string>& args);
int cmd_render_forward(const std::vector<std::string>& args);
// `render --mode htex`: a surface scene through the Htex object-space backend (app/cmd_render_htex.cpp).
bool wants_htex(const std::vector<std::string>& args);
int cmd_render_htex(const std::vector<std::string>& args);
// `render --mode texel|msa`: a surface scene through an atlas-based texture-space backend
// (app/cmd_render_atlas.cpp).
bool wants_atlas_mode(const std::vector<std::string>& args);
int cmd_render_atlas(const std::vector<std::string>& args);

struct ParsedArgs;
// `info --plan`: prints the frame plan the volume options give (app/cmd_plan.cpp).
int info_plan(const ParsedArgs& a);

extern const char* const kRenderHelp;
extern const char* const kViewHelp;
extern const char* const kConvertHelp;
extern const char* const kInfoHelp;
extern const char* const kDevicesHelp;
extern const char* const kBenchHelp;

}  // namespace prismoid::app
