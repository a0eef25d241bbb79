#pragma once
// VTK's progress events, forwarded to io::Progress. Internal to io/ (it names VTK types).
#include <functional>
#include <string>

#include "io/progress.hpp"

class vtkAlgorithm;

namespace prismoid::io::detail {

// Where one VTK step sits in the whole load: its own fraction f is reported as
// start + f * (end - start), under `stage`.
struct ProgressSpan {
  double start = 0.0;
  double end = 1.0;
  std::string stage;
};

// Runs `update` (by default algorithm->Update()) with the algorithm's ProgressEvent forwarded to
// `progress`. When the callback returns false, the algorithm's AbortExecute flag is set (VTK
// stops at its next check) and, once `update` returns, Cancelled(source) is thrown, before
// anything reads the algorithm's partial output. Without a callback it is plain `update`.
void update_with_progress(vtkAlgorithm* algorithm, const Progress& progress, const ProgressSpan& span, const std::string& source,
                          const std::function<void()>& update = {});

}  // namespace prismoid::io::detail
