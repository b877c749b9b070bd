#version 450
#extension GL_GOOGLE_include_directive : require
// Forward pass: world-space position, normal, tangent, both UV sets and the vertex colour for forward.frag.
#include "renderer/forward_common.glsl"

layout(location = 0) in vec3 inPosition;
layout(location = 1) in vec3 inNormal;
layout(location = 2) in vec2 inUv;
layout(location = 3) in vec4 inTangent;
layout(location = 4) in vec2 inUv1;
layout(location = 5) in vec4 inColor;

layout(location = 0) out vec3 vWorldPosition;
layout(location = 1) out vec3 vNormal;
layout(location = 2) out vec2 vUv;
layout(location = 3) out vec4 vTangent;
layout(location = 4) out vec2 vUv1;
layout(location = 5) out vec4 vColor;


void main() {
    // The depth prepass and the forward pass (depth test LessOrEqual, no depth write) must get the
    // same depth bits for the same vertex: `precise` forbids contracting these products into
    // FMAs differently per pipeline. Across GL programs only `invariant gl_Position` promises
    // equal results; the GL translation adds it (gl_shader_translation.cpp). The SPIR-V leaves it
    // out: Mesa's SPIR-V reader warns on glslang's decoration of the gl_PerVertex member.
    precise vec4 world = draw.world * vec4(inPosition, 1.0);
    vWorldPosition = world.xyz;
    vNormal = mat3(draw.normalMatrix) * inNormal;
    vTangent = vec4(mat3(draw.world) * inTangent.xyz, inTangent.w);
    vUv = inUv;
    vUv1 = inUv1;
    vColor = inColor;
    // Points are one pixel (GLES and Vulkan read the size only from here).
    gl_PointSize = 1.0;
    precise vec4 position = frame.viewProjection * world;
    gl_Position = position;
}
