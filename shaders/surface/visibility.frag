#version 460
// The shadowed forward backend's depth pre-pass: besides the depth, each pixel's nearest
// triangle as its global index + 1 (0: no surface) in an R32UI target. With the GREATER depth
// test a fragment is written only when it is nearer than everything drawn before it, so the
// value left is that of the fragment whose depth is left (the first of equal depths).
#extension GL_GOOGLE_include_directive : require

layout(early_fragment_tests) in;
layout(location = 0) out uint out_triangle;

void main() { out_triangle = uint(gl_PrimitiveID) + 1u; }
