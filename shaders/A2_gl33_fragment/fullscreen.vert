#version 330 core
// The vertex shader of every pass: one triangle, twice the size of the screen, that
// the rasteriser clips to exactly cover it, so the fragment shader runs once for every
// pixel. Its three corners come from gl_VertexID; no vertex buffer is needed.

void main() {
    vec2 corner = vec2((gl_VertexID << 1) & 2, gl_VertexID & 2);  // (0,0) (2,0) (0,2)
    gl_Position = vec4(corner * 2.0 - 1.0, 0.0, 1.0);
}
