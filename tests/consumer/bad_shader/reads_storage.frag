#version 450
layout(set = 0, binding = 0, std430) readonly buffer Colors {
    vec4 colors[];
};
layout(location = 0) out vec4 fragColor;

void main() { fragColor = colors[0]; }
