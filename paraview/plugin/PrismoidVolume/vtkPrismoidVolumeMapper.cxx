#include "vtkPrismoidVolumeMapper.h"

#include <algorithm>
#include <chrono>
#include <cstdint>
#include <exception>
#include <sstream>
#include <vector>

#include <vtkCamera.h>
#include <vtkDataArray.h>
#include <vtkMatrix4x4.h>
#include <vtkObjectFactory.h>
#include <vtkOpenGLRenderUtilities.h>
#include <vtkOpenGLRenderWindow.h>
#include <vtkOpenGLState.h>
#include <vtkTextureObject.h>
#include <vtk_glew.h>
#include <vtkRenderer.h>
#include <vtkUnstructuredGridBase.h>
#include <vtkVolume.h>

#include "prismoid_session.hpp"
#include "vtk_to_prismoid.hpp"

vtkStandardNewMacro(vtkPrismoidVolumeMapper);

vtkPrismoidVolumeMapper::vtkPrismoidVolumeMapper() : Texture(vtkTextureObject::New()) {}

vtkPrismoidVolumeMapper::~vtkPrismoidVolumeMapper() { this->Texture->Delete(); }

void vtkPrismoidVolumeMapper::PrintSelf(ostream& os, vtkIndent indent) {
  this->Superclass::PrintSelf(os, indent);
  os << indent << "Backend: " << this->Backend << "\n" << indent << "Ordering: " << this->Ordering << "\n"
     << indent << "Quantity: " << this->Quantity << "\n";
}

void vtkPrismoidVolumeMapper::ReleaseGraphicsResources(vtkWindow* window) { this->Texture->ReleaseGraphicsResources(window); }

namespace {

// The depth (0..1) of the nearest corner of the volume's bounds, where the image is drawn, as
// VTK's own image-based unstructured mappers place theirs.
float nearest_bounds_depth(vtkRenderer* ren, vtkVolume* vol) {
  double b[6];
  vol->GetBounds(b);
  vtkMatrix4x4* m = ren->GetActiveCamera()->GetCompositeProjectionTransformMatrix(ren->GetTiledAspectRatio(), 0.0, 1.0);
  double nearest = 1.0;
  for (int corner = 0; corner < 8; ++corner) {
    const double p[4] = {b[corner & 1], b[2 + ((corner >> 1) & 1)], b[4 + ((corner >> 2) & 1)], 1.0};
    double q[4];
    m->MultiplyPoint(p, q);
    if (q[3] <= 0.0) return 0.0;  // a corner behind the eye: the eye is at or inside the bounds
    nearest = std::min(nearest, 0.5 * q[2] / q[3] + 0.5);
  }
  return static_cast<float>(std::clamp(nearest, 0.0, 1.0));
}

}  // namespace

void vtkPrismoidVolumeMapper::Blend(vtkRenderer* ren, vtkVolume* vol, int width, int height, float* premultiplied) {
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
  state->vtkglEnable(GL_BLEND);
  state->vtkglBlendFuncSeparate(GL_ONE, GL_ONE_MINUS_SRC_ALPHA, GL_ONE, GL_ONE_MINUS_SRC_ALPHA);  // premultiplied "over"
  state->vtkglDepthMask(GL_FALSE);
  const float z = 2.0f * nearest_bounds_depth(ren, vol) - 1.0f;  // drawn where the volume begins, as VTK's mappers do
  float verts[12] = {-1.0f, -1.0f, z, 1.0f, -1.0f, z, 1.0f, 1.0f, z, -1.0f, 1.0f, z};
  float tcoords[8] = {0.0f, 0.0f, 1.0f, 0.0f, 1.0f, 1.0f, 0.0f, 1.0f};
  this->Texture->CopyToFrameBuffer(tcoords, verts, nullptr, nullptr);
}

void vtkPrismoidVolumeMapper::Render(vtkRenderer* ren, vtkVolume* vol) {
  namespace pv = prismoid::paraview;
  this->LastFrameDrawn = false;
  this->LastError.clear();
  this->LastFrameMilliseconds = 0.0;
  const auto start = std::chrono::steady_clock::now();
  vtkUnstructuredGridBase* grid = this->GetInput();
  if (!grid || grid->GetNumberOfCells() == 0) return;  // an empty piece (one rank's share may be): nothing to draw
  try {
    int cell_flag = 0;
    vtkDataArray* scalars = vtkAbstractMapper::GetScalars(grid, this->ScalarMode, this->ArrayAccessMode, this->ArrayId, this->ArrayName, cell_flag);
    std::ostringstream key;
    key << grid << ':' << grid->GetMTime() << ':' << scalars << ':' << (scalars ? scalars->GetMTime() : 0) << ':' << cell_flag;
    pv::Session& session = pv::Session::instance();
    if (!session.has_mesh(key.str())) {
      std::size_t skipped = 0;
      session.set_mesh(key.str(), pv::tet_mesh_from(grid, scalars, cell_flag == 1, skipped));
    }

    prismoid::frame::FrameSettings settings;
    settings.resolve.quantity = prismoid::volume::Quantity::Color;
    settings.resolve.transfer = pv::transfer_function_from(vol->GetProperty());
    if (this->Quantity == 1)  // absorption only: no emission, so the colour is the background's share
      for (auto& point : settings.resolve.transfer.color) point.rgb = glm::dvec3(0.0);
    settings.resolve.background = glm::vec3(0.0f);  // premultiplied colour and alpha over nothing: VTK blends
    settings.backend = this->Backend == 1 ? prismoid::frame::IntervalBackend::Compute : prismoid::frame::IntervalBackend::Mesh;
    settings.ordering = this->Ordering == 1 ? prismoid::frame::Ordering::Exact : prismoid::frame::Ordering::GpuSort;

    int width = 0, height = 0, x0 = 0, y0 = 0;
    ren->GetTiledSizeAndOrigin(&width, &height, &x0, &y0);
    if (width <= 0 || height <= 0) return;
    const prismoid::frame::OffscreenFrame frame =
        session.render(pv::camera_from(ren->GetActiveCamera()), settings, static_cast<uint32_t>(width), static_cast<uint32_t>(height));

    // VTK's image rows run bottom to top, ours top to bottom.
    std::vector<float> image(frame.emission.size());
    const size_t row = static_cast<size_t>(width) * 4;
    for (int y = 0; y < height; ++y)
      std::copy_n(frame.emission.begin() + static_cast<std::ptrdiff_t>(static_cast<size_t>(y) * row), row,
                  image.begin() + static_cast<std::ptrdiff_t>(static_cast<size_t>(height - 1 - y) * row));
    this->Blend(ren, vol, width, height, image.data());
    this->LastFrameDrawn = true;
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
