// Skinning and morphing of one vertex (renderer/src/deform/mesh_deformer.*), shared by deform.comp
// (compute path) and deform_points.vert (fallback path) so that both run the same math. The
// includer defines, before including this file:
//   vec4 morphDisplacement(int index)  entry `index` of the displacement array:
//                                      ((target * vertexCount + vertex) * 3 + attribute),
//                                      attribute 0 position, 1 normal, 2 tangent (xyz)
//   mat4 jointMatrix(int joint)        the skin joint's world matrix times its inverse bind matrix
// Order (as renderer::posedVertices): morph targets first, then the skin.
#include "janus/shaders/bindings.h"

const int kMaxMorphTargets = 64;   // renderer::kMaxMorphTargets

layout(set = 0, binding = JANUS_BINDING_DEFORM_UNIFORMS, std140) uniform DeformUniforms {
    ivec4 counts;   // x vertices, y morph targets, z 1 = skinned, w unused
    ivec4 target;   // fallback path: the output texture's width and height in texels
    vec4 morphWeights[kMaxMorphTargets / 4];
} deform;

struct PosedVertex {
    vec3 position;
    vec3 normal;
    vec4 tangent;
};

float morphWeight(int target) { return deform.morphWeights[target / 4][target % 4]; }

// A zero vector (points and lines without normals, meshes without tangents) stays zero.
vec3 normalizedOrZero(vec3 v) { return dot(v, v) > 0.0 ? normalize(v) : v; }

PosedVertex deformVertex(int vertex, vec3 position, vec3 normal, vec4 tangent, vec4 joints, vec4 weights) {
    // `precise`: both paths (and every pipeline) must get the same bits for the same vertex.
    precise vec3 p = position;
    precise vec3 n = normal;
    precise vec3 t = tangent.xyz;
    for (int target = 0; target < deform.counts.y; ++target) {
        float w = morphWeight(target);
        int at = (target * deform.counts.x + vertex) * 3;
        p += w * morphDisplacement(at).xyz;
        n += w * morphDisplacement(at + 1).xyz;
        t += w * morphDisplacement(at + 2).xyz;
    }
    if (deform.counts.z != 0) {
        precise mat4 skin = weights.x * jointMatrix(int(joints.x)) + weights.y * jointMatrix(int(joints.y)) +
                            weights.z * jointMatrix(int(joints.z)) + weights.w * jointMatrix(int(joints.w));
        p = (skin * vec4(p, 1.0)).xyz;
        mat3 linear = mat3(skin);
        // Normals by the inverse transpose (exact for non-uniform scale), tangents by the matrix.
        n = determinant(linear) != 0.0 ? transpose(inverse(linear)) * n : linear * n;
        t = linear * t;
    }
    PosedVertex result;
    result.position = p;
    result.normal = normalizedOrZero(n);
    result.tangent = vec4(normalizedOrZero(t), tangent.w);
    return result;
}
