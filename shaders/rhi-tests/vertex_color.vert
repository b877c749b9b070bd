#version 450
// Position straight to clip space (tests choose exact NDC values) plus a per-vertex colour.
layout(location = 0) in vec4 inPosition;
layout(location = 1) in vec4 inColor;
layout(location = 0) flat out vec4 vColor;

void main() {
    vColor = inColor;
    gl_Position = inPosition;
    gl_PointSize = 1.0;   // point lists: Vulkan and GLES read the size only from here
}
