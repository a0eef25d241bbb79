#pragma once
// FastAtlas behind the surface renderer's interface (surface_backend.hpp): the per-frame atlas of
// fastatlas_pass, its options and its counters.
#include "renderer/surface/surface_backend.hpp"

namespace prismoid::surface {

const SurfaceBackendInfo& fastatlas_backend();

}  // namespace prismoid::surface
