#include "app/bench/bench_cases.hpp"

#include "app/common/volume_option_table.hpp"
#include "app/common/dataset_loader.hpp"
#include "renderer/frame/volume_modes.hpp"

namespace prismoid::bench {

namespace {

using Options = std::vector<std::pair<std::string, std::string>>;

void add(std::vector<BenchCase>& out, const std::string& dataset, const char* sweep, const char* quantity, std::string_view mode,
         Options options, ImageSize size) {
  out.push_back({dataset, sweep, quantity, std::string(mode), std::move(options), size});
}

// The volume mode table's mode that draws cells in `ordering` and marches or not.
std::string_view mode_of(frame::Ordering ordering, bool march) { return frame::find_volume_mode(ordering, march)->name; }

// The options that draw a case with the compute-rasterized backend (the others use the mesh-shader one).
Options compute() { return {{"volume-backend", "compute"}}; }

}  // namespace

size_t time_steps_of(const std::string& dataset) { return app::time_values(dataset).size(); }

std::vector<BenchCase> bench_cases(const std::vector<std::string>& datasets, const BenchPreset& p) {
  std::vector<BenchCase> cases;
  const ImageSize s = p.size;
  // The modes, by what they do; the modes sweep takes every GPU mode of the table that does not march.
  const std::string_view mesh_order = mode_of(frame::Ordering::MeshOrder, false);
  const std::string_view sorted = mode_of(frame::Ordering::GpuSort, false);
  const std::string_view sorted_march = mode_of(frame::Ordering::GpuSort, true);
  const std::string_view exact = mode_of(frame::Ordering::Exact, false);
  for (const std::string& d : datasets) {
    // The modes side by side: order-independent quantities need no order (the mesh-order modes
    // alone); colour in every order the GPU modes draw in.
    for (const char* quantity : {"optical-depth", "transmittance"})
      for (const frame::VolumeMode& m : frame::volume_mode_table())
        if (m.gpu() && !m.march && m.ordering == frame::Ordering::MeshOrder) add(cases, d, "modes", quantity, m.name, {}, s);
    for (const frame::VolumeMode& m : frame::volume_mode_table())
      if (m.gpu() && !m.march) add(cases, d, "modes", "color", m.name, {}, s);
    // The compute backend beside it: the order-independent quantities, and colour, which it
    // composites in each pixel's own depth order whatever the mode's cell order.
    for (const char* quantity : {"optical-depth", "transmittance"}) add(cases, d, "modes", quantity, mesh_order, compute(), s);
    add(cases, d, "modes", "color", exact, compute(), s);
    // Tetlet size (cells per mesh-shader workgroup; 16 is the default measured above), at the
    // option table's values.
    for (const std::string& t : app::volume_option_sweep("tetlet-size", p.quick))
      add(cases, d, "tetlet-size", "optical-depth", mesh_order, {{"tetlet-size", t}}, s);
    // Pre-integration table size (0, the default above, integrates each segment exactly).
    for (const std::string& n : app::volume_option_sweep("preintegration-size", p.quick))
      add(cases, d, "preintegration", "color", sorted, {{"preintegration-size", n}}, s);
    // A time series' or an Exodus file's steps, each a case: its transmittance in mesh order and
    // its colour in exact order, so that cost and accuracy are followed over the simulation's time.
    const size_t steps = time_steps_of(d);
    for (size_t i = 0; i < steps; ++i) {
      add(cases, d, "time", "transmittance", mesh_order, {{"time-step", std::to_string(i)}}, s);
      add(cases, d, "time", "color", exact, {{"time-step", std::to_string(i)}}, s);
    }
    // What moving to the next step costs a viewer at a still camera, on both backends: each step
    // uploaded whole, or a static mesh's fields alone (its order kept).
    if (steps > 1)
      for (const Options& backend : {Options{}, compute()})
        for (const char* how : {"whole", "fields"}) {
          Options options = backend;
          options.emplace_back(kStepSwitch, how);
          add(cases, d, "time", "color", exact, options, s);
        }
  }
  // Image size, on the first dataset: half and twice the preset's size beside the size itself.
  if (!p.quick && !datasets.empty())
    for (const uint32_t f : {1u, 4u}) {
      const ImageSize sized{std::max(1u, s.width * f / 2), std::max(1u, s.height * f / 2)};
      add(cases, datasets.front(), "image-size", "optical-depth", mesh_order, {}, sized);
      add(cases, datasets.front(), "image-size", "color", sorted, {}, sized);
      add(cases, datasets.front(), "image-size", "optical-depth", mesh_order, compute(), sized);
      add(cases, datasets.front(), "image-size", "color", exact, compute(), sized);
    }
  // March step, on an analytic field: the marched field against the same field's reference,
  // beside the piecewise-linear tetrahedra of the same field.
  {
    const std::string field = std::string(kSweepField) + (p.quick ? ":4" : ":16");
    add(cases, field, "march-step", "optical-depth", mesh_order, {}, s);
    add(cases, field, "march-step", "color", sorted, {}, s);
    for (const char* divisions : p.quick ? std::vector<const char*>{"25", "100"} : std::vector<const char*>{"25", "50", "100", "200", "400"}) {
      // --march-step is in world units; the field box is the unit cube scaled by the field
      // (resolved when the case runs: "diagonal/N").
      add(cases, field, "march-step", "optical-depth", sorted_march, {{"march-step", std::string("diagonal/") + divisions}}, s);
      add(cases, field, "march-step", "color", sorted_march, {{"march-step", std::string("diagonal/") + divisions}}, s);
    }
  }
  // Cell count: the same field split into N^3 cubes, from about a thousand cells upwards.
  for (const uint32_t n : p.quick ? std::vector<uint32_t>{6, 12} : std::vector<uint32_t>{6, 12, 24, 48, 96, 128}) {
    if (field_cells(n) > p.max_cells) break;
    // append rather than +: GCC 12 warns falsely (-Warray-bounds) about + here.
    const std::string field = std::string(kSweepField).append(":").append(std::to_string(n));
    add(cases, field, "cells", "optical-depth", mesh_order, {}, s);
    add(cases, field, "cells", "color", sorted, {}, s);
    add(cases, field, "cells", "optical-depth", mesh_order, compute(), s);
    add(cases, field, "cells", "color", exact, compute(), s);
  }
  return cases;
}

std::string settings_label(const BenchCase& c) {
  std::string s;
  for (const auto& [k, v] : c.options) s += (s.empty() ? "" : " ") + k + "=" + v;
  return s.empty() ? "default" : s;
}

}  // namespace prismoid::bench
