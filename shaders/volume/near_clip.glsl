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

// Which side of the plane through a, b, c the point p lies on (sign of the orientation).
float orientation(vec3 a, vec3 b, vec3 c, vec3 p) { return dot(cross(b - a, c - a), p - a); }

// The three pieces of a split prism touch in a chain: 0 and 1 share the face (a1, a2, b0),
// 1 and 2 share (a1, b0, b2) (see split_prism), 0 and 2 only an edge. A ray crossing two of
// them crosses the shared face, so ordering each adjacent pair by the side of their shared
// face the eye (the camera-space origin) is on orders them front to back for every ray.
void order_pieces_front_to_back(inout vec3 pieces[3][4], uint count) {
  if (count != 3u) return;
  // Piece 0's vertex off the shared face is pieces[0][0]; piece 1's is pieces[1][1].
  bool zero_first = orientation(pieces[0][1], pieces[0][2], pieces[0][3], pieces[0][0]) *
                        orientation(pieces[0][1], pieces[0][2], pieces[0][3], vec3(0.0)) > 0.0;
  bool one_before_two = orientation(pieces[2][0], pieces[2][1], pieces[2][3], pieces[1][1]) *
                            orientation(pieces[2][0], pieces[2][1], pieces[2][3], vec3(0.0)) > 0.0;
  vec3 p0[4] = pieces[0], p1[4] = pieces[1], p2[4] = pieces[2];
  if (zero_first && one_before_two) return;                    // 0, 1, 2
  // 0 and 2 both before 1: no ray meets both without crossing 1 between them, so either order.
  if (zero_first) { pieces[1] = p2; pieces[2] = p1; return; }  // 0, 2, 1
  if (one_before_two) { pieces[0] = p1; pieces[1] = p0; return; }  // 1, 0, 2
  pieces[0] = p2; pieces[2] = p0;                                // 2, 1, 0
}

#endif
