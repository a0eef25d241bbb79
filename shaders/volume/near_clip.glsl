// Clipping a tetrahedron against the near plane (Tricard 2024, section 2.3), in camera space.
// The part in front of the plane is empty, the tetrahedron itself, a small tetrahedron
// (3 vertices behind), or a prism (1 or 2 vertices behind) split into 3 tetrahedra.
// Each intersection is computed from the edge's front vertex towards its back vertex, so
// neighbouring cells that share the edge compute bit-identical points (no cracks).
#ifndef PRISMOID_NEAR_CLIP_GLSL
#define PRISMOID_NEAR_CLIP_GLSL

// Point where the edge from `front` (depth >= near) to `back` (depth < near) meets the plane.
vec3 near_crossing(vec3 front, vec3 back, float near_depth) {
  float df = -front.z, db = -back.z;
  float t = (df - near_depth) / (df - db);  // df - db > 0 since df >= near > db
  vec3 p = mix(front, back, t);
  p.z = -near_depth;  // exactly on the plane, whatever the rounding of mix
  return p;
}

// Writes the prism with triangles (a0 a1 a2) and (b0 b1 b2), ai joined to bi, as 3 tetrahedra.
void split_prism(vec3 a0, vec3 a1, vec3 a2, vec3 b0, vec3 b1, vec3 b2, inout vec3 pieces[3][4]) {
  pieces[0] = vec3[4](a0, a1, a2, b0);
  pieces[1] = vec3[4](a1, a2, b0, b2);
  pieces[2] = vec3[4](a1, b0, b1, b2);
}

// Returns the number of tetrahedra (0 to 3) that make up the part with depth >= near.
uint clip_near(vec3 cam[4], float near_depth, out vec3 pieces[3][4]) {
  uint front_idx[4], back_idx[4];
  uint nf = 0u, nb = 0u;
  for (uint i = 0u; i < 4u; ++i) {
    if (-cam[i].z >= near_depth) front_idx[nf++] = i;
    else back_idx[nb++] = i;
  }
  if (nb == 0u) {
    pieces[0] = cam;
    return 1u;
  }
  if (nf == 0u) return 0u;
  if (nf == 1u) {
    vec3 a = cam[front_idx[0]];
    pieces[0] = vec3[4](a, near_crossing(a, cam[back_idx[0]], near_depth), near_crossing(a, cam[back_idx[1]], near_depth),
                        near_crossing(a, cam[back_idx[2]], near_depth));
    return 1u;
  }
  if (nf == 3u) {
    vec3 b = cam[back_idx[0]];
    vec3 a0 = cam[front_idx[0]], a1 = cam[front_idx[1]], a2 = cam[front_idx[2]];
    split_prism(a0, a1, a2, near_crossing(a0, b, near_depth), near_crossing(a1, b, near_depth),
                near_crossing(a2, b, near_depth), pieces);
    return 3u;
  }
  // Two in front (a0, a1), two behind (b0, b1): a wedge with triangles (a0, a0b0, a0b1) and
  // (a1, a1b0, a1b1).
  vec3 a0 = cam[front_idx[0]], a1 = cam[front_idx[1]];
  vec3 b0 = cam[back_idx[0]], b1 = cam[back_idx[1]];
  split_prism(a0, near_crossing(a0, b0, near_depth), near_crossing(a0, b1, near_depth), a1,
              near_crossing(a1, b0, near_depth), near_crossing(a1, b1, near_depth), pieces);
  return 3u;
}

#endif
