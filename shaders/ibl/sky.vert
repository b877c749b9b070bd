#version 450
// The sky background: a triangle covering the target at the far plane (depth 1), so with a
// LessOrEqual test against the scene's depth it shows only where no surface was drawn.
layout(location = 0) out vec2 vNdc;

void main() {
    vec2 uv = vec2((gl_VertexIndex << 1) & 2, gl_VertexIndex & 2);
    vNdc = uv * 2.0 - 1.0;
    gl_Position = vec4(vNdc, 1.0, 1.0);
}
