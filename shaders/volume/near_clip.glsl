// Clipping a tetrahedron against the near plane (Tricard 2024, section 2.3), in camera
// orientation relative to the cell's reference point (interval_body.glsl): depths are measured
// from the reference point's, so the plane and the vertices keep float precision however far
// the eye is. The part in front of the plane is empty, the tetrahedron itself, a small
// tetrahedron (3 vertices behind), or a prism (1 or 2 vertices behind) split into 3 tetrahedra.
// Each vertex carries the cell's linear field, interpolated along the cut edges with the points.
#ifndef PRISMOID_NEAR_CLIP_GLSL
#define PRISMOID_NEAR_CLIP_GLSL

// A vertex: position relative to the reference point in xyz (camera orientation, -z ahead),
// the linear field's value there in w.
struct ClipPiece {
  vec4 v[4];
};

// Point where the edge from `front` (relative depth >= near) to `back` (< near) meets the
// plane; computed from the edge's front vertex.
vec4 near_crossing(vec4 front, vec4 back, float near_depth) {
  float df = -front.z, db = -back.z;
  float t = (df - near_depth) / (df - db);  // df - db > 0 since df >= near > db
  vec4 p = mix(front, back, t);
  p.z = -near_depth;  // exactly on the plane, whatever the rounding of mix
  return p;
}

// Writes the prism with triangles (a0 a1 a2) and (b0 b1 b2), ai joined to bi, as 3 tetrahedra.
void split_prism(vec4 a0, vec4 a1, vec4 a2, vec4 b0, vec4 b1, vec4 b2, inout ClipPiece pieces[3]) {
  pieces[0].v = vec4[4](a0, a1, a2, b0);
  pieces[1].v = vec4[4](a1, a2, b0, b2);
  pieces[2].v = vec4[4](a1, b0, b1, b2);
}

// Returns the number of tetrahedra (0 to 3) that make up the part with relative depth
// (-z) >= near_depth, the near plane's depth minus the reference point's.
uint clip_near(vec4 cell[4], float near_depth, out ClipPiece pieces[3]) {
  uint front_idx[4], back_idx[4];
  uint nf = 0u, nb = 0u;
  for (uint i = 0u; i < 4u; ++i) {
    if (-cell[i].z >= near_depth) front_idx[nf++] = i;
    else back_idx[nb++] = i;
  }
  if (nb == 0u) {
    pieces[0].v = cell;
    return 1u;
  }
  if (nf == 0u) return 0u;
  if (nf == 1u) {
    vec4 a = cell[front_idx[0]];
    pieces[0].v = vec4[4](a, near_crossing(a, cell[back_idx[0]], near_depth), near_crossing(a, cell[back_idx[1]], near_depth),
                          near_crossing(a, cell[back_idx[2]], near_depth));
    return 1u;
  }
  if (nf == 3u) {
    vec4 b = cell[back_idx[0]];
    vec4 a0 = cell[front_idx[0]], a1 = cell[front_idx[1]], a2 = cell[front_idx[2]];
    split_prism(a0, a1, a2, near_crossing(a0, b, near_depth), near_crossing(a1, b, near_depth),
                near_crossing(a2, b, near_depth), pieces);
    return 3u;
  }
  // Two in front (a0, a1), two behind (b0, b1): a wedge with triangles (a0, a0b0, a0b1) and
  // (a1, a1b0, a1b1).
  vec4 a0 = cell[front_idx[0]], a1 = cell[front_idx[1]];
  vec4 b0 = cell[back_idx[0]], b1 = cell[back_idx[1]];
  split_prism(a0, near_crossing(a0, b0, near_depth), near_crossing(a0, b1, near_depth), a1,
              near_crossing(a1, b0, near_depth), near_crossing(a1, b1, near_depth), pieces);
  return 3u;
}

// Which side of the plane through a, b, c the point p lies on (sign of the orientation).
float orientation(vec3 a, vec3 b, vec3 c, vec3 p) { return dot(cross(b - a, c - a), p - a); }

// The three pieces of a split prism touch in a chain: 0 and 1 share the face (a1, a2, b0),
// 1 and 2 share (a1, b0, b2) (see split_prism), 0 and 2 only an edge. A ray crossing two of
// them crosses the shared face, so ordering each adjacent pair by the side of their shared
// face the eye is on orders them front to back for every ray. `eye` is in the pieces' frame.
void order_pieces_front_to_back(inout ClipPiece pieces[3], uint count, vec3 eye) {
  if (count != 3u) return;
  // Piece 0's vertex off the shared face is pieces[0].v[0]; piece 1's is pieces[1].v[1].
  vec3 s0 = pieces[0].v[1].xyz, s1 = pieces[0].v[2].xyz, s2 = pieces[0].v[3].xyz;
  bool zero_first = orientation(s0, s1, s2, pieces[0].v[0].xyz) * orientation(s0, s1, s2, eye) > 0.0;
  vec3 t0 = pieces[2].v[0].xyz, t1 = pieces[2].v[1].xyz, t2 = pieces[2].v[3].xyz;
  bool one_before_two = orientation(t0, t1, t2, pieces[1].v[1].xyz) * orientation(t0, t1, t2, eye) > 0.0;
  ClipPiece p0 = pieces[0], p1 = pieces[1], p2 = pieces[2];
  if (zero_first && one_before_two) return;                    // 0, 1, 2
  // 0 and 2 both before 1: no ray meets both without crossing 1 between them, so either order.
  if (zero_first) { pieces[1] = p2; pieces[2] = p1; return; }  // 0, 2, 1
  if (one_before_two) { pieces[0] = p1; pieces[1] = p0; return; }  // 1, 0, 2
  pieces[0] = p2; pieces[2] = p0;                                // 2, 1, 0
}

#endif
