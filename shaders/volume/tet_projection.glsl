// Projection of one tetrahedron into an interval-shading proxy (Tricard 2024, section 2.2).
// Input: the four vertices in camera space (all in front of the near plane).
// Output: up to 5 screen-space vertices carrying (1/depth_a, 1/depth_b) and up to 4 triangles.
// Depth is the positive distance along the viewing axis; 1/depth is affine in screen space
// on any plane, so the rasterizer's screen-space interpolation of it is exact.
#ifndef PRISMOID_TET_PROJECTION_GLSL
#define PRISMOID_TET_PROJECTION_GLSL

struct TetProxy {
  vec2 ndc[5];
  vec2 inv_depth[5];   // x: one bounding surface, y: the other (order unspecified)
  uvec3 triangles[4];
  uint vertex_count;
  uint triangle_count;
};

float cross2(vec2 a, vec2 b) { return a.x * b.y - a.y * b.x; }

// Faces listed opposite each vertex, wound so that all four have the same orientation
// sense for a positively oriented tetrahedron. Their projected signed areas sum to zero.
const uvec3 kFaceOpposite[4] = uvec3[4](uvec3(1, 2, 3), uvec3(0, 3, 2), uvec3(0, 1, 3), uvec3(0, 2, 1));

// Drops proxy triangles of (near) zero area. They arise when a vertex falls on the silhouette
// (edge-on faces); their true coverage is nil, but a rasterizer given a sliver of rounding
// width can still cover pixel centres with it, interpolating attributes across a vanishing
// area, which gives wild values or NaN.
void drop_degenerate_triangles(inout TetProxy proxy, float eps) {
  uint kept = 0u;
  for (uint t = 0u; t < proxy.triangle_count; ++t) {
    uvec3 tri = proxy.triangles[t];
    float a = cross2(proxy.ndc[tri.y] - proxy.ndc[tri.x], proxy.ndc[tri.z] - proxy.ndc[tri.x]);
    if (abs(a) > eps) proxy.triangles[kept++] = tri;
  }
  proxy.triangle_count = kept;
}

TetProxy project_tetrahedron(vec3 cam[4], mat4 projection) {
  TetProxy proxy;
  proxy.vertex_count = 0u;
  proxy.triangle_count = 0u;

  vec2 s[4];
  float inv_d[4];
  for (int i = 0; i < 4; ++i) {
    vec4 clip = projection * vec4(cam[i], 1.0);
    s[i] = clip.xy / clip.w;
    inv_d[i] = 1.0 / (-cam[i].z);
  }

  // Signed doubled areas of the projected faces. A face whose area is below `eps` is edge-on
  // and carries no coverage, so it must not decide the classification. `eps` has two parts:
  // one relative to the projected size of the tetrahedron, and one for rounding: projected
  // positions carry an error of a few ulps of their magnitude (|s| up to ~1 in NDC), so an
  // exactly edge-on face (an edge along the view ray, a face in a plane through the eye)
  // computes an area of that error times the tetrahedron's extent, not zero. We allow 16 ulp
  // (2^-24 each) of |s|: generous for the few roundings of the projection, yet at 1024^2 a
  // full-screen cell only loses proxy triangles under a quarter of a pixel in area.
  float area[4];
  float scale = 0.0, magnitude = 0.0;
  for (int i = 0; i < 4; ++i) {
    uvec3 f = kFaceOpposite[i];
    area[i] = cross2(s[f.y] - s[f.x], s[f.z] - s[f.x]);
    for (int j = 0; j < 4; ++j) scale = max(scale, dot(s[i] - s[j], s[i] - s[j]));
    magnitude = max(magnitude, max(abs(s[i].x), abs(s[i].y)));
  }
  float eps = 1e-6 * scale + 16.0 * 5.96e-8 * max(magnitude, 1.0) * sqrt(scale);
  int positive = 0, negative = 0;
  for (int i = 0; i < 4; ++i) {
    if (area[i] > eps) ++positive;
    else if (area[i] < -eps) ++negative;
  }
  if (positive == 0 || negative == 0) return proxy;  // projects to a segment or a point

  if (positive == 1 || negative == 1) {
    // Case 1: the silhouette is the single face whose sign is alone; the vertex opposite it
    // projects inside, and its barycentrics are the other faces' areas over the silhouette's.
    float lone_sign = (positive == 1) ? 1.0 : -1.0;
    int inner = 0;
    for (int i = 0; i < 4; ++i)
      if (area[i] * lone_sign > eps) inner = i;
    uvec3 f = kFaceOpposite[inner];
    float inv_far_face = 0.0;
    float denom = area[inner];  // |denom| > eps, the largest magnitude of the four
    float lambda_sum = 0.0;
    float lambdas[3];
    for (int k = 0; k < 3; ++k) {
      // The face opposite f[k] holds the inner vertex and the other two silhouette vertices.
      lambdas[k] = clamp(-area[f[k]] / denom, 0.0, 1.0);
      lambda_sum += lambdas[k];
    }
    if (!(lambda_sum > 0.0)) return proxy;  // cannot happen when the areas sum to zero; keeps NaN out
    for (int k = 0; k < 3; ++k) inv_far_face += lambdas[k] / lambda_sum * inv_d[f[k]];
    for (int k = 0; k < 3; ++k) {
      proxy.ndc[k] = s[f[k]];
      proxy.inv_depth[k] = vec2(inv_d[f[k]]);
    }
    proxy.ndc[3] = s[inner];
    proxy.inv_depth[3] = vec2(inv_d[inner], inv_far_face);
    proxy.triangles[0] = uvec3(3, 0, 1);
    proxy.triangles[1] = uvec3(3, 1, 2);
    proxy.triangles[2] = uvec3(3, 2, 0);
    proxy.vertex_count = 4u;
    proxy.triangle_count = 3u;
    drop_degenerate_triangles(proxy, eps);
    return proxy;
  }

  // Case 2: two faces of each sign. The edge shared by the two positive faces and the edge
  // shared by the two negative faces are the quad's diagonals; they cross at the inner vertex.
  int pos[2], neg[2];
  int np = 0, nn = 0;
  for (int i = 0; i < 4; ++i) {
    if (area[i] > eps) pos[np++] = i;
    else if (area[i] < -eps) neg[nn++] = i;
  }
  // The positive faces (opposite pos[0], pos[1]) share the edge joining the other two
  // vertices, neg[0]-neg[1]; the negative faces share the edge pos[0]-pos[1].
  int a = neg[0], b = neg[1];   // diagonal 1: edge a-b
  int c = pos[0], d = pos[1];   // diagonal 2: edge c-d
  vec2 ab = s[b] - s[a];
  vec2 cd = s[d] - s[c];
  // |denom| is twice the quad's area, the sum of the two positive faces' (> 2 eps), so the
  // division is safe; the guard only keeps NaN out if rounding ever says otherwise.
  float denom = cross2(ab, cd);
  if (!(abs(denom) > 0.0)) return proxy;
  float t = clamp(cross2(s[c] - s[a], cd) / denom, 0.0, 1.0);
  float u = clamp(cross2(s[c] - s[a], ab) / denom, 0.0, 1.0);
  proxy.ndc[0] = s[a];
  proxy.ndc[1] = s[c];
  proxy.ndc[2] = s[b];
  proxy.ndc[3] = s[d];
  proxy.inv_depth[0] = vec2(inv_d[a]);
  proxy.inv_depth[1] = vec2(inv_d[c]);
  proxy.inv_depth[2] = vec2(inv_d[b]);
  proxy.inv_depth[3] = vec2(inv_d[d]);
  proxy.ndc[4] = mix(s[a], s[b], t);
  proxy.inv_depth[4] = vec2(mix(inv_d[a], inv_d[b], t), mix(inv_d[c], inv_d[d], u));
  proxy.triangles[0] = uvec3(4, 0, 1);
  proxy.triangles[1] = uvec3(4, 1, 2);
  proxy.triangles[2] = uvec3(4, 2, 3);
  proxy.triangles[3] = uvec3(4, 3, 0);
  proxy.vertex_count = 5u;
  proxy.triangle_count = 4u;
  drop_degenerate_triangles(proxy, eps);
  return proxy;
}

#endif
