// The fragment's interval on its pixel ray, between the two bounding surfaces its proxy
// interpolates (tet_projection.glsl), measured from the cell's reference point c: the depths
// of its ends relative to c's depth (exact to the cell's size, however far the eye is), the
// cell's field there, and where points of the ray lie in the field's coordinates (mesh-local
// placed by frame.field_origin, which is the identity for fields whose parameters can be moved
// into the mesh frame). All terms stay of the size of the cell and of its offset from the pixel ray, however
// far from the eye or the world origin both are. The caller declares `frame`.
#ifndef PRISMOID_INTERVAL_RAY_GLSL
#define PRISMOID_INTERVAL_RAY_GLSL

struct IntervalRay {
  float front, back;          // depths along the viewing axis, front <= back (relative precision)
  float rel_front, rel_back;  // the same minus c's depth (absolute precision of the cell's size)
  float field_front, field_back;  // the cell's linear field at both ends
  float length_per_depth;     // world length of one unit of depth along this ray
  vec3 ray;                   // the camera-space point at depth d is d * ray
};

// The compute backend (shaders/volume/compute/) finds the same interval on each pixel's own
// ray and fills the struct itself; it defines PRISMOID_INTERVAL_RAY_COMPUTE, since a compute
// shader has no gl_FragCoord.
#ifndef PRISMOID_INTERVAL_RAY_COMPUTE
// inv_depth, relative: the interpolated attributes of surfaces a and b (v_inv_depth,
// v_relative); reference: c and the field there (p_reference).
IntervalRay interval_ray(vec2 inv_depth, vec4 relative, vec4 reference) {
  IntervalRay r;
  float depth_a = 1.0 / inv_depth.x, depth_b = 1.0 / inv_depth.y;
  float rel_a = relative.x * depth_a, rel_b = relative.y * depth_b;
  float field_a = reference.w + relative.z * depth_a, field_b = reference.w + relative.w * depth_b;
  bool a_first = rel_a <= rel_b;
  r.front = a_first ? depth_a : depth_b;
  r.back = a_first ? depth_b : depth_a;
  r.rel_front = a_first ? rel_a : rel_b;
  r.rel_back = a_first ? rel_b : rel_a;
  r.field_front = a_first ? field_a : field_b;
  r.field_back = a_first ? field_b : field_a;
  vec2 ndc = gl_FragCoord.xy * frame.viewport.zw * 2.0 - 1.0;
  r.ray = vec3(ndc * frame.ray_scale.xy, -1.0);
  r.length_per_depth = length(r.ray);
  return r;
}

// The depth along the viewing axis where this fragment's pixel ray ends (opaque geometry,
// volume::ResolveSettings::depth_limit), +inf where nothing is.
layout(std430, set = 0, binding = PRISMOID_BINDING_DEPTH_LIMIT) readonly buffer DepthLimit { float depth_limit[]; };
float pixel_depth_limit() {
  if (frame.options.z != 1u) return uintBitsToFloat(0x7F800000u);
  uvec2 p = uvec2(gl_FragCoord.xy);
  return depth_limit[p.y * uint(frame.viewport.x) + p.x];
}
#endif

// The interval's length in world units.
float interval_length(IntervalRay r) { return (r.rel_back - r.rel_front) * r.length_per_depth; }

// Opaque geometry: the pixel's ray ends at depth `limit` along the viewing axis (+inf: nowhere).
// The interval keeps what lies before it: its back end moves there, the field at it interpolated
// along the interval (the field is linear along the ray inside a cell). False when nothing is left.
bool end_at(inout IntervalRay r, float limit) {
  if (!(r.front < limit)) return false;
  if (r.back > limit) {
    float kept = (limit - r.front) / (r.back - r.front);
    r.field_back = mix(r.field_front, r.field_back, kept);
    r.rel_back = r.rel_front + (limit - r.front);
    r.back = limit;
  }
  return true;
}

#endif
