#pragma once
// The texel shading backend behind the surface renderer's interface (surface_backend.hpp):
// queue, shading and gather of texel_pass over the static atlas of texel_atlas.
#include "renderer/surface/surface_backend.hpp"

namespace prismoid::surface {

const SurfaceBackendInfo& texel_backend();

}  // namespace prismoid::surface
