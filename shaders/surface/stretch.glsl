// Sander's stretch between the screen and a texture-space atlas, per pixel (Sander et al.,
// "Texture mapping progressive meshes", section 3; as the FastAtlas paper measures its atlases):
// of the map from atlas texels to screen pixels, the largest (Gamma) and smallest (gamma) singular
// value of its Jacobian, the inverse of the atlas-per-pixel one whose columns are the atlas
// coordinate's change one pixel right (ux) and one pixel down (uy). 1 is one texel per pixel;
// above 1 the atlas undersamples the image. The backends sum (Gamma^2 + gamma^2) / 2 over their
// pixels (L2: its root mean) and keep the largest Gamma (L-infinity).
#ifndef PRISMOID_SURFACE_STRETCH_GLSL
#define PRISMOID_SURFACE_STRETCH_GLSL

// false where the atlas map is degenerate or not finite there.
bool pixel_stretch(vec2 ux, vec2 uy, out float big, out float small) {
  float f = dot(ux, ux) + dot(uy, uy);
  float det = abs(ux.x * uy.y - ux.y * uy.x);
  float root = sqrt(max(f * f - 4.0 * det * det, 0.0));
  float s1 = sqrt(0.5 * (f + root)), s2 = sqrt(max(0.5 * (f - root), 0.0));
  // s2 from det / s1 keeps it accurate where the two are far apart.
  if (s1 > 0.0) s2 = det / s1;
  big = 1.0 / s2;
  small = 1.0 / s1;
  return s2 > 0.0 && !isinf(big) && !isnan(big) && !isnan(small);
}

// Fixed point of the per-pixel L2 term in the sums: 1/4096 (a relative rounding of 1e-4 at a
// stretch of 1), capped at a stretch of 64. The sums are 64-bit, as two words with a carry
// (stretch_add), so no image size wraps them.
uint stretch_sum_term(float big, float small) { return uint(min(4096.0 * 0.5 * (big * big + small * small) + 0.5, 16777216.0)); }
#define PRISMOID_STRETCH_ONE 4096.0

#endif
