#pragma once
// Scripted sessions: a text file of commands, one a line, that drives the window the way a
// person would (keys, camera, mode and transfer-function changes, screenshots), so tests and
// benchmarks need no one at the keyboard. `#` starts a comment.
//
//   frame N                 run the following commands at frame N (frames count from 0)
//   wait N                  ... N frames after the previous ones
//   key NAME                a key press as the window gets it: R, F, P, H, C, X, shift+X, W...
//   mode NAME               a GPU volume mode of renderer/frame/volume_modes.hpp
//   shadows on|off          the surface window's ray-traced shadows
//   quantity NAME           optical-depth, transmittance, color, isosurface
//   tf PRESET|FILE          a preset or a ParaView JSON colour map
//   tf-range LO HI          the transfer function's scalar range ("tf-range data": the data's)
//   tf-export FILE          writes the transfer function as ParaView JSON
//   tetlet-size N | shared-vertices on|off | preintegration-size N | march-step X | density-scale X
//   camera OPTIONS          --eye x,y,z --target x,y,z --up x,y,z --fovy D --near N (as render)
//   view +X|-X|+Y|-Y|+Z|-Z  an axis-aligned view;  reset: fit the data
//   rotate DX DY | pan DX DY | zoom STEPS      what mouse drags and the wheel do (pixels, steps)
//   drag DX DY BUTTON...    a mouse drag as the bindings see it (left, middle, right, shift)
//   fly on|off | fly-move RIGHT UP FORWARD SECONDS | fly-look DX DY
//   ui on|off               show or hide the panels
//   screenshot FILE         the window as displayed (with the panels when shown), PNG
//   render W H FILE         this view at W x H through render's path (no panels), PNG or PFM
//   print-camera            the camera as render options, on stdout
//   resize W H | iconify | restore | close
//   rss                     records the process's resident memory (for leak checks)
//   open PATH [ARRAY]       opens a dataset in the background, as the path box does
//   drop PATH...            files dropped onto the window (the drop callback's path)
//   wait-load [SECONDS]     later commands wait until the loads end (default timeout 120 s);
//                           frames keep being drawn, and `wait N` after it counts from the end
//   cancel-load             the panel's Cancel: stops the load and drops the queued ones
//   show INDEX on|off       shows or hides dataset INDEX (from 0, in the order opened)
//   active INDEX            makes dataset INDEX the one the transfer function's range follows
//   compare off|split|difference   A | B, or the current mode against the CPU reference
//   compare-mode NAME | compare-quantity NAME    split view's B
//   wait-reference [SECONDS]  holds the script until the difference view shows the current
//                           view's reference (default: at most 300 s; then a message)
#include <cstdint>
#include <string>
#include <vector>

namespace prismoid::app {

struct ScriptCommand {
  uint32_t frame = 0;              // when it runs
  std::string verb;
  std::vector<std::string> args;   // the words after the verb
  std::string rest;                // the text after the verb, as written (camera options)
  std::string where;               // "FILE:LINE", for messages
};

// Parses a script; InputError("FILE:LINE", ...) for an unknown verb or a wrong argument count.
std::vector<ScriptCommand> parse_script(const std::string& text, const std::string& source);
std::vector<ScriptCommand> read_script(const std::string& path);

}  // namespace prismoid::app
