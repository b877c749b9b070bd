#version 450
// Reads a block in layout LAYOUT (std140 or std430) into a flat array, and writes a block of
// the same layout with scalar i = i + 0.5 (declaration order), for comparison with C++ structs.
layout(local_size_x = 1) in;

#define BLOCK_MEMBERS vec3 v; float f; float arr[3]; mat4 m; vec2 tail;
layout(LAYOUT, set = 0, binding = 0) readonly buffer Source { BLOCK_MEMBERS } src;
layout(std430, set = 0, binding = 1) writeonly buffer Flat { float values[]; } flatOut;
layout(LAYOUT, set = 0, binding = 2) writeonly buffer Destination { BLOCK_MEMBERS } dst;

void main() {
    for (int i = 0; i < 3; ++i) flatOut.values[i] = src.v[i];
    flatOut.values[3] = src.f;
    for (int i = 0; i < 3; ++i) flatOut.values[4 + i] = src.arr[i];
    for (int i = 0; i < 16; ++i) flatOut.values[7 + i] = src.m[i / 4][i % 4];
    for (int i = 0; i < 2; ++i) flatOut.values[23 + i] = src.tail[i];

    dst.v = vec3(0.5, 1.5, 2.5);
    dst.f = 3.5;
    for (int i = 0; i < 3; ++i) dst.arr[i] = float(4 + i) + 0.5;
    for (int i = 0; i < 16; ++i) dst.m[i / 4][i % 4] = float(7 + i) + 0.5;
    dst.tail = vec2(23.5, 24.5);
}
