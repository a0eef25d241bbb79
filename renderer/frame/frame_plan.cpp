#include "renderer/frame/frame_plan.hpp"

#include "renderer/frame/volume_passes.hpp"

#include <algorithm>
#include <sstream>
#include <stdexcept>

#include "scene/input_error.hpp"
#include "scene/setting_names.hpp"
#include "scene/tet_mesh.hpp"

namespace prismoid::frame {

const char* ordering_name(Ordering ordering) {
  switch (ordering) {
    case Ordering::MeshOrder: return "mesh-order";
    case Ordering::GpuSort: return "gpu-sort";
    case Ordering::Exact: return "exact";
  }
  return "?";
}

const char* interval_backend_name(IntervalBackend backend) { return backend.name.data(); }

VolumeContents volume_contents(uint64_t cells, bool point_extinction, bool point_scalars, const volume::ResolveSettings& settings) {
  VolumeContents v;
  v.cells = cells;
  v.optics = settings.quantity == volume::Quantity::Color        ? VolumeOptics::EmissionAbsorption
             : settings.quantity == volume::Quantity::Isosurface ? VolumeOptics::Isosurface
                                                                 : VolumeOptics::AbsorptionOnly;
  // The interval pass integrates colour over the scalar field, optical depth over sigma.
  const bool per_point = settings.quantity == volume::Quantity::Color ? point_scalars : point_extinction;
  v.field = settings.march.enabled ? FieldModel::Marched : per_point ? FieldModel::Linear : FieldModel::PerCell;
  return v;
}

VolumeContents volume_contents(const TetMesh& mesh, const volume::ResolveSettings& settings) {
  return volume_contents(mesh.tets.size(), mesh.linear_extinction(), !mesh.point_scalars.empty(), settings);
}

bool FramePlan::has(std::string_view name) const {
  return std::any_of(passes.begin(), passes.end(), [&](const PlannedPass& p) { return p.name == name; });
}

const PlannedPass* FramePlan::find(PassId id) const {
  const auto found = std::find_if(passes.begin(), passes.end(), [&](const PlannedPass& p) { return p.id == id; });
  return found == passes.end() ? nullptr : &*found;
}

std::vector<std::string> FramePlan::gpu_pass_names() const {
  std::vector<std::string> names;
  for (const PlannedPass& p : passes)
    if (p.kind == PassKind::Gpu) names.push_back(p.name);
  return names;
}

namespace {

// The plan under construction: CPU passes and GPU passes kept apart so each decision can be
// written where it is made and the CPU ones still run first.
struct PlanBuilder {
  std::vector<PlannedPass> cpu, gpu;
  std::vector<SkippedPass> skipped;
  void run(PassId id, std::string name, PassKind kind, std::string reason) {
    (kind == PassKind::Cpu ? cpu : gpu).push_back({id, std::move(name), kind, std::move(reason)});
  }
  void skip(std::string name, std::string reason) { skipped.push_back({std::move(name), std::move(reason)}); }
};

void plan_transfer(const SceneContents& scene, const VolumeContents& volume, const FrameSettings& settings, PlanBuilder& plan) {
  const uint32_t n = settings.resolve.preintegration_size;
  if (volume.optics != VolumeOptics::EmissionAbsorption) {
    plan.skip("preintegrate", volume.optics == VolumeOptics::Isosurface ? "an isosurface needs no transfer function"
                                                                        : "absorption only: no transfer function to integrate");
    return;
  }
  const std::string table = std::to_string(n) + "^3";
  if (n > 0) {
    if (scene.transfer_changed)
      plan.run(PassId::Preintegrate, "preintegrate", PassKind::Cpu,
               "transfer function or table size changed (or none yet): the " + table + " table of exact segment integrals is built");
    else
      plan.skip("preintegrate", "table unchanged (" + table + ")");
    return;
  }
  plan.skip("preintegrate", "pre-integration off: segments are integrated exactly in the shader");
  if (scene.transfer_changed)
    plan.run(PassId::TransferUpload, "transfer-function upload", PassKind::Cpu,
             "transfer function changed (or none yet): its breakpoints go to the shader's exact segment integrals");
  else
    plan.skip("transfer-function upload", "transfer function unchanged");
}

void plan_tetlets(const SceneContents& scene, const FrameSettings& settings, PlanBuilder& plan) {
  const uint32_t size = settings.resolve.tetlet_size;
  if (!settings.resolve.shared_vertices) {
    plan.skip("build-tetlets", "shared vertices off: each cell loads its own 4 points");
    return;
  }
  if (scene.tetlets_built)
    plan.skip("build-tetlets", "tetlets of " + std::to_string(size) + " cells already built");
  else
    plan.run(PassId::BuildTetlets, "build-tetlets", PassKind::Cpu,
             "shared vertices: cells grouped into tetlets of " + std::to_string(size) + " (once per size)");
}

void skip_ordering(PlanBuilder& plan, const std::string& why) {
  for (const char* name : {"exact-order", "sort", "upload-order"}) plan.skip(name, why);
}

// Returns whether the last frame's order is drawn with again.
bool plan_ordering(const SceneContents& scene, const VolumeContents& volume, const FrameSettings& settings, PlanBuilder& plan) {
  if (volume.optics == VolumeOptics::AbsorptionOnly) {
    skip_ordering(plan, "optical depth is order-independent (sums of sigma * length commute)");
    return false;
  }
  if (volume.optics == VolumeOptics::Isosurface) {
    skip_ordering(plan, "an isosurface is order-independent (the depth test keeps the nearest hit)");
    return false;
  }
  if (volume.cells == 0) {
    skip_ordering(plan, "no cells to order");
    return false;
  }
  if (settings.ordering == Ordering::MeshOrder) {
    skip_ordering(plan, "mesh order asked for (" + setting("mode", "interval") + "): colour composited unsorted, approximate");
    return false;
  }
  const bool reuse = !scene.camera_moved && !scene.scene_moved && scene.order_kept == settings.ordering;
  const std::string moved = !scene.order_kept                       ? "no earlier order to reuse"
                            : scene.scene_moved                       ? "the scene changed"
                            : scene.camera_moved                      ? "the camera moved"
                                                                      : "the last order came from another ordering";
  if (settings.ordering == Ordering::GpuSort) {
    plan.skip("exact-order", "GPU sort asked for, not the exact order");
    plan.skip("upload-order", "the GPU sort writes the order in device memory");
    if (reuse)
      plan.skip("sort", "order reused: camera still (the last frame's sorted order is still in its buffer)");
    else
      plan.run(PassId::Sort, "sort", PassKind::Gpu,
               "colour is order-dependent: cells sorted front to back by centroid distance on the GPU (" + moved + ")");
    return reuse;
  }
  plan.skip("sort", "exact order asked for, not the GPU sort");
  if (reuse) {
    plan.skip("exact-order", "order reused: camera still (the last frame's order is still in device memory)");
    plan.skip("upload-order", "order reused: camera still");
    return true;
  }
  plan.run(PassId::ExactOrder, "exact-order", PassKind::Cpu,
           "colour is order-dependent: topological visibility order over face adjacency for this eye (" + moved + ")");
  plan.run(PassId::UploadOrder, "upload-order", PassKind::Gpu, "the CPU's exact order copied to device memory for the mesh shader");
  return false;
}

std::string interval_reason_of(const VolumeContents& volume, const FrameSettings& settings) {
  const volume::ResolveSettings& r = settings.resolve;
  std::string why;
  switch (volume.optics) {
    case VolumeOptics::AbsorptionOnly: why = "optical depth per interval, blended additively"; break;
    case VolumeOptics::EmissionAbsorption: why = "emission-absorption per interval, composited front to back"; break;
    case VolumeOptics::Isosurface: why = "the nearest isovalue crossing per interval, depth tested"; break;
  }
  switch (volume.field) {
    case FieldModel::PerCell: why += "; per-cell field: exact"; break;
    case FieldModel::Linear: why += "; linear point field: exact"; break;
    case FieldModel::Marched: why += "; non-linear field marched in steps of at most " + std::to_string(r.march.step); break;
  }
  if (volume.optics == VolumeOptics::EmissionAbsorption && volume.field != FieldModel::Marched && r.preintegration_size > 0)
    why += "; segments looked up in the pre-integrated table";
  if (r.shared_vertices) why += "; tetlets (shared vertices)";
  why += "; " + std::to_string(r.tetlet_size) + " cells per workgroup";
  return why;
}

void plan_surfaces(const SceneContents& scene, PlanBuilder& plan) {
  plan.skip("surface-shading", scene.surfaces == 0 ? "no surfaces in the scene" : "surfaces are not renderable yet");
  std::string gi;
  if (!scene.indirect_wanted) gi = "no indirect light asked for";
  else if (scene.surfaces == 0) gi = "no surfaces: nothing indirect to gather";
  else if (scene.lights == 0 && scene.emissive_surfaces == 0) gi = "no lights or emissive surfaces: nothing to gather";
  else gi = "global illumination is not implemented yet";
  plan.skip("gi", gi);
}

}  // namespace

std::string interval_reason(const VolumeContents& volume, const FrameSettings& settings) { return interval_reason_of(volume, settings); }

FramePlan plan_frame(const SceneContents& scene, const FrameSettings& settings, const VolumePasses& passes) {
  if (scene.volumes.size() > 1) throw std::invalid_argument("plan_frame: one volume per frame (FrameRenderer draws one mesh)");
  const volume::ResolveSettings& r = settings.resolve;
  if (r.shared_vertices && volume::order_dependent(r.quantity) && settings.ordering != Ordering::MeshOrder)
    throw InputError(setting("shared-vertices"), "tetlets fix the order cells are drawn in: use it with optical depth or "
                                          "transmittance, or with " + setting("mode", "interval"));
  if (!passes.tetlets && r.shared_vertices) throw InputError(setting("shared-vertices"), std::string(passes.tetlets_refused));
  PlanBuilder plan;
  FramePlan result;
  if (scene.volumes.empty()) {
    for (const char* name : {"preintegrate", "build-tetlets", "exact-order", "sort", "upload-order", "interval-shading", "resolve"})
      plan.skip(name, "no volume in the scene");
  } else {
    const VolumeContents& volume = scene.volumes.front();
    plan_transfer(scene, volume, settings, plan);
    if (passes.tetlets) plan_tetlets(scene, settings, plan);
    else plan.skip("build-tetlets", std::string(passes.no_tetlets));
    if (passes.chosen_order) {
      result.reuses_order = plan_ordering(scene, volume, settings, plan);
    } else {
      const std::string why = volume.optics == VolumeOptics::EmissionAbsorption ? std::string(passes.own_order)
                              : volume.optics == VolumeOptics::Isosurface && !passes.isosurface_order.empty()
                                  ? std::string(passes.isosurface_order)
                              : volume.optics == VolumeOptics::Isosurface
                                  ? "an isosurface is order-independent (the depth test keeps the nearest hit)"
                                  : "optical depth is order-independent (sums of sigma * length commute)";
      skip_ordering(plan, why);
    }
    std::vector<PlannedPass> runs;
    std::vector<SkippedPass> skips;
    passes.intervals(volume, settings, runs, skips);
    for (PlannedPass& p : runs) plan.run(p.id, std::move(p.name), p.kind, std::move(p.reason));
    for (SkippedPass& p : skips) plan.skip(std::move(p.name), std::move(p.reason));
    plan.run(PassId::Resolve, "resolve", PassKind::Gpu,
             volume.optics == VolumeOptics::EmissionAbsorption ? "the display colour (colour over the background) and the transmittance"
                                                               : "the quantity and its display colour from what the interval pass drew");
  }
  plan_surfaces(scene, plan);
  result.passes = std::move(plan.cpu);
  result.passes.insert(result.passes.end(), plan.gpu.begin(), plan.gpu.end());
  result.skipped = std::move(plan.skipped);
  return result;
}

const char* pass_kind_text(PassKind kind) {
  switch (kind) {
    case PassKind::Gpu: return "GPU";
    case PassKind::Cpu: return "CPU";
    case PassKind::Within: return "GPU, within the pass above";
  }
  return "?";
}

std::string format_plan(const FramePlan& plan) {
  std::ostringstream out;
  for (const PlannedPass& p : plan.passes) out << "  " << p.name << " (" << pass_kind_text(p.kind) << "): " << p.reason << "\n";
  for (const SkippedPass& s : plan.skipped) out << "  " << s.name << ": skipped, " << s.reason << "\n";
  return out.str();
}

const char* surface_gi_name(SurfaceGi gi) {
  switch (gi) {
    case SurfaceGi::None: return "off";
    case SurfaceGi::RestirBiased: return "biased";
    case SurfaceGi::RestirUnbiased: return "unbiased";
    case SurfaceGi::PathTraced: return "path-traced";
  }
  return "?";
}

namespace {

std::string count_of(uint64_t n, const std::string& one, const std::string& many) {
  return std::to_string(n) + " " + (n == 1 ? one : many);
}

// "2 point lights, 1 directional light and 1280 emissive triangles": what casts shadows.
std::string shadow_casters(const SurfaceContents& scene) {
  std::vector<std::string> parts;
  if (scene.point_lights) parts.push_back(count_of(scene.point_lights, "point light", "point lights"));
  if (scene.directional_lights) parts.push_back(count_of(scene.directional_lights, "directional light", "directional lights"));
  if (scene.emissive_triangles) parts.push_back(count_of(scene.emissive_triangles, "emissive triangle", "emissive triangles"));
  std::string text;
  for (size_t i = 0; i < parts.size(); ++i) text += (i == 0 ? "" : i + 1 == parts.size() ? " and " : ", ") + parts[i];
  return text;
}

bool casters_are_one(const SurfaceContents& scene) { return uint64_t(scene.point_lights) + scene.directional_lights + scene.emissive_triangles == 1; }

// What lights the scene for a bounce: the shadow casters and the sky.
std::string light_sources(const SurfaceContents& scene) {
  const std::string casters = shadow_casters(scene);
  if (!scene.sky) return casters;
  return casters.empty() ? "the sky" : casters + " and the sky";
}

const char* gi_words(SurfaceGi gi) {
  switch (gi) {
    case SurfaceGi::None: return "none";
    case SurfaceGi::RestirBiased: return "ReSTIR GI, biased";
    case SurfaceGi::RestirUnbiased: return "ReSTIR GI, unbiased";
    case SurfaceGi::PathTraced: return "one bounce path traced per sample and frame, no reuse";
  }
  return "?";
}

}  // namespace

FramePlan plan_surface_frame(const SurfaceContents& scene, const SurfaceFrameSettings& settings) {
  const SurfacePasses& passes = settings.passes;
  if (settings.gi != SurfaceGi::None && passes.gi.empty())
    throw std::logic_error("plan_surface_frame: mode " + settings.mode + " asks for GI its backend does not host");
  PlanBuilder plan;
  if (scene.triangles == 0) {
    for (const char* role : {"pre-z", "allocation", "shading", "shadow rays", "gi", "display"}) plan.skip(role, "no surfaces in the scene");
    FramePlan result;
    result.skipped = std::move(plan.skipped);
    return result;
  }
  // Shadow rays: asked for, traceable, and something to cast them.
  std::string no_shadows;
  if (passes.shadow_rays.name.empty()) no_shadows = passes.shadow_rays.what;
  else if (!settings.device_traces_rays) no_shadows = "the device traces no rays (no ray-tracing pipeline)";
  else if (!settings.shadows) no_shadows = "shadows are off";
  else if (!scene.casts_shadows()) no_shadows = "no light casts shadows";
  const bool shadows = no_shadows.empty();
  const auto what = [&](const SurfaceStep& step) { return shadows && !step.with_shadows.empty() ? step.with_shadows : step.what; };
  const auto role = [&](PassId id, const SurfaceStep& step, const char* role_name) {
    if (step.name.empty()) plan.skip(role_name, step.what);
    else plan.run(id, step.name, PassKind::Gpu, what(step));
  };
  role(PassId::SurfacePreZ, passes.pre_z, "pre-z");
  role(PassId::SurfaceAllocation, passes.allocation, "allocation");
  role(PassId::SurfaceShading, passes.shading, "shading");
  if (shadows)
    plan.run(PassId::ShadowRays, passes.shadow_rays.name, PassKind::Within,
             shadow_casters(scene) + (casters_are_one(scene) ? " casts" : " cast") + " shadows: " + passes.shadow_rays.what);
  else
    plan.skip("shadow rays", no_shadows);
  // GI: asked for, and light to bounce.
  if (settings.gi == SurfaceGi::None) {
    plan.skip("gi", "no indirect light asked for (mode " + settings.mode + ")");
  } else if (!scene.lit()) {
    plan.skip("gi", "indirect light asked for, but no light, emitter or sky lights the scene: nothing to bounce");
  } else {
    const std::string why = std::string("one-bounce indirect light asked for (mode ") + settings.mode + ": " + gi_words(settings.gi) +
                            "), bouncing the light of " + light_sources(scene) + " off " + count_of(scene.triangles, "triangle", "triangles");
    for (const SurfaceStep& step : passes.gi) plan.run(PassId::GlobalIllumination, step.name, PassKind::Gpu, why + ": " + step.what);
  }
  role(PassId::SurfaceDisplay, passes.display, "display");
  FramePlan result;
  result.passes = std::move(plan.gpu);
  result.skipped = std::move(plan.skipped);
  return result;
}

}  // namespace prismoid::frame
