#include "app/common/frame_stats_writer.hpp"

#include <algorithm>
#include <cmath>
#include <sstream>
#include <variant>

#include "app/common/cli_args.hpp"
#include "app/common/volume_options.hpp"

namespace prismoid::app {

namespace {

using mixed::FrameStats;
using mixed::VolumeStats;

bool is_color(const VolumeStats& v) { return v.settings.resolve.quantity == volume::Quantity::Color; }

std::string ordering_text(const frame::FrameReport& r) { return r.ordering + (r.order_exact ? " [exact]" : " [approximate]"); }

// What the frame holds, for the first line.
std::string contents_text(const FrameStats& s) {
  std::ostringstream out;
  if (s.volume) {
    out << s.volume->dataset << ", " << s.volume->cells << " cells";
    if (s.mixed) out << ", with " << s.mixed->scene << ", " << s.mixed->triangles << " triangles";
  } else if (s.surfaces) {
    const mixed::SurfaceStats& f = *s.surfaces;
    out << f.scene << ", " << f.triangles << " triangles, " << f.emitters << " emissive" << (f.counts.space.empty() ? "" : ", " + f.counts.space);
    if (f.supersample > 1) out << ", " << f.supersample << "x" << f.supersample << " supersampled";
  }
  return out.str();
}

// The volume's backend, its memory and its counts (GPU frames).
void volume_backend_text(std::ostream& out, const FrameStats& s, bool with_backend) {
  const frame::FrameReport& r = s.volume->report;
  const double cells = static_cast<double>(std::max<uint64_t>(s.volume->cells, 1));
  const double pixels = static_cast<double>(s.width) * s.height;
  if (with_backend) {
    const std::string& reason = s.volume->settings.backend_reason;
    out << "  backend: " << r.backend << (reason.empty() ? "" : " (" + reason + ")");
    if (r.backend_bytes > 0)  // the compute backend's tile lists and keys (the mesh backend has none)
      out << "; its memory " << r.backend_bytes << " bytes (" << json_number(static_cast<double>(r.backend_bytes) / cells) << " per cell, "
          << json_number(static_cast<double>(r.backend_bytes) / pixels) << " per pixel)";
    out << "\n";
  }
  if (r.counts_known)
    out << "  pairs: " << r.pairs << " (tile, cell); pixels composited out of exact order: " << r.inexact_pixels
        << "; tiles rastered in chunks: " << r.split_tiles << " (" << r.chunks << " chunks, " << r.redone_tiles
        << " rastered again whole for colour order); cells binned by a workgroup: " << r.big_cells << "\n";
}

// The passes, each with its spread where frames were timed, and their total.
void passes_text(std::ostream& out, const FrameStats& s) {
  const char* where = s.gpu ? " GPU" : " CPU";
  const bool spread = s.timing && s.frames > 1;
  for (size_t i = 0; i < s.passes.size(); ++i) {
    const vk::PassTiming& p = s.passes[i];
    out << "  " << p.name << ": " << (std::isfinite(p.gpu_ms) ? json_number(p.gpu_ms) + " ms" : "no timestamps") << where;
    if (spread && std::isfinite(p.gpu_ms) && i < s.timing->passes.size())
      out << " (best " << json_number(s.timing->passes[i].ms.best) << ", worst " << json_number(s.timing->passes[i].ms.worst) << ")";
    out << "\n";
  }
  if (s.passes.empty()) return;
  out << "  total: " << json_number(s.passes_ms()) << " ms" << where;
  if (spread)
    out << " (medians of " << s.frames << " frames; a whole frame: best " << json_number(s.timing->total_ms.best) << ", median "
        << json_number(s.timing->total_ms.median) << ", worst " << json_number(s.timing->total_ms.worst) << ")";
  out << "\n";
  if (s.timing) print_sm_clock(out, *s.timing);
}

void surfaces_text(std::ostream& out, const mixed::SurfaceStats& f) {
  const surface::BackendCounts& c = f.counts;
  out << "  covered: " << f.covered_pixels << " pixels" << (c.shaded_field.empty() ? "" : ", " + std::to_string(c.shaded) + " shading invocations")
      << (c.summary.empty() ? "" : c.summary.front()) << "\n";
  for (size_t i = 1; i < c.summary.size(); ++i) out << "  " << c.summary[i] << "\n";
  if (f.default_lighting) out << "  no lights in the scene: default key light (it casts shadows) and sky\n";
}

// The volume's settings and what its frame drew.
void volume_json(StatsJson& js, const FrameStats& s) {
  const VolumeStats& v = *s.volume;
  const frame::FrameReport& r = v.report;
  const volume::ResolveSettings& resolve = v.settings.resolve;
  js["ordering"] = r.ordering;
  js["order_exact"] = r.order_exact;
  js["gpu_mesh_bytes"] = r.mesh_bytes;
  if (s.gpu) {
    const double cells = static_cast<double>(std::max<uint64_t>(v.cells, 1));
    const double pixels = static_cast<double>(s.width) * s.height;
    js["backend"] = r.backend;
    js["backend_reason"] = v.settings.backend_reason;
    js["backend_bytes"] = r.backend_bytes;
    js["backend_bytes_per_cell"] = static_cast<double>(r.backend_bytes) / cells;
    js["backend_bytes_per_pixel"] = static_cast<double>(r.backend_bytes) / pixels;
    if (r.counts_known) {
      js["pairs"] = r.pairs;
      js["inexact_pixels"] = r.inexact_pixels;
      js["split_tiles"] = r.split_tiles;
      js["chunks"] = r.chunks;
      js["redone_tiles"] = r.redone_tiles;
      js["big_cells"] = r.big_cells;
    }
  }
  if (r.counted) {  // as the driver counts them (lavapipe counts no clipper input for mesh shaders)
    js["fragments"] = r.fragments;
    if (r.primitives > 0) js["proxy_triangles"] = r.primitives;
  }
  js["tetlet_size"] = resolve.tetlet_size;
  js["shared_vertices"] = resolve.shared_vertices;
  if (r.tetlet_points_per_cell > 0.0) js["tetlet_points_per_cell"] = r.tetlet_points_per_cell;
  if (is_color(v)) {
    js["transfer_function"] = resolve.transfer.name;
    js["tf_range"] = {resolve.transfer.range_lo, resolve.transfer.range_hi};
    js["preintegration_size"] = resolve.preintegration_size;
  }
  if (v.analytic_field) {
    js["field"] = resolve.march.field.name;
    js["march_step"] = resolve.march.step;
    if (resolve.quantity == volume::Quantity::Isosurface) js["isovalue"] = resolve.march.isovalue;
  }
}

void surfaces_json(StatsJson& js, const mixed::SurfaceStats& f) {
  if (f.takes_supersample) js["supersample"] = f.supersample;
  js["triangles"] = f.triangles;
  js["emitters"] = f.emitters;
  js["gpu_scene_bytes"] = f.gpu_scene_bytes;
  js["covered_pixels"] = f.covered_pixels;
  js["default_lighting"] = f.default_lighting;
  js["shadows"] = f.shadows;
  if (!f.counts.shaded_field.empty()) js[f.counts.shaded_field] = f.counts.shaded;
  for (const auto& [key, value] : f.counts.stats) std::visit([&, &key = key](const auto& x) { js[key] = x; }, value);
}

}  // namespace

namespace {

void path_text(std::ostream& out, const FrameStats& s, const FrameOutput& output) {
  const mixed::PathStats& p = *s.path;
  const reference::PathTracerCounts& c = p.counts;
  out << "wrote " << output.image << " (" << s.width << "x" << s.height << ", " << p.scene << ", " << p.settings.samples_per_pixel
      << " samples per pixel, at most " << p.settings.max_bounces << " bounces) on the CPU path tracer in " << json_number(p.seconds)
      << " s\n"
      << "  " << c.rays << " rays; guards: " << c.zero_pdf << " zero-pdf samples, " << c.non_finite << " non-finite samples, "
      << c.backfacing_normals << " back-facing shading normals, " << c.degenerate_triangles << " degenerate triangles skipped\n";
  if (p.default_lighting) out << "  no lights in the scene: default key light (it casts shadows) and sky\n";
}

StatsJson path_json(const FrameStats& s) {
  const mixed::PathStats& p = *s.path;
  StatsJson js;
  js["device"] = s.device;
  js["dataset"] = p.scene;
  js["mode"] = p.mode;
  js["width"] = s.width;
  js["height"] = s.height;
  js["samples_per_pixel"] = p.settings.samples_per_pixel;
  js["max_bounces"] = p.settings.max_bounces;
  js["seed"] = p.settings.seed;
  js["seconds"] = p.seconds;
  js["rays"] = p.counts.rays;
  js["zero_pdf"] = p.counts.zero_pdf;
  js["non_finite"] = p.counts.non_finite;
  js["backfacing_normals"] = p.counts.backfacing_normals;
  js["degenerate_triangles"] = p.counts.degenerate_triangles;
  return js;
}

}  // namespace

std::string frame_text(const FrameStats& s, const FrameOutput& output) {
  std::ostringstream out;
  if (s.path) {
    path_text(out, s, output);
    return out.str();
  }
  out << "wrote " << output.image << " (" << s.width << "x" << s.height << ", " << contents_text(s) << ") on " << s.device << "\n";
  if (s.volume && s.mixed) {
    const frame::FrameReport& r = s.volume->report;
    out << "  volume: --mode " << s.volume->mode << (s.gpu ? ", backend " + r.backend : "") << ", ordering " << ordering_text(r)
        << "; surfaces: " << (s.gpu ? "--surface-mode " + s.mixed->mode : std::string("direct light (forward's reference)"))
        << (s.mixed->shadows ? " with shadows" : " without shadows") << ", opaque, ending the volume's rays\n";
    if (s.gpu) volume_backend_text(out, s, false);
  } else if (s.volume) {
    out << "  ordering: " << ordering_text(s.volume->report) << "\n";
    if (s.gpu) volume_backend_text(out, s, true);
  }
  passes_text(out, s);
  if (output.accuracy && s.volume)
    print_accuracy(out, *output.accuracy, is_color(*s.volume),
                   std::string("double precision, exact per-pixel order") +
                       (s.mixed ? std::string(", the surfaces' direct light") + (s.mixed->shadows ? " with shadows" : "") : ""));
  for (const vk::PassTiming& p : s.cpu_passes) out << "  " << p.name << ": " << json_number(p.gpu_ms) << " ms CPU\n";
  if (s.volume && !s.mixed && s.volume->report.counted) {
    const frame::FrameReport& r = s.volume->report;
    out << "  drawn: " << r.fragments << " fragments";
    if (r.primitives > 0) out << ", " << r.primitives << " proxy triangles";
    out << "\n";
  }
  if (s.surfaces) surfaces_text(out, *s.surfaces);
  return out.str();
}

StatsJson frame_json(const FrameStats& s, const FrameOutput& output) {
  if (s.path) return path_json(s);
  StatsJson js;
  js["device"] = s.device;
  js["driver"] = s.driver;
  if (s.volume) {
    js["dataset"] = s.volume->dataset;
    js["cells"] = s.volume->cells;
    if (s.mixed) {
      js["surfaces"] = s.mixed->scene;
      js["triangles"] = s.mixed->triangles;
    }
    js["mode"] = s.volume->mode;
    if (s.mixed) {
      js["surface_mode"] = s.mixed->mode;
      js["shadows"] = s.mixed->shadows;
    }
    js["quantity"] = quantity_name(s.volume->settings.resolve.quantity);
  } else if (s.surfaces) {
    js["dataset"] = s.surfaces->scene;
    js["mode"] = s.surfaces->mode;
    js["quantity"] = "color";
  }
  js["width"] = s.width;
  js["height"] = s.height;
  if (s.volume) volume_json(js, s);
  if (s.surfaces) surfaces_json(js, *s.surfaces);
  js["warnings"] = s.warnings;
  if (s.volume || (s.surfaces && s.surfaces->takes_frames)) js["frames"] = s.frames;
  js["passes"] = s.timing ? passes_json(*s.timing) : passes_json(s.passes);
  if (s.timing) add_sm_clock(js, *s.timing);
  if (s.volume) js["cpu_passes"] = cpu_passes_json(s.cpu_passes);
  if (s.mixed_plan) add_plan(js, *s.mixed_plan);
  else if (s.plan) add_plan(js, *s.plan);
  js["gpu_ms_total"] = s.passes_ms();
  if (s.timing) js["frame_ms"] = {{"best", s.timing->total_ms.best}, {"median", s.timing->total_ms.median}, {"worst", s.timing->total_ms.worst}};
  js["validation_messages"] = output.validation_messages;
  if (output.accuracy && s.volume) add_accuracy(js, *output.accuracy, is_color(*s.volume));
  return js;
}

}  // namespace prismoid::app
