#version 450
// Fallback mesh deformer: writes the texel deform_points.vert computed.
layout(location = 0) flat in vec4 vTexel;
layout(location = 0) out vec4 outTexel;

void main() { outTexel = vTexel; }
