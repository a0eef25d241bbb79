#pragma once
// The forward backend behind the surface renderer's interface (surface_backend.hpp): a depth
// pre-pass and one shading invocation per covered pixel (forward_pass), or with shadows one
// ray-generation invocation per pixel tracing them (shadowed_forward_pass).
#include "renderer/surface/surface_backend.hpp"

namespace prismoid::surface {

const SurfaceBackendInfo& forward_backend();

}  // namespace prismoid::surface
