#version 450
// Each dispatch reads the uniform slice its dynamic offset selects and writes the slice's value
// at the slice's index (tests/rhi/dynamic_offsets_test.cpp).
layout(local_size_x = 1) in;
layout(std140, set = 0, binding = 0) uniform Slice { uint index; uint value; } slice;
layout(std430, set = 0, binding = 1) writeonly buffer Results { uint values[]; } results;

void main() { results.values[slice.index] = slice.value; }
