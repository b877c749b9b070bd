#version 450
// White whose alpha ramps from 0 at the target's left edge to 1 at its right (with
// fullscreen.vert): alpha to coverage turns it into a coverage ramp (tests/rhi/multisample_test.cpp).
layout(location = 0) in vec2 vUv;
layout(location = 0) out vec4 outColor;

void main() { outColor = vec4(1.0, 1.0, 1.0, vUv.x); }
