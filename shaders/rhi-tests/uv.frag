#version 450
// The interpolated texture coordinate of fullscreen.vert and the pixel's window x, for checking
// that every backend samples varyings at pixel centres (tests/rhi/orientation_test.cpp).
layout(location = 0) in vec2 vUv;
layout(location = 0) out vec4 outValue;

void main() { outValue = vec4(vUv, gl_FragCoord.x, 1.0); }
