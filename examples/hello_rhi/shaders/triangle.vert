#version 450
// A triangle with one colour for all its vertices, from a uniform block.
layout(location = 0) in vec2 position;

layout(set = 0, binding = 0, std140) uniform Tint {
    vec4 color;
} tint;

layout(location = 0) out vec4 color;

void main() {
    color = tint.color;
    // Clip space is Vulkan's on every backend: y = -1 is the top row, depth runs 0..1.
    gl_Position = vec4(position, 0.0, 1.0);
}
