#version 460
// Visibility sort keys: for each tetrahedron, its centroid m's squared distance from the eye e
// minus the mesh origin's, |m - e|^2 - |e|^2 = |m|^2 - 2 m.e (all mesh-local), and its index.
// The difference orders like the distance, and never forms m - e, which for an eye far away
// (2e8 at --fovy 1e-6) rounds every cell to the same few floats. Signed floats become
// unsigned keys that order alike: negative ones bit-inverted, positive ones with the sign set.
#extension GL_GOOGLE_include_directive : require
#include "../shared/sort.h"

layout(local_size_x = PRISMOID_SORT_WORKGROUP_SIZE) in;
layout(set = 0, binding = PRISMOID_SORT_KEYS_BINDING_POSITIONS, std430) readonly buffer Positions { vec4 positions[]; };
layout(set = 0, binding = PRISMOID_SORT_KEYS_BINDING_TETS, std430) readonly buffer Tets { uvec4 tets[]; };
layout(set = 0, binding = PRISMOID_SORT_KEYS_BINDING_KEYS, std430) writeonly buffer Keys { uint keys[]; };
layout(set = 0, binding = PRISMOID_SORT_KEYS_BINDING_VALUES, std430) writeonly buffer Values { uint values[]; };
layout(push_constant) uniform Push { SortKeysPush push; };

void main() {
  // One block of keys per workgroup, like the sort, so both dispatch the same group count.
  for (uint i = 0; i < PRISMOID_SORT_ITEMS_PER_INVOCATION; ++i) {
    const uint cell = gl_WorkGroupID.x * PRISMOID_SORT_BLOCK + i * PRISMOID_SORT_WORKGROUP_SIZE + gl_LocalInvocationID.x;
    if (cell >= push.counts.x) return;
    const uvec4 tet = tets[cell];
    const vec3 center = 0.25 * (positions[tet.x].xyz + positions[tet.y].xyz + positions[tet.z].xyz + positions[tet.w].xyz);
    const uint bits = floatBitsToUint(dot(center, center) - 2.0 * dot(center, push.eye.xyz));
    keys[cell] = (bits & 0x80000000u) != 0u ? ~bits : bits | 0x80000000u;
    values[cell] = cell;
  }
}
