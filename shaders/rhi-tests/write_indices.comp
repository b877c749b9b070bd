#version 450
// Writes the 32-bit indices 0, 1, 2 of one triangle, for an indexed draw whose index buffer a
// shader wrote (tests/rhi/index_value_checks_test.cpp).
layout(local_size_x = 3) in;
layout(std430, set = 0, binding = 0) writeonly buffer Indices { uint data[]; } indices;

void main() {
    indices.data[gl_LocalInvocationID.x] = gl_LocalInvocationID.x;
}
