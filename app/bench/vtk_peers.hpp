#pragma once
// VTK's own unstructured-grid volume mappers as peers for the bench: the same mesh, camera and
// transfer function, rendered by VTK 9.1 through OpenGL (an X display is needed: see
// x_display.hpp), read back into the display encoding of frame::OffscreenFrame so that
// reference::image_error(peer.display, ref.display, 1.0, 4, 3) measures them against the CPU
// reference like any of our own modes.
//
// What is rendered: for Quantity::Color the transfer function of the mesh's scalars (point
// scalars, linear in each cell, else cell scalars); for Transmittance and OpticalDepth the
// display those quantities have (the medium colour over the background, mixed by exp(-tau)),
// which is emission-absorption with the constant colour `medium` and extinction sigma itself
// as the scalar. Isosurfaces and marched analytic fields have no VTK peer here (InputError).
#include <cstdint>
#include <string>
#include <string_view>
#include <vector>

#include "renderer/volume/resolve_settings.hpp"
#include "scene/camera.hpp"
#include "scene/tet_mesh_fwd.hpp"

namespace prismoid::bench {

// vtkProjectedTetrahedraMapper, vtkUnstructuredGridVolumeRayCastMapper,
// vtkUnstructuredGridVolumeZSweepMapper.
enum class Peer { ProjectedTetrahedra, RayCast, ZSweep };
inline constexpr Peer kPeers[] = {Peer::ProjectedTetrahedra, Peer::RayCast, Peer::ZSweep};

// "vtk-projected-tetrahedra", "vtk-ray-cast", "vtk-zsweep".
std::string_view peer_name(Peer peer);

struct PeerFrame {
  uint32_t width = 0, height = 0;
  // Linear RGBA per pixel, row 0 at the top, alpha 1: the encoding of OffscreenFrame::display.
  std::vector<float> display;
  // Wall-clock ms of each timed frame: VTK's Render() up to a glFinish (WaitForCompletion).
  std::vector<double> frame_ms;
  std::string gl_renderer;  // GL_RENDERER of the context VTK drew with
};

// Renders two warm-up frames and then `frames` timed frames of the same view, and returns the
// last image (the second warm-up frame's when frames is 0). InputError for an empty mesh, a zero size, a
// mesh without the scalars the quantity needs, or a quantity with no peer; std::runtime_error
// when VTK reports an error or no X display can be opened.
PeerFrame render_peer(Peer peer, const TetMesh& mesh, const Camera& camera, const volume::ResolveSettings& resolve,
                      uint32_t width, uint32_t height, uint32_t frames);

}  // namespace prismoid::bench
