#pragma once
// The meshlet shading atlas behind the surface renderer's interface (surface_backend.hpp):
// visibility, block management, shading and display of msa_pass over the meshlets of meshlets.
#include "renderer/surface/surface_backend.hpp"

namespace prismoid::surface {

const SurfaceBackendInfo& msa_backend();

}  // namespace prismoid::surface
