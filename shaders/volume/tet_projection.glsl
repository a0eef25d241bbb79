// Projection of one tetrahedron into an interval-shading proxy (Tricard 2024, section 2.2).
// Input: the four vertices relative to the cell's reference point c (camera orientation, all in
// front of the near plane) with the cell's linear field there, c in camera space and the field
// at c. Output: up to 5 screen-space vertices and up to 4 triangles, each vertex carrying, for
// the two bounding surfaces a and b over it: 1/depth, (depth - depth_c)/depth and
// (field - field_c)/depth. Depth is the positive distance along the viewing axis; on a plane,
// 1/depth, and hence anything linear in camera space divided by depth, is affine in screen
// space, so the rasterizer's screen-space interpolation of all three is exact. The last two are
// small numbers computed from positions relative to c, so the fragment recovers the interval's
// ends relative to c (and its length) with the precision of the cell's size rather than of its
// distance from the eye: 1/depth alone, at a depth of 2e8, pins a surface only to +-8 units.
// The inner vertex's second surface is found in 3D, relative to c (the ray to the vertex met
// with the far face's plane, or the two diagonal edges' crossing as seen from the eye), not by
// barycentrics of projected points, whose rounding (of the points' distance from the screen
// centre, not of the cell's size) a small or distant cell would magnify.
#ifndef PRISMOID_TET_PROJECTION_GLSL
#define PRISMOID_TET_PROJECTION_GLSL

struct TetProxy {
  vec2 ndc[5];
  vec2 inv_depth[5];   // 1/depth of surface a (x) and surface b (y) (which is in front unspecified)
  vec4 relative[5];    // per surface a, b: (depth - depth_c) / depth in xy, (field - field_c) / depth in zw
  uvec3 triangles[4];
  uint vertex_count;
  uint triangle_count;
};

float cross2(vec2 a, vec2 b) { return a.x * b.y - a.y * b.x; }

// Faces listed opposite each vertex, wound so that all four have the same orientation
// sense for a positively oriented tetrahedron. Their projected signed areas sum to zero.
const uvec3 kFaceOpposite[4] = uvec3[4](uvec3(1, 2, 3), uvec3(0, 3, 2), uvec3(0, 1, 3), uvec3(0, 2, 1));

// Twice the signed area of the projected triangle (p0, p1, p2) (x) and a bound on its rounding
// (y): each corner carries an error of a few ulps of its magnitude (at least 1: the camera
// transform's own rounding), we allow 16 ulp (2^-24 each), and each edge's error multiplies the
// other edge. The area is taken from the corner of smallest magnitude, so a corner far off
// screen (a cell 10^6 times taller than wide, seen from beside it) only brings its error
// times the short edges, not times itself.
vec2 area_and_rounding(vec2 p0, vec2 p1, vec2 p2) {
  float m0 = max(max(abs(p0.x), abs(p0.y)), 1.0), m1 = max(max(abs(p1.x), abs(p1.y)), 1.0), m2 = max(max(abs(p2.x), abs(p2.y)), 1.0);
  // Rotating the corners keeps the orientation, hence the area.
  if (m1 < m0 && m1 <= m2) {
    vec2 p = p0; p0 = p1; p1 = p2; p2 = p;
    float m = m0; m0 = m1; m1 = m2; m2 = m;
  } else if (m2 < m0 && m2 < m1) {
    vec2 p = p2; p2 = p1; p1 = p0; p0 = p;
    float m = m2; m2 = m1; m1 = m0; m0 = m;
  }
  vec2 a = p1 - p0, b = p2 - p0;
  const float ulp = 5.96e-8;
  float rounding = 16.0 * ulp * ((m0 + m1) * (abs(b.x) + abs(b.y)) + (m0 + m2) * (abs(a.x) + abs(a.y))) +
                   4.0 * ulp * (abs(a.x * b.y) + abs(a.y * b.x));
  return vec2(cross2(a, b), rounding);
}

// Drops proxy triangles whose area is within rounding of zero. They arise when a vertex falls on
// the silhouette (edge-on faces); their true coverage is nil, but a rasterizer given a sliver of
// rounding width can still cover pixel centres with it, interpolating attributes across a
// vanishing area, which gives wild values or NaN.
void drop_degenerate_triangles(inout TetProxy proxy) {
  uint kept = 0u;
  for (uint t = 0u; t < proxy.triangle_count; ++t) {
    uvec3 tri = proxy.triangles[t];
    vec2 a = area_and_rounding(proxy.ndc[tri.x], proxy.ndc[tri.y], proxy.ndc[tri.z]);
    if (abs(a.x) > a.y) proxy.triangles[kept++] = tri;
  }
  proxy.triangle_count = kept;
}

// Stores proxy vertex k: screen position s, surface a's and surface b's (1/depth,
// (depth - depth_c)/depth, (field - field_c)/depth).
void set_proxy_vertex(inout TetProxy proxy, uint k, vec2 s, vec3 a, vec3 b) {
  proxy.ndc[k] = s;
  proxy.inv_depth[k] = vec2(a.x, b.x);
  proxy.relative[k] = vec4(a.y, b.y, a.z, b.z);
}

// The surface attributes (1/depth, (depth - depth_c)/depth, (field - field_c)/depth) of the
// point at `offset` from c (camera orientation) where the field is `value`.
vec3 surface_at(vec3 offset, float value, vec3 cam_c, float field_c) {
  float inv_d = 1.0 / -(cam_c.z + offset.z);
  return vec3(inv_d, -offset.z * inv_d, (value - field_c) * inv_d);
}

vec2 project_point(vec3 cam, mat4 projection) {
  vec4 clip = projection * vec4(cam, 1.0);
  return clip.xy / clip.w;
}

// `piece`: the vertices relative to c (xyz) with the field there (w); `cam_c`: c in camera
// space; `field_c`: the field at c.
TetProxy project_tetrahedron(vec4 piece[4], vec3 cam_c, float field_c, mat4 projection) {
  TetProxy proxy;
  proxy.vertex_count = 0u;
  proxy.triangle_count = 0u;

  vec2 s[4];
  vec3 surf[4];  // per vertex: 1/depth, (depth - depth_c)/depth, (field - field_c)/depth
  for (int i = 0; i < 4; ++i) {
    s[i] = project_point(cam_c + piece[i].xyz, projection);
    surf[i] = surface_at(piece[i].xyz, piece[i].w, cam_c, field_c);
  }

  // Signed doubled areas of the projected faces. A face whose area is within the rounding of
  // its projected corners is edge-on (an edge along the view ray, a face in a plane through the
  // eye compute an area of that rounding, not zero) and carries no coverage, so it must not
  // decide the classification. Nothing else makes a face edge-on: a real face of any shape,
  // however thin or long on screen, votes with its sign.
  float area[4];
  bool counts[4];
  int positive = 0, negative = 0;
  for (int i = 0; i < 4; ++i) {
    uvec3 f = kFaceOpposite[i];
    vec2 a = area_and_rounding(s[f.x], s[f.y], s[f.z]);
    area[i] = a.x;
    counts[i] = abs(a.x) > a.y;
    if (counts[i] && a.x > 0.0) ++positive;
    if (counts[i] && a.x < 0.0) ++negative;
  }
  if (positive == 0 || negative == 0) return proxy;  // projects to a segment or a point

  if (positive == 1 || negative == 1) {
    // Case 1: the silhouette is the single face whose sign is alone; the vertex opposite it
    // projects inside.
    float lone_sign = (positive == 1) ? 1.0 : -1.0;
    int inner = 0;
    for (int i = 0; i < 4; ++i)
      if (counts[i] && area[i] * lone_sign > 0.0) inner = i;
    uvec3 f = kFaceOpposite[inner];
    // The ray from the eye through the inner vertex p meets the silhouette face's plane at
    // p + k (cam_c + p) (camera space, all relative to c): k = -n.(p - v0) / n.(cam_c + p).
    vec3 p = piece[inner].xyz, v0 = piece[f.x].xyz, v1 = piece[f.y].xyz, v2 = piece[f.z].xyz;
    vec3 n = cross(v1 - v0, v2 - v0);
    float along = dot(n, cam_c + p);
    if (!(abs(along) > 0.0)) return proxy;  // the silhouette face edge-on: cannot pass the area test
    vec3 q = p - dot(n, p - v0) / along * (cam_c + p);
    // The field at q from its barycentrics in the face (3D, relative to c).
    float nn = dot(n, n);
    vec3 lambda = clamp(vec3(dot(n, cross(v1 - q, v2 - q)), dot(n, cross(v2 - q, v0 - q)), dot(n, cross(v0 - q, v1 - q))) / nn,
                        0.0, 1.0);
    float lambda_sum = lambda.x + lambda.y + lambda.z;
    if (!(lambda_sum > 0.0)) return proxy;  // keeps NaN out (nn > 0 for a face that passed the area test)
    vec3 far_face = surface_at(q, dot(lambda, vec3(piece[f.x].w, piece[f.y].w, piece[f.z].w)) / lambda_sum, cam_c, field_c);
    for (int k = 0; k < 3; ++k) set_proxy_vertex(proxy, uint(k), s[f[k]], surf[f[k]], surf[f[k]]);
    set_proxy_vertex(proxy, 3u, s[inner], surf[inner], far_face);
    proxy.triangles[0] = uvec3(3, 0, 1);
    proxy.triangles[1] = uvec3(3, 1, 2);
    proxy.triangles[2] = uvec3(3, 2, 0);
    proxy.vertex_count = 4u;
    proxy.triangle_count = 3u;
    drop_degenerate_triangles(proxy);
    return proxy;
  }

  // Case 2: two faces of each sign. The edge shared by the two positive faces and the edge
  // shared by the two negative faces are the quad's diagonals; they cross at the inner vertex.
  int pos[2], neg[2];
  int np = 0, nn = 0;
  for (int i = 0; i < 4; ++i) {
    if (counts[i] && area[i] > 0.0) pos[np++] = i;
    else if (counts[i] && area[i] < 0.0) neg[nn++] = i;
  }
  // The positive faces (opposite pos[0], pos[1]) share the edge joining the other two
  // vertices, neg[0]-neg[1]; the negative faces share the edge pos[0]-pos[1].
  int a = neg[0], b = neg[1];   // diagonal 1: edge a-b
  int c = pos[0], d = pos[1];   // diagonal 2: edge c-d
  // The diagonals cross where edge a-b meets the plane through the eye and edge c-d (and c-d
  // the plane through the eye and a-b); in camera orientation relative to c (the eye at -cam_c),
  // the plane's normal m = (cam_c + c) x (d - c) gives the parameter m.(a - c) / m.(a - b).
  vec3 pa = piece[a].xyz, pb = piece[b].xyz, pc = piece[c].xyz, pd = piece[d].xyz;
  vec3 m_cd = cross(cam_c + pc, pd - pc), m_ab = cross(cam_c + pa, pb - pa);
  float t_denom = dot(m_cd, pa - pb), u_denom = dot(m_ab, pc - pd);
  // Nonzero while the quad has area (its faces passed the area test); the guard
  // only keeps NaN out if rounding ever says otherwise.
  if (!(abs(t_denom) > 0.0) || !(abs(u_denom) > 0.0)) return proxy;
  float t = clamp(dot(m_cd, pa - pc) / t_denom, 0.0, 1.0);
  float u = clamp(dot(m_ab, pc - pa) / u_denom, 0.0, 1.0);
  vec4 on_ab = mix(piece[a], piece[b], t), on_cd = mix(piece[c], piece[d], u);
  set_proxy_vertex(proxy, 0u, s[a], surf[a], surf[a]);
  set_proxy_vertex(proxy, 1u, s[c], surf[c], surf[c]);
  set_proxy_vertex(proxy, 2u, s[b], surf[b], surf[b]);
  set_proxy_vertex(proxy, 3u, s[d], surf[d], surf[d]);
  set_proxy_vertex(proxy, 4u, project_point(cam_c + on_ab.xyz, projection), surface_at(on_ab.xyz, on_ab.w, cam_c, field_c),
                   surface_at(on_cd.xyz, on_cd.w, cam_c, field_c));
  proxy.triangles[0] = uvec3(4, 0, 1);
  proxy.triangles[1] = uvec3(4, 1, 2);
  proxy.triangles[2] = uvec3(4, 2, 3);
  proxy.triangles[3] = uvec3(4, 3, 0);
  proxy.vertex_count = 5u;
  proxy.triangle_count = 4u;
  drop_degenerate_triangles(proxy);
  return proxy;
}

#endif
