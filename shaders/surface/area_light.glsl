// Light from an emissive triangle, in float: the twin of renderer/reference/area_light.cpp.
// Polygons hold corners relative to the shading point.
#ifndef PRISMOID_SURFACE_AREA_LIGHT_GLSL
#define PRISMOID_SURFACE_AREA_LIGHT_GLSL

#include "../shared/surface.h"
#include "../shared/surface_math.h"

#define PolygonCorners vec3[PRISMOID_CLIPPED_POLYGON_MAX]

// Keeps the part with dot(normal, p) >= 0 (Sutherland-Hodgman); returns the new corner count.
// A crossing is cut from the corner below, so the two emitters sharing an edge cut it at the
// same point whichever way they run along it.
int clip_to_hemisphere(PolygonCorners src, int count, vec3 normal, out PolygonCorners dst) {
  int out_count = 0;
  for (int i = 0; i < count; ++i) {
    vec3 a = src[i];
    vec3 b = src[i + 1 == count ? 0 : i + 1];
    float da = dot(normal, a), db = dot(normal, b);
    if (da >= 0.0 && out_count < PRISMOID_CLIPPED_POLYGON_MAX) dst[out_count++] = a;
    if ((da >= 0.0) != (db >= 0.0) && out_count < PRISMOID_CLIPPED_POLYGON_MAX) {
      vec3 below = da < 0.0 ? a : b, above = da < 0.0 ? b : a;
      float d_below = min(da, db), d_above = max(da, db);
      dst[out_count++] = below + (above - below) * (d_below / (d_below - d_above));
    }
  }
  return out_count;
}

// a x b for two corners, taken from the shorter corner and the edge: nearly parallel corners (a
// small or distant light) and a corner next to the shading point keep their digits, and an edge
// run the other way gets exactly the negated vector, so the terms of an edge two emitters share
// cancel (a shading point near an emitter's corner: renderer/reference/area_light.hpp).
vec3 corner_cross(vec3 a, vec3 b) { return dot(a, a) <= dot(b, b) ? cross(a, b - a) : cross(a - b, b); }

// Lambert's formula: the integral of dot(normal, w) over the polygon's directions, for a polygon
// on the non-negative side of `normal`.
float projected_solid_angle(PolygonCorners poly, int count, vec3 normal) {
  float sum = 0.0;
  for (int i = 0; i < count; ++i) {
    vec3 a = poly[i];
    vec3 b = poly[i + 1 == count ? 0 : i + 1];
    vec3 c = corner_cross(a, b);
    float len = length(c);
    if (!(len > 0.0)) continue;
    float theta = prismoid_atan2_upper(len, dot(a, b));
    sum += theta * (dot(normal, c) / len);
  }
  return 0.5 * abs(sum);
}

// Solid angle of the triangle (a, b, c) seen from the origin (Van Oosterom & Strackee 1983);
// `edges` = cross(b - a, c - a).
float triangle_solid_angle(vec3 a, vec3 b, vec3 c, vec3 edges) {
  float la = length(a), lb = length(b), lc = length(c);
  float triple = abs(dot(a, edges));
  float denom = la * lb * lc + dot(a, b) * lc + dot(a, c) * lb + dot(b, c) * la;
  return 2.0 * prismoid_atan2_upper(triple, denom);
}

#endif
