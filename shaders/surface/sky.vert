#version 460
// One triangle covering the viewport at the far depth (0 with reversed z): with an EQUAL depth
// test it is drawn exactly where no surface was.
void main() {
  vec2 p = vec2(float((gl_VertexIndex & 1) * 4 - 1), float((gl_VertexIndex & 2) * 2 - 1));
  gl_Position = vec4(p, 0.0, 1.0);
}
