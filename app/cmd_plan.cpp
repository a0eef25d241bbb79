// `prismoid info FILE --plan`: the frame plan for the volume options, without a GPU.
#include <iostream>

#include "app/cli.hpp"
#include "app/commands.hpp"
#include "app/volume_options.hpp"
#include "renderer/frame/frame_plan.hpp"

namespace prismoid::app {

int info_plan(const ParsedArgs& a) {
  const VolumeChoice choice = volume_choice(a);
  std::cout << choice.mesh.name << ": " << choice.mesh.tets.size() << " cells, mode " << choice.mode << ", quantity "
            << quantity_name(choice.quantity) << "\n";
  if (choice.mode == "reference") {
    std::cout << "plan: the CPU double-precision reference, one pass on the CPU (no GPU passes)\n";
    return kOk;
  }
  // A first frame: nothing from an earlier frame to reuse (a still camera later skips the ordering).
  frame::SceneContents scene;
  scene.volumes.push_back(frame::volume_contents(choice.mesh, choice.settings.resolve));
  const frame::FramePlan plan = frame::plan_frame(scene, choice.settings);
  std::cout << "plan (first frame):\n";
  for (const frame::PlannedPass& p : plan.passes)
    std::cout << "  " << p.name << " (" << (p.kind == frame::PassKind::Gpu ? "GPU" : "CPU") << "): " << p.reason << "\n";
  std::cout << "skipped:\n";
  for (const frame::SkippedPass& s : plan.skipped) std::cout << "  " << s.name << ": " << s.reason << "\n";
  return kOk;
}

}  // namespace prismoid::app
