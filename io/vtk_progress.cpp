#include "io/vtk_progress.hpp"

#include <vtkAlgorithm.h>
#include <vtkCallbackCommand.h>
#include <vtkCommand.h>
#include <vtkNew.h>

namespace prismoid::io::detail {

namespace {

struct Forwarding {
  const Progress* progress;
  const ProgressSpan* span;
  bool cancelled = false;
};

void forward(vtkObject* caller, unsigned long, void* client, void* call_data) {
  auto* state = static_cast<Forwarding*>(client);
  if (state->cancelled || !call_data) return;
  const double fraction = *static_cast<const double*>(call_data);
  const ProgressSpan& span = *state->span;
  if (!(*state->progress)(span.start + fraction * (span.end - span.start), span.stage)) {
    state->cancelled = true;
    if (auto* algorithm = vtkAlgorithm::SafeDownCast(caller)) algorithm->SetAbortExecute(1);
  }
}

}  // namespace

void update_with_progress(vtkAlgorithm* algorithm, const Progress& progress, const ProgressSpan& span, const std::string& source,
                          const std::function<void()>& update) {
  auto run = [&] { update ? update() : void(algorithm->Update()); };
  if (!progress) {
    run();
    return;
  }
  report(progress, span.start, span.stage, source);
  Forwarding state{&progress, &span};
  vtkNew<vtkCallbackCommand> observer;
  observer->SetCallback(forward);
  observer->SetClientData(&state);
  {
    // Removed however `update` ends: the observer points at this frame.
    struct Watch {
      vtkAlgorithm* algorithm;
      unsigned long tag;
      ~Watch() {
        algorithm->RemoveObserver(tag);
        algorithm->SetAbortExecute(0);  // a reader reused after a cancel starts afresh
      }
    } watch{algorithm, algorithm->AddObserver(vtkCommand::ProgressEvent, observer)};
    run();
  }
  if (state.cancelled) throw Cancelled(source);
  report(progress, span.end, span.stage, source);
}

}  // namespace prismoid::io::detail
