#version 450
// Pixel x of a 32x1 R32UI target receives the bits of the x-th scalar of the block, in
// declaration order, so the test can compare what the shader saw with a C++ struct.
layout(std140, set = 0, binding = 0) uniform Block {
    vec3 v;
    float f;
    float arr[3];
    mat4 m;
    vec2 tail;
} block;
layout(location = 0) out uint outBits;

void main() {
    int i = int(gl_FragCoord.x);
    float value = -1.0;
    if (i < 3) value = block.v[i];
    else if (i == 3) value = block.f;
    else if (i < 7) value = block.arr[i - 4];
    else if (i < 23) value = block.m[(i - 7) / 4][(i - 7) % 4];
    else if (i < 25) value = block.tail[i - 23];
    outBits = floatBitsToUint(value);
}
