#pragma once
// The scene's list of datasets: adding a loaded one, showing and hiding, choosing the active
// one, and keeping ViewState::scene (what is drawn: the visible datasets as one mesh) current.
// Each edit returns an empty string when applied, else why not; a note when the mode or the
// quantity had to change to fit the new scene.
#include <string>

#include "app/viewer/view_state.hpp"

namespace prismoid::app {

// Rebuilds state.scene: the one visible dataset as it is (its mesh shared, its field kept), or
// the union of several (merge_meshes: no analytic field, so no marching). Needs a visible dataset.
void rebuild_scene(ViewState& state);

// Adds a loaded dataset, visible and active, and rebuilds the scene.
std::string add_dataset(ViewState& state, Dataset dataset);
// Shows or hides dataset `index`; the last visible one cannot be hidden.
std::string show_dataset(ViewState& state, size_t index, bool visible);
// Makes dataset `index` the active one: the transfer function's range becomes its data range.
std::string set_active(ViewState& state, size_t index);
// Shows `step`, another time step of dataset `index` loaded as it was, in its place (visible as
// it was); the transfer function's range follows the step's data where state.range_per_step.
std::string show_step(ViewState& state, size_t index, Dataset step);

}  // namespace prismoid::app
