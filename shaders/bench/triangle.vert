#version 450
// A tiny triangle straight in clip space: the benchmark measures the CPU cost of issuing draws,
// so the vertex stage does nothing but pass the position through.
layout(location = 0) in vec2 inPosition;

void main() { gl_Position = vec4(inPosition, 0.0, 1.0); }
