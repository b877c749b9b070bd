#version 450
#extension GL_GOOGLE_include_directive : require
// Compute path of the mesh deformer: one invocation per vertex reads the mesh's vertex, morphs
// and skins it (deform_common.glsl) and writes it, in the renderer's Vertex layout (20 floats:
// position, normal, uv, tangent, uv1, colour, padding), to the posed vertex buffer the frame draws.
#include "janus/shaders/bindings.h"

layout(local_size_x = 64) in;

layout(std430, set = 0, binding = JANUS_BINDING_DEFORM_JOINTS) readonly buffer JointMatrices { mat4 jointMatrices[]; };
layout(std430, set = 0, binding = JANUS_BINDING_DEFORM_MORPHS) readonly buffer MorphDisplacements { vec4 displacements[]; };
layout(std430, set = 0, binding = JANUS_BINDING_DEFORM_BASE) readonly buffer BaseVertices { float baseVertices[]; };
layout(std430, set = 0, binding = JANUS_BINDING_DEFORM_SKIN) readonly buffer SkinWeights { vec4 skinWeights[]; };   // joints, weights per vertex
layout(std430, set = 0, binding = JANUS_BINDING_DEFORM_OUTPUT) writeonly buffer PosedVertices { float posedVertices[]; };

vec4 morphDisplacement(int index) { return displacements[index]; }
mat4 jointMatrix(int joint) { return jointMatrices[joint]; }

#include "renderer/deform_common.glsl"

const int kVertexFloats = 20;   // sizeof(renderer::Vertex) / 4

void main() {
    int vertex = int(gl_GlobalInvocationID.x);
    if (vertex >= deform.counts.x) return;
    int at = vertex * kVertexFloats;
    vec3 position = vec3(baseVertices[at], baseVertices[at + 1], baseVertices[at + 2]);
    vec3 normal = vec3(baseVertices[at + 3], baseVertices[at + 4], baseVertices[at + 5]);
    vec4 tangent = vec4(baseVertices[at + 8], baseVertices[at + 9], baseVertices[at + 10], baseVertices[at + 11]);
    PosedVertex posed = deformVertex(vertex, position, normal, tangent, skinWeights[vertex * 2], skinWeights[vertex * 2 + 1]);
    for (int i = 0; i < kVertexFloats; ++i) posedVertices[at + i] = baseVertices[at + i];
    posedVertices[at] = posed.position.x;
    posedVertices[at + 1] = posed.position.y;
    posedVertices[at + 2] = posed.position.z;
    posedVertices[at + 3] = posed.normal.x;
    posedVertices[at + 4] = posed.normal.y;
    posedVertices[at + 5] = posed.normal.z;
    posedVertices[at + 8] = posed.tangent.x;
    posedVertices[at + 9] = posed.tangent.y;
    posedVertices[at + 10] = posed.tangent.z;
}
