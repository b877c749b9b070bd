#version 450
// Writes six ColorVertex records (vec4 position, vec4 colour) of a green rectangle covering the
// left half of the target, for a draw that reads them as a vertex buffer.
layout(local_size_x = 6) in;
layout(std430, set = 0, binding = 0) writeonly buffer Vertices { vec4 data[]; } vertices;

void main() {
    const vec2 corners[6] = vec2[6](vec2(-1, -1), vec2(-1, 1), vec2(0, -1), vec2(0, -1), vec2(-1, 1), vec2(0, 1));
    uint i = gl_LocalInvocationID.x;
    vertices.data[2u * i] = vec4(corners[i], 0.0, 1.0);
    vertices.data[2u * i + 1u] = vec4(0.0, 1.0, 0.0, 1.0);
}
