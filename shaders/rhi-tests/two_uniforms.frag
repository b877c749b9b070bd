#version 450
// Two uniform blocks, each giving two channels: the image shows which slice of each a draw read
// (tests/rhi/dynamic_offsets_test.cpp: dynamic offsets are taken in binding order).
layout(std140, set = 0, binding = 0) uniform First { vec4 color; } first;
layout(std140, set = 0, binding = 1) uniform Second { vec4 color; } second;
layout(location = 0) out vec4 outColor;

void main() { outColor = vec4(first.color.rg, second.color.ba); }
