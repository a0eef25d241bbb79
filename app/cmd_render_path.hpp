#pragma once
// `render --mode path-reference`'s part of the surface verb (app/cmd_render_surface.cpp): the CPU
// path tracer's options, and the report of its frame.
#include <iosfwd>
#include <string>
#include <vector>

#include "app/common/cli_args.hpp"
#include "renderer/mixed/scene_renderer.hpp"
#include "renderer/reference/path_tracer.hpp"

namespace prismoid::app {

class OutputFiles;

// The path tracer's options: render parses them with every surface mode and refuses them for the
// GPU ones.
extern const std::vector<std::string> kPathTracerOptions;
extern const char* const kPathTracerOptionsHelp;

// --spp, --max-bounces and --seed (InputError naming the option for a value out of range).
reference::PathTracerSettings path_tracer_settings(const ParsedArgs& a);

// Writes the image and --variance of a path-traced frame into `files`, the --stats file, and says
// what was drawn (the frame's stats, through app/common/frame_stats_writer).
void report_path_traced(const ParsedArgs& a, OutputFiles& files, const mixed::SceneFrame& drawn, std::ostream& said);

}  // namespace prismoid::app
