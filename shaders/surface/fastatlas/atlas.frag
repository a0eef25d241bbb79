#version 460
// The triangle-ID atlas: each covered texel keeps the nearest triangle (depth test).
layout(location = 0) flat in uint in_triangle;
layout(location = 0) out uint out_id;

void main() { out_id = in_triangle; }
