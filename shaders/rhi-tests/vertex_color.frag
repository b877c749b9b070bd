#version 450
// flat: tests give every vertex of a triangle one colour, so no interpolation rounding enters
// the comparison (and the provoking-vertex difference between GL and Vulkan cannot matter).
layout(location = 0) flat in vec4 vColor;
layout(location = 0) out vec4 outColor;

void main() { outColor = vColor; }
