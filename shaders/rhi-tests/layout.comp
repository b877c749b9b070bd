#version 450
// Reads a block in layout LAYOUT (std140 or std430) into a flat array, and writes a block of
// the same layout with scalar i = i + 0.5 (declaration order), for comparison with C++ structs.
layout(local_size_x = 1) in;

#define BLOCK_MEMBERS vec3 v; float f; float arr[3]; mat4 m; vec2 tail;
layout(LAYOUT, set = 0, binding = 0) readonly buffer Source { BLOCK_MEMBERS } src;
layout(std430, set = 0, binding = 1) writeonly buffer Flat { float values[]; } flatOut;
layout(LAYOUT, set = 0, binding = 2) writeonly buffer Destination { BLOCK_MEMBERS } dst;

// Constant indices into the blocks only: NVIDIA's GL compiler rejected SPIRV-Cross's output of
// the first version of this shader ("lvalue in array access too complex", "possible array index
// out of bounds"), whose loops wrote dst.m[i / 4][i % 4] and read src.v[i] / src.arr[i] with
// dynamic indices through buffer blocks. What the test checks, the layouts, needs no dynamic index.
void putVec4(int base, vec4 v) {
    flatOut.values[base] = v.x;
    flatOut.values[base + 1] = v.y;
    flatOut.values[base + 2] = v.z;
    flatOut.values[base + 3] = v.w;
}

void main() {
    flatOut.values[0] = src.v.x;
    flatOut.values[1] = src.v.y;
    flatOut.values[2] = src.v.z;
    flatOut.values[3] = src.f;
    flatOut.values[4] = src.arr[0];
    flatOut.values[5] = src.arr[1];
    flatOut.values[6] = src.arr[2];
    putVec4(7, src.m[0]);
    putVec4(11, src.m[1]);
    putVec4(15, src.m[2]);
    putVec4(19, src.m[3]);
    flatOut.values[23] = src.tail.x;
    flatOut.values[24] = src.tail.y;

    dst.v = vec3(0.5, 1.5, 2.5);
    dst.f = 3.5;
    dst.arr[0] = 4.5;
    dst.arr[1] = 5.5;
    dst.arr[2] = 6.5;
    dst.m = mat4(vec4(7.5, 8.5, 9.5, 10.5), vec4(11.5, 12.5, 13.5, 14.5), vec4(15.5, 16.5, 17.5, 18.5), vec4(19.5, 20.5, 21.5, 22.5));
    dst.tail = vec2(23.5, 24.5);
}
