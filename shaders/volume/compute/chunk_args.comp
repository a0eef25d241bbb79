#version 460
// Compute interval backend, after tile_chunks.comp: sizes the indirect dispatches of the
// split tiles' other chunks and of their merge (their kernels loop over what one dispatch
// cannot launch).
#extension GL_GOOGLE_include_directive : require
#include "../../shared/compute_intervals.h"

layout(local_size_x = 1) in;
layout(std430, set = 0, binding = PRISMOID_CI_BINDING_STATS) buffer Stats { uint stats[]; };

void main() {
  stats[PRISMOID_CI_ARGS_CHUNKS] = min(stats[PRISMOID_CI_STAT_EXTRA_CHUNKS], PRISMOID_CI_MAX_GROUPS);
  stats[PRISMOID_CI_ARGS_CHUNKS + 1] = 1u;
  stats[PRISMOID_CI_ARGS_CHUNKS + 2] = 1u;
  stats[PRISMOID_CI_ARGS_MERGE] = min(stats[PRISMOID_CI_STAT_SPLIT_TILES], PRISMOID_CI_MAX_GROUPS);
  stats[PRISMOID_CI_ARGS_MERGE + 1] = 1u;
  stats[PRISMOID_CI_ARGS_MERGE + 2] = 1u;
}
