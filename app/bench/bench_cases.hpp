#pragma once
// What `prismoid bench` measures: the list of cases (dataset x sweep x quantity x mode x setting x
// image size), built from the preset before anything is loaded (a time series' index of steps
// aside). Plain data, no Vulkan.
#include <cstdint>
#include <string>
#include <utility>
#include <vector>

namespace prismoid::bench {

struct ImageSize {
  uint32_t width = 0, height = 0;
  bool operator==(const ImageSize&) const = default;
};

struct BenchCase {
  std::string dataset;  // as `prismoid render` names it ("" is the embedded default)
  std::string sweep;    // which question the case answers: modes, tetlet-size, preintegration,
                        // march-step, image-size, cells, time
  std::string quantity, mode;
  std::vector<std::pair<std::string, std::string>> options;  // volume options beyond --quantity/--mode
  ImageSize size;
};

struct BenchPreset {
  bool quick = false;
  double warm_up_seconds = 0.0;  // frames before each row's timed ones (timing::warm_up)
  ImageSize size;              // the image size of every sweep but image-size
  uint64_t max_cells = 0;      // the cell-count sweep stops below this many cells
};

// The cells of field:NAME:N (N^3 cubes, 6 tetrahedra each).
constexpr uint64_t field_cells(uint32_t n) { return 6ull * n * n * n; }

// The field dataset the march-step and cell-count sweeps use.
inline constexpr const char* kSweepField = "field:marschner-lobb";

// Every case the preset asks for, datasets in the order given, then the field sweeps.
// Colour cases of datasets without scalars are skipped later, when the data says so. InputError
// for a time series whose steps cannot be listed.
std::vector<BenchCase> bench_cases(const std::vector<std::string>& datasets, const BenchPreset& preset);

// "key=value key=value", or "default".
std::string settings_label(const BenchCase& c);

// The time steps of a time series (.pvd, 'name_*.vtu') or an Exodus II file; 0 for other datasets.
size_t time_steps_of(const std::string& dataset);

// The option of a `time` case that times switching steps rather than a frame (step_switch in the
// bench): "whole" uploads each step's mesh afresh, "fields" only its fields (a static mesh).
constexpr const char* kStepSwitch = "step-switch";


}  // namespace prismoid::bench
