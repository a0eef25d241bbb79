#pragma once
// The window for surface scenes: the same window, frame loop (window_loop.hpp), camera, panels,
// screenshots and scripts as the volume window (viewer.hpp), drawing through
// surface::SurfaceRenderer, whose modes (the surface mode table's, those the device draws) are
// switched in the panel, with the M key or the script's `mode` verb, and ray-traced shadows with
// L or `shadows on|off`. The panel shows each pass's GPU time, so switching modes shows what each
// costs, and the frame's plan.
#include "app/viewer/viewer.hpp"
#include "scene/surface_scene.hpp"

namespace prismoid::app {

// `scene` with its lights (with_default_lighting already applied). options.mode: the first
// mode (empty: the first the device draws). Script verbs: the camera's (camera, view, reset,
// rotate, pan, zoom, drag, fly...), key, mode, shadows on|off, ui, screenshot, render W H FILE, print-camera,
// resize, close; any other is reported as not available for surfaces.
ViewerReport run_surface_viewer(const SurfaceScene& scene, const ViewerOptions& options);

}  // namespace prismoid::app
