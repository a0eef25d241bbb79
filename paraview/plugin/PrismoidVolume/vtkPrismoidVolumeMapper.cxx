#include "vtkPrismoidVolumeMapper.h"

#include <algorithm>
#include <chrono>
#include <limits>
#include <memory>
#include <stdexcept>
#include <sstream>
#include <vector>

#include <vtkCamera.h>
#include <vtkMultiProcessController.h>
#include <vtkDataArray.h>
#include <vtkObjectFactory.h>
#include <vtkOpenGLRenderWindow.h>
#include <vtkOpenGLState.h>
#include <vtkTextureObject.h>
#include <vtk_glew.h>
#include <vtkRenderWindow.h>
#include <vtkRenderer.h>
#include <vtkUnstructuredGridBase.h>
#include <vtkVolume.h>

#include "prismoid_session.hpp"
#include "vtk_to_prismoid.hpp"

vtkStandardNewMacro(vtkPrismoidVolumeMapper);

int vtkPrismoidVolumeMapper::GetMeshUploads() { return static_cast<int>(prismoid::paraview::Session::instance().mesh_uploads()); }
int vtkPrismoidVolumeMapper::GetFieldUploads() { return static_cast<int>(prismoid::paraview::Session::instance().field_uploads()); }

vtkPrismoidVolumeMapper::vtkPrismoidVolumeMapper() : Texture(vtkTextureObject::New()) {}

vtkPrismoidVolumeMapper::~vtkPrismoidVolumeMapper() { this->Texture->Delete(); }

void vtkPrismoidVolumeMapper::PrintSelf(ostream& os, vtkIndent indent) {
  this->Superclass::PrintSelf(os, indent);
  os << indent << "Backend: " << this->Backend << "\n" << indent << "Ordering: " << this->Ordering << "\n"
     << indent << "Quantity: " << this->Quantity << "\n";
}

void vtkPrismoidVolumeMapper::ReleaseGraphicsResources(vtkWindow* window) { this->Texture->ReleaseGraphicsResources(window); }

namespace {

// Where each pixel's ray meets the opaque geometry ParaView drew before the volume: its depth
// buffer over the viewport, as depths along the viewing axis (row 0 at the top, +inf where the
// buffer holds the far plane). VTK's perspective depth d in [0, 1] of the clipping range (n, f)
// is z_ndc = 2d - 1 = ((f + n) - 2fn / z) / (f - n), so z = 2fn / ((f + n) - z_ndc (f - n)).
// Empty when no pixel has geometry.
std::vector<float> opaque_depths(vtkRenderer* ren, int x0, int y0, int width, int height) {
  std::vector<float> window(static_cast<size_t>(width) * height);
  if (!ren->GetRenderWindow()->GetZbufferData(x0, y0, x0 + width - 1, y0 + height - 1, window.data())) return {};
  const double* range = ren->GetActiveCamera()->GetClippingRange();
  const double n = range[0], f = range[1];
  std::vector<float> depth(window.size(), std::numeric_limits<float>::infinity());
  bool any = false;
  for (int y = 0; y < height; ++y)
    for (int x = 0; x < width; ++x) {
      const double d = window[static_cast<size_t>(y) * width + x];
      if (!(d < 1.0)) continue;  // the far plane: nothing drawn there
      const double z = 2.0 * f * n / ((f + n) - (2.0 * d - 1.0) * (f - n));
      depth[static_cast<size_t>(height - 1 - y) * width + x] = static_cast<float>(std::max(z, n));
      any = true;
    }
  if (!any) depth.clear();
  return depth;
}

}  // namespace

void vtkPrismoidVolumeMapper::Blend(vtkRenderer* ren, int width, int height, float* premultiplied) {
  // One texel per pixel, sampled at its centre: a quad over the whole viewport with texture
  // coordinates 0..1 and nearest filtering puts texel (x, y) on pixel (x, y) exactly. (VTK's
  // vtkRayCastImageDisplayHelper maps texel centres to the viewport's edges instead, stretching
  // the image by one pixel, and filters it.)
  auto* window = vtkOpenGLRenderWindow::SafeDownCast(ren->GetRenderWindow());
  if (!window) throw std::runtime_error("the render window is not an OpenGL one");
  vtkOpenGLState* state = window->GetState();
  this->Texture->SetContext(window);
  this->Texture->SetMinificationFilter(vtkTextureObject::Nearest);
  this->Texture->SetMagnificationFilter(vtkTextureObject::Nearest);
  if (!this->Texture->Create2DFromRaw(static_cast<unsigned int>(width), static_cast<unsigned int>(height), 4, VTK_FLOAT, premultiplied))
    throw std::runtime_error("could not make the image's OpenGL texture");
  vtkOpenGLState::ScopedglEnableDisable blend(state, GL_BLEND);
  vtkOpenGLState::ScopedglBlendFuncSeparate blend_function(state);
  vtkOpenGLState::ScopedglDepthMask depth_mask(state);
  vtkOpenGLState::ScopedglEnableDisable depth_test(state, GL_DEPTH_TEST);
  state->vtkglEnable(GL_BLEND);
  state->vtkglBlendFuncSeparate(GL_ONE, GL_ONE_MINUS_SRC_ALPHA, GL_ONE, GL_ONE_MINUS_SRC_ALPHA);  // premultiplied "over"
  state->vtkglDepthMask(GL_FALSE);
  // No depth test: each pixel's rays already ended at the opaque geometry (opaque_depths).
  state->vtkglDisable(GL_DEPTH_TEST);
  float verts[12] = {-1.0f, -1.0f, 0.0f, 1.0f, -1.0f, 0.0f, 1.0f, 1.0f, 0.0f, -1.0f, 1.0f, 0.0f};
  float tcoords[8] = {0.0f, 0.0f, 1.0f, 0.0f, 1.0f, 1.0f, 0.0f, 1.0f};
  this->Texture->CopyToFrameBuffer(tcoords, verts, nullptr, nullptr);
}

void vtkPrismoidVolumeMapper::WarnNothingDrawn(const std::string& why) {
  if (this->ReportedWarning != why) vtkWarningMacro(<< "Prismoid volume: " << why);
  this->ReportedWarning = why;
}

void vtkPrismoidVolumeMapper::Render(vtkRenderer* ren, vtkVolume* vol) {
  namespace pv = prismoid::paraview;
  this->LastFrameDrawn = false;
  this->LastError.clear();
  this->LastFrameMilliseconds = 0.0;
  const auto start = std::chrono::steady_clock::now();
  vtkUnstructuredGridBase* grid = this->GetInput();
  if (!grid || grid->GetNumberOfCells() == 0) {
    // An empty piece is one rank's share in a parallel run; alone, the input itself is empty.
    vtkMultiProcessController* ranks = vtkMultiProcessController::GetGlobalController();
    if (!ranks || ranks->GetNumberOfProcesses() <= 1) this->WarnNothingDrawn("the input has no cells: nothing to draw");
    return;
  }
  try {
    int cell_flag = 0;
    vtkDataArray* scalars = vtkAbstractMapper::GetScalars(grid, this->ScalarMode, this->ArrayAccessMode, this->ArrayId, this->ArrayName, cell_flag);
    // A vector array maps through the colour function's vector mode: one component, or the magnitude.
    const int component = scalars && scalars->GetNumberOfComponents() > 1 ? pv::mapped_component(vol->GetProperty()) : -1;
    std::ostringstream key;
    key << grid << ':' << grid->GetMTime() << ':' << scalars << ':' << (scalars ? scalars->GetMTime() : 0) << ':' << cell_flag << ':'
        << component;
    pv::Session& session = pv::Session::instance();
    if (!session.has_mesh(key.str())) {
      std::size_t skipped = 0;
      session.set_mesh(key.str(), pv::tet_mesh_from(grid, scalars, cell_flag == 1, component, skipped));
    }

    prismoid::frame::FrameSettings settings;
    settings.resolve.quantity = prismoid::volume::Quantity::Color;
    settings.resolve.transfer = pv::transfer_function_from(vol->GetProperty());
    if (this->Quantity == 1)  // absorption only: no emission, so the colour is the background's share
      for (auto& point : settings.resolve.transfer.color) point.rgb = glm::dvec3(0.0);
    settings.resolve.background = glm::vec3(0.0f);  // premultiplied colour and alpha over nothing: VTK blends
    settings.backend = this->Backend == 1 ? prismoid::frame::IntervalBackend::Compute : prismoid::frame::IntervalBackend::Mesh;
    settings.ordering = this->Ordering == 1 ? prismoid::frame::Ordering::Exact : prismoid::frame::Ordering::GpuSort;

    // A colour map whose opacity is 0 over every value of the array draws nothing (ParaView's own
    // mappers too): said, rather than an empty frame without a word (a constant array falls on
    // the opacity function's first point, often 0).
    bool nothing_visible = false;
    if (scalars && this->Quantity == 0) {
      double range[2] = {0.0, 0.0};
      scalars->GetRange(range, component);  // component -1: the magnitude
      if (pv::largest_opacity(settings.resolve.transfer, range[0], range[1]) <= 0.0) {
        std::ostringstream why;
        why << "the opacity function is 0 over every value of the array '" << (scalars->GetName() ? scalars->GetName() : "")
            << "' (" << range[0] << (range[0] == range[1] ? ", constant" : std::string(" to ") + std::to_string(range[1]))
            << "): nothing is drawn; raise its opacity there (Edit color map)";
        this->WarnNothingDrawn(why.str());
        nothing_visible = true;
      }
    }

    int width = 0, height = 0, x0 = 0, y0 = 0;
    ren->GetTiledSizeAndOrigin(&width, &height, &x0, &y0);
    if (width <= 0 || height <= 0) return;
    // Opaque geometry (slices, contours, glyphs drawn before the volume) ends the rays.
    std::vector<float> opaque = opaque_depths(ren, x0, y0, width, height);
    if (!opaque.empty()) settings.resolve.depth_limit = std::make_shared<const std::vector<float>>(std::move(opaque));
    const prismoid::frame::OffscreenFrame frame =
        session.render(pv::camera_from(ren->GetActiveCamera()), settings, static_cast<uint32_t>(width), static_cast<uint32_t>(height));

    // VTK's image rows run bottom to top, ours top to bottom.
    std::vector<float> image(frame.emission.size());
    const size_t row = static_cast<size_t>(width) * 4;
    for (int y = 0; y < height; ++y)
      std::copy_n(frame.emission.begin() + static_cast<std::ptrdiff_t>(static_cast<size_t>(y) * row), row,
                  image.begin() + static_cast<std::ptrdiff_t>(static_cast<size_t>(height - 1 - y) * row));
    this->Blend(ren, width, height, image.data());
    this->LastFrameDrawn = true;
    if (!nothing_visible) this->ReportedWarning.clear();
    this->LastFrameMilliseconds = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count();
  } catch (const std::exception& e) {
    // A clear message in ParaView's output, never a crash: the volume is simply not drawn. Said
    // once, not at every frame the same input fails.
    if (this->ReportedError != e.what()) vtkErrorMacro(<< "Prismoid volume: " << e.what());
    this->LastError = this->ReportedError = e.what();
    return;
  }
  this->ReportedError.clear();
}
