#version 460
// The tile raster (tile_raster.glsl) for emission-absorption through the transfer function, in each pixel's depth order.
#extension GL_GOOGLE_include_directive : require
#include "../../shared/compute_intervals.h"
#define PRISMOID_CI_RASTER_MODE PRISMOID_CI_EMISSION
#include "tile_raster.glsl"
