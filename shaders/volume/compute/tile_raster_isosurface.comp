#version 460
// The tile raster (tile_raster.glsl) for the nearest isosurface hit.
#extension GL_GOOGLE_include_directive : require
#include "../../shared/compute_intervals.h"
#define PRISMOID_CI_RASTER_MODE PRISMOID_CI_ISOSURFACE
#include "tile_raster.glsl"
