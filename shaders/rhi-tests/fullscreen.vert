#version 450
// One triangle covering the target; vUv = (0,0) at row 0, column 0 (see rhi.h Conventions).
layout(location = 0) out vec2 vUv;

void main() {
    vec2 uv = vec2((gl_VertexIndex << 1) & 2, gl_VertexIndex & 2);
    vUv = uv;
    gl_Position = vec4(uv * 2.0 - 1.0, 0.0, 1.0);
}
