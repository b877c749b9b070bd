#version 450
// The colour comes from a uniform block so that every draw needs its own binding (the benchmark
// rebinds the block at a different buffer offset per draw; the last draw's colour is checked).
layout(std140, set = 0, binding = 0) uniform DrawParameters { vec4 color; } drawParameters;
layout(location = 0) out vec4 outColor;

void main() { outColor = drawParameters.color; }
