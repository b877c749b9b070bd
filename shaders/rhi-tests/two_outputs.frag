#version 450
// Two colour attachments: the vertex colour and its channels reversed.
layout(location = 0) flat in vec4 vColor;
layout(location = 0) out vec4 outColor;
layout(location = 1) out vec4 outReversed;

void main() {
    outColor = vColor;
    outReversed = vColor.abgr;
}
