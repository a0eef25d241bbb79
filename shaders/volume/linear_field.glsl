// The linear function through four values at a tetrahedron's vertices, as a plane in
// camera space: sigma(p) = dot(field.xyz, p) + field.w.
#ifndef PRISMOID_LINEAR_FIELD_GLSL
#define PRISMOID_LINEAR_FIELD_GLSL

vec4 linear_field(vec3 p[4], float s[4]) {
  vec3 e1 = p[1] - p[0], e2 = p[2] - p[0], e3 = p[3] - p[0];
  vec3 c23 = cross(e2, e3), c31 = cross(e3, e1), c12 = cross(e1, e2);
  float det = dot(e1, c23);
  float scale = max(max(dot(e1, e1), dot(e2, e2)), dot(e3, e3));
  // A (nearly) flat cell has no well-defined gradient, and no ray spends length in it:
  // give it its mean value instead of dividing by a vanishing volume.
  if (abs(det) <= 1e-6 * scale * sqrt(scale)) {
    return vec4(0.0, 0.0, 0.0, 0.25 * (s[0] + s[1] + s[2] + s[3]));
  }
  // Gradient from the inverse of the edge matrix: rows of the inverse are the cross products
  // over the determinant.
  vec3 g = ((s[1] - s[0]) * c23 + (s[2] - s[0]) * c31 + (s[3] - s[0]) * c12) / det;
  return vec4(g, s[0] - dot(g, p[0]));
}

#endif
