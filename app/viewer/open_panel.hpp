#pragma once
// The panel's Data section: the datasets of the scene (show/hide, which one is active), a path
// box with Open, the recent files, and while a load runs its progress bar and Cancel; a load
// that fails opens a popup with the data layer's message. What needs the frame loop (opening,
// cancelling, showing, choosing the active dataset) comes back as DataRequests.
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "app/viewer/view_state.hpp"

namespace prismoid::app {

// What the loop tells the section about loading, each frame.
struct LoadStatus {
  bool running = false;
  std::string label;     // the file being loaded
  double fraction = 0.0;  // negative: unknown
  std::string stage;
  double seconds = 0.0;
  size_t queued = 0;      // waiting after it
};

struct RecentEntry {
  std::string path;
  bool exists = true;  // missing files are shown greyed and cannot be opened
};

// The section's text boxes and what the loop gives it to show.
struct DataPanel {
  char path[1024] = "";
  char array[128] = "";  // the array to read from the next file opened (empty: none)
  LoadStatus load;
  std::vector<RecentEntry> recent;
  std::string error;           // the last failed load's (or request's) message, for the popup
  std::string error_title = "Could not open";
  bool show_error = false;     // open the popup on the next frame
  bool playing = false;        // the active dataset's steps are playing
  bool step_loading = false;   // a step is loading
};

struct DataRequests {
  std::vector<std::string> open;  // paths, in order
  std::string array;              // from the array box
  bool cancel = false;
  std::optional<std::pair<size_t, bool>> show;  // dataset, visible
  std::optional<size_t> make_active;
  // Time (the active dataset's steps): the step asked for, play or pause, the colour range per step.
  std::optional<uint32_t> time_step;
  std::optional<bool> play;
  std::optional<bool> range_per_step;
  std::optional<std::optional<uint32_t>> compare_step;  // split view's B at this step (none: at A's)
};

void draw_data_section(const ViewState& state, DataPanel& panel, DataRequests& requests);
// The modal error popup ("Could not open", or a failed request's title); drawn every frame (it
// shows only while open).
void draw_load_error_popup(DataPanel& panel);

}  // namespace prismoid::app
