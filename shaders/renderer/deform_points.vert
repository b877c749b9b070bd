#version 450
#extension GL_GOOGLE_include_directive : require
// Fallback path of the mesh deformer (no compute, no SSBOs): the vertex shader morphs and skins
// (deform_common.glsl) with the joint matrices and the displacements in RGBA32F textures, and
// writes the posed vertex as five RGBA32F texels of a render target, one point per texel:
// instance k of vertex v draws texel 5 v + k, whose 16 bytes are bytes 16 k .. 16 k + 15 of the
// renderer's 80-byte Vertex. Copying the target to a buffer then gives the posed vertex buffer
// that the compute path writes directly.
#include "janus/shaders/bindings.h"

layout(location = 0) in vec3 inPosition;
layout(location = 1) in vec3 inNormal;
layout(location = 2) in vec2 inUv;
layout(location = 3) in vec4 inTangent;
layout(location = 4) in vec2 inUv1;
layout(location = 5) in vec4 inColor;
layout(location = 6) in vec4 inJoints;
layout(location = 7) in vec4 inWeights;

layout(set = 0, binding = JANUS_BINDING_DEFORM_JOINTS) uniform sampler2D jointTexture;   // joint j's column c at texel (4 (j % 256) + c, j / 256)
layout(set = 0, binding = JANUS_BINDING_DEFORM_MORPHS) uniform sampler2D morphTexture;   // entry i at texel (i % width, i / width)

layout(location = 0) flat out vec4 vTexel;

vec4 morphDisplacement(int index) {
    int width = textureSize(morphTexture, 0).x;
    return texelFetch(morphTexture, ivec2(index % width, index / width), 0);
}
mat4 jointMatrix(int joint) {
    ivec2 at = ivec2(4 * (joint % 256), joint / 256);
    return mat4(texelFetch(jointTexture, at, 0), texelFetch(jointTexture, at + ivec2(1, 0), 0), texelFetch(jointTexture, at + ivec2(2, 0), 0),
                texelFetch(jointTexture, at + ivec2(3, 0), 0));
}

#include "renderer/deform_common.glsl"

void main() {
    int vertex = gl_VertexIndex;
    int part = gl_InstanceIndex;
    PosedVertex posed = deformVertex(vertex, inPosition, inNormal, inTangent, inJoints, inWeights);
    if (part == 0) vTexel = vec4(posed.position, posed.normal.x);
    else if (part == 1) vTexel = vec4(posed.normal.yz, inUv);
    else if (part == 2) vTexel = posed.tangent;
    else if (part == 3) vTexel = vec4(inUv1, inColor.rg);
    else vTexel = vec4(inColor.ba, 0.0, 0.0);
    int texel = vertex * 5 + part;
    ivec2 xy = ivec2(texel % deform.target.x, texel / deform.target.x);
    // The texel's centre; NDC y -1 is row 0 (the RHI's convention on every backend).
    gl_Position = vec4((vec2(xy) + 0.5) / vec2(deform.target.xy) * 2.0 - 1.0, 0.0, 1.0);
    gl_PointSize = 1.0;
}
