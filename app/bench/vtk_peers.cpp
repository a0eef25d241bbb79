#include "app/bench/vtk_peers.hpp"

// How our model maps onto VTK's, and where VTK's necessarily differs.
//
// Our model (renderer/volume/segment_integral.hpp): along a ray, extinction sigma(s) and colour
// c(s) come from a transfer function of the scalar s, both piecewise linear in s; light reaching
// the eye is the integral of sigma c exp(-tau), and the background shows through exp(-tau).
//
// Transfer function. We hand VTK the function's breakpoints (volume::breakpoints: the union of
// the colour and opacity points plus the ends of the range, each with both values) as
// vtkColorTransferFunction RGB points and vtkPiecewiseFunction points at the same scalars
// (s = range_lo + x (range_hi - range_lo)), both clamping beyond the ends as ours does. VTK's
// unstructured-grid integrators and projected tetrahedra read the scalar opacity function's value
// divided by the property's scalar opacity unit distance as the attenuation coefficient itself
// (not as the opacity 1 - exp(-sigma d) of a slab of thickness d, which is what VTK's
// structured-volume ray casters mean by it). So opacity_vtk(s) = sigma(s) / sigma_max and unit
// distance = 1 / sigma_max give sigma exactly and piecewise linear in s, as ours, while using the
// whole [0, 1] range of the opacity function (projected tetrahedra keep it in 8 bits). The colour
// model is the same: emission sigma c, colour in linear RGB, no shading (ShadeOff), linear
// interpolation of the scalar inside each cell, the renderer's background = ours.
//
// Where VTK differs, peer by peer:
// - Every peer: the picture ends in VTK's 8-bit RGBA framebuffer (read back here as bytes / 255,
//   no sRGB encoding: VTK writes linear values as they are, and so do we), so every channel is
//   off by up to 0.5/255 from rounding alone; geometry goes through VTK's own matrices.
// - vtk-ray-cast (vtkUnstructuredGridVolumeRayCastMapper, Bunyk's cell-to-cell traversal): we
//   give it vtkUnstructuredGridLinearRayIntegrator, its most exact integrator (Moreland & Angel's
//   closed form for colour and attenuation linear along each segment, split at the transfer
//   function's control points; float arithmetic and an erf fit good to about 1e-7). The default
//   for point data, vtkUnstructuredGridPartialPreIntegration, tabulates the same integral.
//   Geometry: the ray of image sample (X, Y) runs through the window point (X, Y), a pixel
//   corner (its entry and exit depths come exactly from the faces' screen-space planes), but each
//   segment's length is measured between those depths un-projected at NDC (2X/(W-1) - 1,
//   2Y/(H-1) - 1), i.e. along a slightly different ray. The samples are drawn as a linearly
//   filtered texture stretched so that window pixel x shows the samples around (x + 0.5)(W-1)/W:
//   the picture lies up to a pixel off ours and is slightly blurred. It stops integrating once
//   alpha reaches 0.99 (after a batch of cells), and it stores premultiplied colour and alpha in
//   8 bits by truncation (up to 1/255 low each; alpha's moves the background's share by up to
//   bg/255) before blending them over the background. When a mesh vertex projects exactly onto
//   the ray grid (at even sizes the ball's centre, which fitted cameras look at), the column of
//   rays through it loses its absorption (a bright line). Sample distance auto-adjustment is
//   off: one ray per pixel.
// - vtk-zsweep (vtkUnstructuredGridVolumeZSweepMapper, Farias et al.'s sweep of the faces in
//   depth order): the same linear ray integrator; scalars at the faces are interpolated across
//   each face's screen projection by its own scan conversion of vertices truncated to whole
//   pixels; its image goes through 8 bits and is drawn like the ray caster's.
// - vtk-projected-tetrahedra (vtkProjectedTetrahedraMapper, Shirley & Tuchman with Wylie's
//   thick-vertex split): cells are sorted back to front by their centres (not an exact visibility
//   order for every mesh); colour and opacity are looked up per vertex (point scalars) or per
//   cell and truncated to 8 bits each; across the projected triangles the colour and attenuation
//   are interpolated linearly in screen space, and at the thick vertex they are the average of
//   the front and back values, so each cell's fragment gets alpha = 1 - exp(-sigma_avg l) with an
//   averaged colour instead of the exact integral of a linearly varying sigma and c; blended in a
//   float framebuffer, then copied into the 8-bit one. It drops any cell with a vertex in front of
//   the near plane (our reference clips such a cell at the near plane instead).
//
// Precision: the mesh and the camera are moved by the same offset (the centre of the mesh's
// bounds) before VTK sees them, as our renderer does with its local origin; that changes no ray.
#include <algorithm>
#include <chrono>
#include <cmath>
#include <sstream>
#include <stdexcept>

#include <glm/geometric.hpp>

#include <vtkAutoInit.h>
VTK_MODULE_INIT(vtkRenderingOpenGL2);
VTK_MODULE_INIT(vtkRenderingVolumeOpenGL2);

#include <vtkCallbackCommand.h>
#include <vtkCamera.h>
#include <vtkCellArray.h>
#include <vtkCellData.h>
#include <vtkCellType.h>
#include <vtkColorTransferFunction.h>
#include <vtkCommand.h>
#include <vtkDoubleArray.h>
#include <vtkIdTypeArray.h>
#include <vtkNew.h>
#include <vtkOpenGLRenderWindow.h>
#include <vtkPiecewiseFunction.h>
#include <vtkPointData.h>
#include <vtkPoints.h>
#include <vtkProjectedTetrahedraMapper.h>
#include <vtkRenderWindow.h>
#include <vtkRenderer.h>
#include <vtkSmartPointer.h>
#include <vtkUnsignedCharArray.h>
#include <vtkUnstructuredGrid.h>
#include <vtkUnstructuredGridLinearRayIntegrator.h>
#include <vtkUnstructuredGridVolumeRayCastMapper.h>
#include <vtkUnstructuredGridVolumeZSweepMapper.h>
#include <vtkVolume.h>
#include <vtkVolumeProperty.h>

#include "app/bench/x_display.hpp"
#include "scene/input_error.hpp"
#include "scene/tet_mesh.hpp"

namespace prismoid::bench {

std::string_view peer_name(Peer peer) {
  switch (peer) {
    case Peer::ProjectedTetrahedra: return "vtk-projected-tetrahedra";
    case Peer::RayCast: return "vtk-ray-cast";
    case Peer::ZSweep: return "vtk-zsweep";
  }
  return "vtk-unknown";
}

namespace {

// The optical model in VTK's terms: which scalars, and the piecewise-linear colour and
// extinction over them.
struct OpticalModel {
  const std::vector<double>* scalars = nullptr;
  bool per_point = false;
  std::vector<double> s;              // breakpoints, increasing
  std::vector<glm::dvec3> rgb;        // colour at each breakpoint
  std::vector<double> sigma;          // extinction at each breakpoint
};

OpticalModel optical_model(const TetMesh& mesh, const volume::ResolveSettings& resolve, const std::string& source) {
  OpticalModel m;
  if (resolve.quantity == volume::Quantity::Color) {
    m.per_point = !mesh.point_scalars.empty();
    m.scalars = m.per_point ? &mesh.point_scalars : &mesh.cell_scalars;
    if (m.scalars->empty())
      throw InputError(mesh.name, "has no scalar field for the transfer function (" + source + " renders colour from scalars)");
    volume::validate(resolve.transfer);
    const auto& tf = resolve.transfer;
    for (const volume::TfSample& b : volume::breakpoints(tf)) {
      m.s.push_back(tf.range_lo + b.x * (tf.range_hi - tf.range_lo));
      m.rgb.push_back(b.rgb);
      m.sigma.push_back(b.sigma);
    }
  } else if (resolve.quantity == volume::Quantity::Transmittance || resolve.quantity == volume::Quantity::OpticalDepth) {
    // The display of both is mix(medium, background, exp(-tau)): constant colour `medium`, and
    // the extinction is the scalar, mapped to itself.
    m.per_point = mesh.linear_extinction();
    m.scalars = m.per_point ? &mesh.point_extinction : &mesh.cell_extinction;
    const double top = m.scalars->empty() ? 0.0 : *std::max_element(m.scalars->begin(), m.scalars->end());
    const double hi = top > 0.0 ? top : 1.0;
    const glm::dvec3 medium(resolve.medium);
    m.s = {0.0, hi};
    m.rgb = {medium, medium};
    m.sigma = {0.0, hi};
  } else {
    throw InputError(source, "has no VTK peer for the isosurface quantity");
  }
  return m;
}

// Collects the messages VTK reports through ErrorEvent instead of printing them.
struct ErrorLog {
  std::vector<std::string> messages;
  vtkNew<vtkCallbackCommand> command;
  ErrorLog() {
    command->SetClientData(this);
    command->SetCallback([](vtkObject* caller, unsigned long, void* client, void* call) {
      auto* self = static_cast<ErrorLog*>(client);
      std::string text = call ? static_cast<const char*>(call) : "unknown error";
      while (!text.empty() && (text.back() == '\n' || text.back() == ' ')) text.pop_back();
      self->messages.push_back(std::string(caller ? caller->GetClassName() : "VTK") + ": " + text);
    });
  }
  void watch(vtkObject* object) { object->AddObserver(vtkCommand::ErrorEvent, command); }
  // A render window that cannot make its GL context calls abort() unless someone observes its
  // ExitEvent: then it returns, and the error it reported first is thrown.
  void watch_exit(vtkObject* window) {
    exit_command->SetClientData(this);
    exit_command->SetCallback([](vtkObject*, unsigned long, void* client, void*) {
      static_cast<ErrorLog*>(client)->messages.push_back("the render window gave up (no usable GL context)");
    });
    window->AddObserver(vtkCommand::ExitEvent, exit_command);
  }
  vtkNew<vtkCallbackCommand> exit_command;
  void throw_if_any(std::string_view peer) const {
    if (messages.empty()) return;
    std::string all;
    for (const auto& m : messages) all += (all.empty() ? "" : "; ") + m;
    throw std::runtime_error(std::string(peer) + ": VTK reported an error: " + all);
  }
};

// The GL_RENDERER line of VTK's capability report.
std::string renderer_string(vtkRenderWindow* window) {
  const char* report = window->ReportCapabilities();
  if (!report) return "";
  std::istringstream lines(report);
  std::string line;
  const std::string key = "OpenGL renderer string:";
  while (std::getline(lines, line)) {
    const auto at = line.find(key);
    if (at == std::string::npos) continue;
    std::string value = line.substr(at + key.size());
    value.erase(0, value.find_first_not_of(" \t"));
    return value;
  }
  return "";
}

}  // namespace

PeerFrame render_peer(Peer peer, const TetMesh& mesh, const Camera& camera, const volume::ResolveSettings& resolve,
                      uint32_t width, uint32_t height, uint32_t frames) {
  const std::string name(peer_name(peer));
  if (width == 0 || height == 0)
    throw InputError(name, "the image size must be at least 1x1, got " + std::to_string(width) + "x" + std::to_string(height));
  if (width > 16384 || height > 16384) throw InputError(name, "the image size is limited to 16384x16384");
  if (mesh.tets.empty() || mesh.points.empty()) throw InputError(mesh.name.empty() ? name : mesh.name, "has no cells to render");
  if (resolve.march.enabled) throw InputError(name, "renders the mesh's own field; a marched analytic field has no VTK peer");
  validate(mesh);
  validate(camera);
  const OpticalModel model = optical_model(mesh, resolve, name);

  // VTK's window draws on this connection (declared first, so it outlives every VTK object):
  // VTK opening its own would abort the process when the display cannot be opened.
  const XConnection x_connection;

  // Mesh and camera relative to the centre of the bounds (see the note at the top).
  const Bounds bounds = bounds_of(mesh);
  const glm::dvec3 origin = bounds.center();

  vtkNew<vtkPoints> points;
  points->SetDataTypeToDouble();
  points->SetNumberOfPoints(static_cast<vtkIdType>(mesh.points.size()));
  for (size_t i = 0; i < mesh.points.size(); ++i) {
    const glm::dvec3 p = mesh.points[i] - origin;
    points->SetPoint(static_cast<vtkIdType>(i), p.x, p.y, p.z);
  }
  vtkNew<vtkUnstructuredGrid> grid;
  grid->SetPoints(points);
  grid->Allocate(static_cast<vtkIdType>(mesh.tets.size()));
  for (const auto& t : mesh.tets) {
    const vtkIdType ids[4] = {t[0], t[1], t[2], t[3]};
    grid->InsertNextCell(VTK_TETRA, 4, ids);
  }
  vtkNew<vtkDoubleArray> scalars;
  scalars->SetName("scalar");
  scalars->SetNumberOfComponents(1);
  scalars->SetNumberOfTuples(static_cast<vtkIdType>(model.scalars->size()));
  for (size_t i = 0; i < model.scalars->size(); ++i) scalars->SetValue(static_cast<vtkIdType>(i), (*model.scalars)[i]);
  if (model.per_point) grid->GetPointData()->SetScalars(scalars);
  else grid->GetCellData()->SetScalars(scalars);

  // The transfer function: see the note at the top.
  const double sigma_max = *std::max_element(model.sigma.begin(), model.sigma.end());
  vtkNew<vtkColorTransferFunction> color;
  color->SetColorSpaceToRGB();
  color->ClampingOn();
  vtkNew<vtkPiecewiseFunction> opacity;
  opacity->ClampingOn();
  for (size_t i = 0; i < model.s.size(); ++i) {
    color->AddRGBPoint(model.s[i], model.rgb[i].r, model.rgb[i].g, model.rgb[i].b);
    opacity->AddPoint(model.s[i], sigma_max > 0.0 ? model.sigma[i] / sigma_max : 0.0);
  }
  vtkNew<vtkVolumeProperty> property;
  property->SetColor(color);
  property->SetScalarOpacity(opacity);
  property->SetScalarOpacityUnitDistance(sigma_max > 0.0 ? 1.0 / sigma_max : 1.0);
  property->SetInterpolationTypeToLinear();
  property->ShadeOff();
  property->IndependentComponentsOn();

  ErrorLog errors;
  vtkSmartPointer<vtkAbstractVolumeMapper> mapper;
  switch (peer) {
    case Peer::ProjectedTetrahedra: {
      auto pt = vtkSmartPointer<vtkProjectedTetrahedraMapper>::New();
      if (!pt) throw std::runtime_error(name + ": VTK has no OpenGL projected tetrahedra mapper (RenderingVolumeOpenGL2 not initialised)");
      mapper = pt;
      break;
    }
    case Peer::RayCast: {
      auto rc = vtkSmartPointer<vtkUnstructuredGridVolumeRayCastMapper>::New();
      rc->SetRayIntegrator(vtkSmartPointer<vtkUnstructuredGridLinearRayIntegrator>::New());
      rc->AutoAdjustSampleDistancesOff();
      rc->SetImageSampleDistance(1.0f);
      mapper = rc;
      break;
    }
    case Peer::ZSweep: {
      auto zs = vtkSmartPointer<vtkUnstructuredGridVolumeZSweepMapper>::New();
      zs->SetRayIntegrator(vtkSmartPointer<vtkUnstructuredGridLinearRayIntegrator>::New());
      zs->AutoAdjustSampleDistancesOff();
      zs->SetImageSampleDistance(1.0f);
      mapper = zs;
      break;
    }
  }
  mapper->SetInputDataObject(grid);
  if (model.per_point) mapper->SetScalarModeToUsePointData();
  else mapper->SetScalarModeToUseCellData();
  errors.watch(mapper);

  vtkNew<vtkVolume> volume;
  volume->SetMapper(mapper);
  volume->SetProperty(property);

  vtkNew<vtkCamera> vcam;
  const glm::dvec3 eye = camera.eye - origin, target = camera.target - origin;
  vcam->SetPosition(eye.x, eye.y, eye.z);
  vcam->SetFocalPoint(target.x, target.y, target.z);
  vcam->SetViewUp(camera.up.x, camera.up.y, camera.up.z);
  vcam->SetUseHorizontalViewAngle(false);
  vcam->SetViewAngle(camera.fovy_degrees);
  // Our projection has no far plane; VTK's needs one: just beyond the farthest corner of the
  // bounds along the viewing axis, so nothing of the mesh is clipped there.
  const glm::dvec3 forward = glm::normalize(camera.target - camera.eye);
  double farthest = 0.0;
  for (int corner = 0; corner < 8; ++corner) {
    const glm::dvec3 c((corner & 1) ? bounds.max.x : bounds.min.x, (corner & 2) ? bounds.max.y : bounds.min.y,
                       (corner & 4) ? bounds.max.z : bounds.min.z);
    farthest = std::max(farthest, glm::dot(c - camera.eye, forward));
  }
  const double far_distance = std::max(farthest, camera.near_distance) * 1.01 + 1e-9;
  vcam->SetClippingRange(camera.near_distance, far_distance);

  vtkNew<vtkRenderer> renderer;
  renderer->SetBackground(resolve.background.r, resolve.background.g, resolve.background.b);
  renderer->SetActiveCamera(vcam);
  renderer->AddVolume(volume);
  renderer->AutomaticLightCreationOff();
  // VTK 9.1's vtkViewport::ComputeAspect skips the computation when the window size, viewport
  // and pixel aspect equal those of its last computation, a cache it does not initialise: a
  // renderer allocated where an earlier one of the same size lived keeps the default aspect
  // 1:1, and the ray-cast and ZSweep mappers (which project with the renderer's aspect) then
  // stretch the picture. Setting the aspect the cache would have computed makes both cases right.
  renderer->SetAspect(double(width) / double(height), 1.0);
  errors.watch(renderer);

  vtkNew<vtkRenderWindow> window;
  window->SetDisplayId(x_connection.display());
  window->SetOffScreenRendering(1);
  window->SetMultiSamples(0);
  window->SetSize(static_cast<int>(width), static_cast<int>(height));
  window->AddRenderer(renderer);
  errors.watch(window);
  errors.watch_exit(window);
  if (!window->IsA("vtkOpenGLRenderWindow"))
    throw std::runtime_error(name + ": VTK made a " + std::string(window->GetClassName()) + ", not an OpenGL render window");

  auto render = [&] {
    window->Render();
    window->WaitForCompletion();  // glFinish
    errors.throw_if_any(name);
  };

  window->Start();  // the X window and GL context, checked before anything draws with them
  errors.throw_if_any(name);

  PeerFrame out;
  out.width = width;
  out.height = height;
  // Warm-up: the context, shaders, the mapper's first analysis of the input. Two frames: on a
  // new window's very first frame vtkOpenGLProjectedTetrahedraMapper draws nothing at all.
  render();
  render();
  out.gl_renderer = renderer_string(window);
  const double* range = vcam->GetClippingRange();
  if (std::abs(range[0] - camera.near_distance) > 1e-9 * camera.near_distance)
    throw std::runtime_error(name + ": VTK moved the near clipping plane to " + std::to_string(range[0]));
  for (uint32_t i = 0; i < frames; ++i) {
    const auto start = std::chrono::steady_clock::now();
    render();
    out.frame_ms.push_back(std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count());
  }

  vtkNew<vtkUnsignedCharArray> pixels;
  if (window->GetRGBACharPixelData(0, 0, static_cast<int>(width) - 1, static_cast<int>(height) - 1, 0, pixels) != 1 ||
      pixels->GetNumberOfTuples() != vtkIdType(width) * height)
    throw std::runtime_error(name + ": could not read the rendered pixels back");
  errors.throw_if_any(name);
  // VTK's rows run bottom to top; ours top to bottom.
  out.display.resize(size_t(width) * height * 4);
  const unsigned char* data = pixels->GetPointer(0);
  for (uint32_t y = 0; y < height; ++y) {
    const unsigned char* row = data + size_t(height - 1 - y) * width * 4;
    float* dst = out.display.data() + size_t(y) * width * 4;
    for (uint32_t x = 0; x < width; ++x) {
      for (int k = 0; k < 3; ++k) dst[4 * x + k] = float(row[4 * x + k]) / 255.0f;
      dst[4 * x + 3] = 1.0f;
    }
  }
  return out;
}

}  // namespace prismoid::bench
