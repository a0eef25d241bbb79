#pragma once
// The frame planner: the passes a frame runs, derived from what the scene contains and from
// what the last frame left behind, each with the reason it is there, and the passes it leaves
// out, each with why. FrameRenderer records exactly the planned passes (nothing else creates
// passes); `prismoid info --plan`, `render --stats` and the window's frame plan show them.
// No Vulkan here: plan_frame is a pure function.
#include <cstdint>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "renderer/volume/resolve_settings.hpp"
#include "scene/tet_mesh_fwd.hpp"

namespace prismoid::frame {

// The order cells are drawn in. It matters only for order-dependent quantities (colour);
// order-independent ones always draw in mesh order and never sort.
enum class Ordering {
  MeshOrder,  // as stored: exact only for order-independent quantities
  GpuSort,    // per-frame radix sort on the GPU by centroid distance (approximate)
  Exact,      // topological order over face adjacency (MPVONC): exact for convex acyclic meshes
};
const char* ordering_name(Ordering ordering);

// The GPU backend that draws a volume frame's intervals (the resolve after them is shared), by
// its name in the volume backend table (renderer/volume/volume_backends.hpp): a backend is a
// line of that table, and nothing here lists them. The name is the table's (a literal).
struct IntervalBackend {
  std::string_view name = "mesh";
  // The first two of the table: mesh shaders and the rasterizer (Tricard 2024), and compute
  // shaders on every core (volume/compute/compute_intervals.hpp).
  static const IntervalBackend Mesh, Compute;
  friend bool operator==(const IntervalBackend&, const IntervalBackend&) = default;
};
inline constexpr IntervalBackend IntervalBackend::Mesh{"mesh"};
inline constexpr IntervalBackend IntervalBackend::Compute{"compute"};
const char* interval_backend_name(IntervalBackend backend);  // its name

struct FrameSettings {
  volume::ResolveSettings resolve;
  Ordering ordering = Ordering::GpuSort;  // the mesh backend's draw order (the compute backend orders per pixel)
  IntervalBackend backend = IntervalBackend::Mesh;
  // Why `backend` draws this frame where it was not asked for by name (--volume-backend auto:
  // the calibration's numbers, frame/backend_choice.hpp); shown in the plan. Empty otherwise.
  std::string backend_reason;
};

// How a volume interacts with light in this frame.
enum class VolumeOptics {
  AbsorptionOnly,      // optical depth, transmittance: sums of sigma * length commute
  EmissionAbsorption,  // colour through a transfer function: compositing is order dependent
  Isosurface,          // the nearest level-set hit, kept by the depth test
};
// How the field inside a cell is known.
enum class FieldModel {
  PerCell,  // constant per cell: integrated exactly
  Linear,   // a point field, linear in each cell: integrated exactly
  Marched,  // non-linear (analytic or sampled grid): marched in steps inside each interval
};

struct VolumeContents {
  VolumeOptics optics = VolumeOptics::AbsorptionOnly;
  FieldModel field = FieldModel::PerCell;
  uint64_t cells = 0;
};

// What a scene says it contains, and what changed since the last frame its renderer recorded.
// The history defaults describe a first frame: everything changed, nothing to reuse.
struct SceneContents {
  std::vector<VolumeContents> volumes;  // one today: FrameRenderer draws one mesh
  uint32_t surfaces = 0;                // none is renderable yet (the surface issues)
  uint32_t lights = 0;
  uint32_t emissive_surfaces = 0;
  bool indirect_wanted = false;
  bool camera_moved = true;      // the eye moved (a visibility order depends on nothing else of the camera)
  bool scene_moved = true;       // geometry or fields changed
  bool transfer_changed = true;  // the transfer function or the pre-integration table size changed
  // What the last frame left in device memory that this one may reuse:
  std::optional<Ordering> order_kept;  // the ordering that made the order buffer the last frame drew with
  bool tetlets_built = false;          // tetlets of the settings' size exist
};

// A volume's contents in a frame with these settings (quantity, marching).
VolumeContents volume_contents(uint64_t cells, bool point_extinction, bool point_scalars, const volume::ResolveSettings& settings);
VolumeContents volume_contents(const TetMesh& mesh, const volume::ResolveSettings& settings);

// What each pass is, for the renderer that records it (names are for people and stats).
enum class PassId {
  TransferUpload,   // "transfer-function upload" (CPU): breakpoints for exact segment integrals
  Preintegrate,     // "preintegrate" (CPU): the N^3 table (and the breakpoints)
  BuildTetlets,     // "build-tetlets" (CPU)
  ExactOrder,       // "exact-order" (CPU)
  Sort,             // "sort" (GPU): keys and radix sort
  UploadOrder,      // "upload-order" (GPU): the CPU's order into device memory
  Intervals,        // volume::interval_pass_name(settings) (GPU)
  BinCells,         // "bin-cells" (GPU, compute backend): cells' tiles, counted, allocated, written as pairs
  TileSort,         // "tile-sort" (GPU, compute backend): pairs sorted by (tile, depth), tile ranges
  TileRaster,       // "tile-raster" (GPU, compute backend): each pixel's intervals, integrated
  Resolve,          // "resolve" (GPU)
  SurfaceShading,   // "surface-shading" in volume plans (never planned there); a surface backend's shading pass
  GlobalIllumination,  // "gi" in volume plans (never planned there); a surface backend's indirect-light passes
  SurfacePreZ,      // a surface backend's depth pre-pass (with its visibility or marking where it fuses them)
  SurfaceAllocation,  // where a texture-space backend's shading lives this frame (pages, blocks)
  ShadowRays,       // traced by the surface shading pass (PassKind::Within)
  SurfaceDisplay,   // the image from the shaded samples (gather, display)
};
// Within: work done inside the GPU pass listed before it (shadow rays traced by the shading
// pass's shaders): planned and explained like a pass, but not timed on its own.
enum class PassKind { Gpu, Cpu, Within };

struct PlannedPass {
  PassId id;
  std::string name;  // = the timestamp pair's name (GPU) or the CPU stage's name in FrameReport
  PassKind kind;
  std::string reason;
};
struct SkippedPass {
  std::string name;
  std::string reason;
};

struct FramePlan {
  std::vector<PlannedPass> passes;  // in the order they run: CPU passes (prepare), then GPU passes (record)
  std::vector<SkippedPass> skipped;
  bool reuses_order = false;        // the order buffer of the last frame is drawn with again
  bool has(std::string_view name) const;
  const PlannedPass* find(PassId id) const;
  std::vector<std::string> gpu_pass_names() const;
};

// Throws InputError for settings no plan satisfies (tetlets with an ordered colour mode, or
// with a backend that builds none). The volume's passes are those of the backend that
// settings.backend names: defined beside the volume backend table (it reads the table), and
// frame/volume_passes.hpp plans with a backend's passes given.
FramePlan plan_frame(const SceneContents& scene, const FrameSettings& settings);

// One line per pass: "  NAME (GPU|CPU): REASON" ("(GPU, within the pass above)" for
// PassKind::Within), then "  NAME: skipped, REASON".
std::string format_plan(const FramePlan& plan);
// "GPU", "CPU" or "GPU, within the pass above": how a pass runs, for people.
const char* pass_kind_text(PassKind kind);

// ---- Surfaces: a frame of one surface scene drawn by one surface backend ----

// What a surface scene holds, for the planner.
struct SurfaceContents {
  uint64_t triangles = 0;
  uint32_t point_lights = 0;
  uint32_t directional_lights = 0;
  uint32_t emissive_triangles = 0;
  bool sky = false;  // the sky is not black (it lights the scene as ambient light, or through GI's rays)
  bool casts_shadows() const { return point_lights + directional_lights + emissive_triangles > 0; }
  bool lit() const { return casts_shadows() || sky; }
};

// The indirect light a surface mode asks for (renderer/surface/surface_modes.hpp). Hosted by a
// backend whose SurfacePasses has GI passes.
enum class SurfaceGi {
  None,
  RestirBiased,    // ReSTIR GI as the paper ships it (biased)
  RestirUnbiased,  // with the bias-correcting shadow ray and count normalization
  PathTraced,      // one fresh bounce sample per sample and frame, nothing reused: the baseline
};
// The --gi word of each: off, biased, unbiased, path-traced.
const char* surface_gi_name(SurfaceGi gi);

// One GPU pass of a surface backend: its timestamp name and what it does (the plan's reason when
// it runs; `with_shadows` instead when the frame traces shadow rays, if not empty). A role the
// backend has no pass for has an empty name, and `what` says why it needs none.
struct SurfaceStep {
  std::string name;
  std::string what;
  std::string with_shadows;
};

// A surface backend's GPU passes by the role each plays in a frame, in the order they run: what
// the backend records (SurfaceBackend), plain data the planner composes a frame from.
struct SurfacePasses {
  SurfaceStep pre_z;       // the depth pre-pass, with visibility or marking where the backend fuses them
  SurfaceStep allocation;  // where shading lives this frame (pages, blocks)
  SurfaceStep shading;     // the shading code over the visible samples (it traces the shadow rays)
  SurfaceStep shadow_rays; // within shading: how its shadow rays are cast (empty name: it cannot trace them)
  std::vector<SurfaceStep> gi;  // the indirect-light passes it hosts, after shading (none: it hosts no GI)
  SurfaceStep display;     // the image from the shaded samples
};

struct SurfaceFrameSettings {
  std::string mode;        // the mode's name, for the reasons
  SurfacePasses passes;    // its backend's
  SurfaceGi gi = SurfaceGi::None;  // the indirect light the mode asks for
  bool shadows = true;     // shadows asked for (the renderer's setting: on by default where rays are traced)
  bool device_traces_rays = false;
};

// The GPU passes of a surface frame, each with why, and each role left out with why (named by
// its role: "pre-z", "allocation", "shading", "shadow rays", "gi", "display"): shadow rays only
// where shadows are asked for, the device traces rays and a light casts them; GI passes only
// where the mode asks for indirect light and something lights the scene to bounce. Pure, like
// plan_frame. Throws std::logic_error when the mode asks for GI its backend does not host.
FramePlan plan_surface_frame(const SurfaceContents& scene, const SurfaceFrameSettings& settings);

}  // namespace prismoid::frame
