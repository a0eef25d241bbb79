// Exclusive prefix sums over the invocations of a workgroup of PRISMOID_SORT_WORKGROUP_SIZE,
// in shared memory (no subgroup operations, so every Vulkan 1.3 device runs it). Call from
// uniform control flow: they contain barriers.
#ifndef PRISMOID_SORT_WORKGROUP_SCAN_GLSL
#define PRISMOID_SORT_WORKGROUP_SCAN_GLSL

#ifdef PRISMOID_SCAN_UINT
shared uint scan_uint[PRISMOID_SORT_WORKGROUP_SIZE];

// Returns the sum of `value` over the invocations before this one; `total` gets the sum over all.
uint workgroup_exclusive_sum(uint value, out uint total) {
  const uint t = gl_LocalInvocationID.x;
  scan_uint[t] = value;
  barrier();
  for (uint offset = 1; offset < PRISMOID_SORT_WORKGROUP_SIZE; offset <<= 1) {
    const uint add = t >= offset ? scan_uint[t - offset] : 0u;
    barrier();
    scan_uint[t] += add;
    barrier();
  }
  const uint inclusive = scan_uint[t];
  total = scan_uint[PRISMOID_SORT_WORKGROUP_SIZE - 1];
  barrier();  // the next call overwrites the array
  return inclusive - value;
}
#endif

#ifdef PRISMOID_SCAN_UVEC4
shared uvec4 scan_uvec4[PRISMOID_SORT_WORKGROUP_SIZE];

// Four independent prefix sums at once (one per component).
uvec4 workgroup_exclusive_sum4(uvec4 value, out uvec4 total) {
  const uint t = gl_LocalInvocationID.x;
  scan_uvec4[t] = value;
  barrier();
  for (uint offset = 1; offset < PRISMOID_SORT_WORKGROUP_SIZE; offset <<= 1) {
    const uvec4 add = t >= offset ? scan_uvec4[t - offset] : uvec4(0u);
    barrier();
    scan_uvec4[t] += add;
    barrier();
  }
  const uvec4 inclusive = scan_uvec4[t];
  total = scan_uvec4[PRISMOID_SORT_WORKGROUP_SIZE - 1];
  barrier();
  return inclusive - value;
}
#endif

#endif
