#version 450
// Instance i is moved right by 0.5 * gl_InstanceIndex, which includes firstInstance (Vulkan
// semantics; GL's gl_InstanceID does not), and takes its colour from a per-instance attribute.
layout(location = 0) in vec4 inPosition;
layout(location = 1) in vec4 inInstanceColor;
layout(location = 0) flat out vec4 vColor;

void main() {
    vColor = inInstanceColor;
    gl_Position = inPosition + vec4(0.5 * float(gl_InstanceIndex), 0.0, 0.0, 0.0);
}
