#version 460
// The tile raster (tile_raster.glsl) for optical depth of the cells' linear fields.
#extension GL_GOOGLE_include_directive : require
#include "../../shared/compute_intervals.h"
#define PRISMOID_CI_RASTER_MODE PRISMOID_CI_OPTICAL_DEPTH
#include "tile_raster.glsl"
