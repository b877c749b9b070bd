// Animation sampling (STEP, LINEAR with slerp, CUBICSPLINE), posing (poseScene: node world
// matrices parents first without recursion, instance worlds, joint matrices, morph weights) and
// the CPU reference of morphing and skinning (posedVertices). docs/SCENES.md, "Animations".
#include "animation.h"

#include <algorithm>
#include <cmath>
#include <cstring>
#include <string>

#include <fmt/format.h>
#include <glm/gtc/matrix_transform.hpp>
#include <glm/gtc/type_ptr.hpp>

#include "scene_internal.h"

namespace janus::renderer {

namespace detail {
namespace {

const char* pathName(AnimationPath path) {
    switch (path) {
        case AnimationPath::Translation: return "translation";
        case AnimationPath::Rotation: return "rotation";
        case AnimationPath::Scale: return "scale";
        case AnimationPath::Weights: return "weights";
    }
    return "?";
}

std::string nodeLabel(const Scene& scene, size_t index) {
    const std::string& name = scene.nodes[index].name;
    return name.empty() ? fmt::format("node {}", index) : fmt::format("node {} ('{}')", index, name);
}

std::string animationLabel(const Scene& scene, size_t index) {
    const std::string& name = scene.animations[index].name;
    return name.empty() ? fmt::format("animation {}", index) : fmt::format("animation {} ('{}')", index, name);
}

bool finite(const float* values, size_t count) {
    for (size_t i = 0; i < count; ++i)
        if (!std::isfinite(values[i])) return false;
    return true;
}
template <typename T>
bool finiteValue(const T& value) {
    return finite(glm::value_ptr(value), sizeof(T) / sizeof(float));
}

glm::quat normalizedOrIdentity(glm::quat q) {
    const float length = glm::length(q);
    return length > 0.0f && std::isfinite(length) ? q / length : glm::quat(1.0f, 0.0f, 0.0f, 0.0f);
}

// Renormalises a normal or tangent direction; a zero (or degenerate) vector stays zero.
glm::vec3 normalizedOrZero(glm::vec3 v) {
    const float length = glm::length(v);
    return length > 0.0f && std::isfinite(length) ? v / length : glm::vec3(0.0f);
}

}  // namespace

glm::quat slerpShortest(glm::quat a, glm::quat b, float t) {
    a = normalizedOrIdentity(a);
    b = normalizedOrIdentity(b);
    float d = glm::dot(a, b);
    if (d < 0.0f) {   // the other way round is shorter: q and -q are the same rotation
        b = -b;
        d = -d;
    }
    glm::quat result;
    if (d > 0.9995f) {
        result = a * (1.0f - t) + b * t;   // nearly parallel: sin(theta) ~ 0, lerp is exact enough
    } else {
        const float theta = std::acos(d);
        const float sinTheta = std::sin(theta);
        result = a * (std::sin((1.0f - t) * theta) / sinTheta) + b * (std::sin(t * theta) / sinTheta);
    }
    return normalizedOrIdentity(result);
}

void sampleAnimation(const AnimationSampler& sampler, AnimationPath path, float time, float* out) {
    const size_t keys = sampler.times.size();
    const size_t c = sampler.components;
    const bool cubic = sampler.interpolation == Interpolation::CubicSpline;
    const size_t stride = cubic ? 3 * c : c;
    // CUBICSPLINE keyframes are (in-tangent, value, out-tangent), each `c` floats.
    auto value = [&](size_t k) { return sampler.values.data() + k * stride + (cubic ? c : 0); };
    auto finish = [&] {
        if (path == AnimationPath::Rotation && c == 4) {
            const glm::quat q = normalizedOrIdentity(glm::quat(out[3], out[0], out[1], out[2]));
            out[0] = q.x, out[1] = q.y, out[2] = q.z, out[3] = q.w;
        }
    };
    if (keys == 1 || !(time > sampler.times.front())) {   // before the first keyframe (or at it)
        std::memcpy(out, value(0), c * sizeof(float));
        return finish();
    }
    if (time >= sampler.times.back()) {
        std::memcpy(out, value(keys - 1), c * sizeof(float));
        return finish();
    }
    // times[k] <= time < times[k + 1]
    const size_t k = size_t(std::upper_bound(sampler.times.begin(), sampler.times.end(), time) - sampler.times.begin()) - 1;
    const float t0 = sampler.times[k], t1 = sampler.times[k + 1];
    const float interval = t1 - t0;
    const float s = (time - t0) / interval;
    const float* a = value(k);
    const float* b = value(k + 1);
    switch (sampler.interpolation) {
        case Interpolation::Step: std::memcpy(out, a, c * sizeof(float)); break;
        case Interpolation::Linear:
            if (path == AnimationPath::Rotation && c == 4) {
                const glm::quat q = slerpShortest(glm::quat(a[3], a[0], a[1], a[2]), glm::quat(b[3], b[0], b[1], b[2]), s);
                out[0] = q.x, out[1] = q.y, out[2] = q.z, out[3] = q.w;
            } else {
                for (size_t i = 0; i < c; ++i) out[i] = a[i] * (1.0f - s) + b[i] * s;
            }
            break;
        case Interpolation::CubicSpline: {
            // glTF 2.0, Appendix C: p(s) = (2s^3 - 3s^2 + 1) v_k + td (s^3 - 2s^2 + s) b_k
            //                              + (-2s^3 + 3s^2) v_k+1 + td (s^3 - s^2) a_k+1,
            // b_k the out-tangent of keyframe k, a_k+1 the in-tangent of keyframe k + 1.
            const float s2 = s * s, s3 = s2 * s;
            const float h00 = 2.0f * s3 - 3.0f * s2 + 1.0f, h10 = s3 - 2.0f * s2 + s, h01 = -2.0f * s3 + 3.0f * s2, h11 = s3 - s2;
            const float* outTangent = sampler.values.data() + k * stride + 2 * c;
            const float* inTangent = sampler.values.data() + (k + 1) * stride;
            for (size_t i = 0; i < c; ++i)
                out[i] = h00 * a[i] + h10 * interval * outTangent[i] + h01 * b[i] + h11 * interval * inTangent[i];
            break;
        }
    }
    finish();
}

glm::mat4 localMatrix(const Node& node, glm::vec3 translation, glm::quat rotation, glm::vec3 scale) {
    if (node.matrix) return *node.matrix;
    // The same operations as the loader's first world matrices, so an unanimated scene's matrices
    // are bit for bit those of the node walk.
    glm::mat4 m = glm::translate(glm::mat4(1.0f), translation);
    m *= glm::mat4_cast(rotation);
    return glm::scale(m, scale);
}

void placeLight(Light& light, const glm::mat4& world) {
    light.position = glm::vec3(world[3]);
    const glm::vec3 forward = -glm::vec3(world[2]);   // lights shine down their local -Z
    light.direction = glm::length(forward) > 0.0f ? glm::normalize(forward) : glm::vec3(0, 0, -1);
}

void placeCamera(Camera& camera, const glm::mat4& world) {
    camera.position = glm::vec3(world[3]);
    camera.target = camera.position - glm::normalize(glm::vec3(world[2]));   // glTF cameras look down -Z
    camera.up = glm::normalize(glm::vec3(world[1]));
}

void validateAnimationData(const Scene& scene) {
    const size_t nodeCount = scene.nodes.size();
    // The hierarchy is a forest whose parent and children links agree: walked from the roots
    // (explicit stack: any depth), every node is reached exactly once.
    std::vector<uint8_t> reached(nodeCount, 0);
    std::vector<uint32_t> stack;
    size_t reachedCount = 0;
    for (size_t n = 0; n < nodeCount; ++n) {
        const Node& node = scene.nodes[n];
        if (node.parent < -1 || (node.parent >= 0 && size_t(node.parent) >= nodeCount))
            throw SceneError(fmt::format("{} has parent {}, which does not exist (the scene has {} nodes)", nodeLabel(scene, n),
                                         node.parent, nodeCount));
        if (!finiteValue(node.translation) || !finiteValue(node.rotation) || !finiteValue(node.scale) ||
            (node.matrix && !finiteValue(*node.matrix)) || !finite(node.weights.data(), node.weights.size()))
            throw SceneError(fmt::format("{} has a NaN or infinite transform or weight", nodeLabel(scene, n)));
        if (node.parent != -1) continue;
        stack.push_back(uint32_t(n));
        while (!stack.empty()) {
            const uint32_t at = stack.back();
            stack.pop_back();
            if (reached[at]) throw SceneError(fmt::format("{} is reached twice in the node hierarchy", nodeLabel(scene, at)));
            reached[at] = 1;
            ++reachedCount;
            for (uint32_t child : scene.nodes[at].children) {
                if (child >= nodeCount)
                    throw SceneError(fmt::format("{} has child {}, which does not exist (the scene has {} nodes)", nodeLabel(scene, at),
                                                 child, nodeCount));
                if (scene.nodes[child].parent != int32_t(at))
                    throw SceneError(fmt::format("{} lists {} as a child, but its parent is {}", nodeLabel(scene, at),
                                                 nodeLabel(scene, child), scene.nodes[child].parent));
                stack.push_back(child);
            }
        }
    }
    if (reachedCount != nodeCount)
        for (size_t n = 0; n < nodeCount; ++n)
            if (!reached[n])
                throw SceneError(fmt::format("{} is not reached from any root node (a cycle, or its parent does not list it as a "
                                             "child); node hierarchies must be trees",
                                             nodeLabel(scene, n)));

    for (size_t s = 0; s < scene.skins.size(); ++s) {
        const Skin& skin = scene.skins[s];
        const std::string label = skin.name.empty() ? fmt::format("skin {}", s) : fmt::format("skin {} ('{}')", s, skin.name);
        if (skin.joints.size() > kMaxSkinJoints)
            throw SceneError(fmt::format("{} has {} joints; Janus skins with at most {}", label, skin.joints.size(), kMaxSkinJoints));
        if (skin.inverseBindMatrices.size() != skin.joints.size())
            throw SceneError(fmt::format("{} has {} joints but {} inverse bind matrices", label, skin.joints.size(),
                                         skin.inverseBindMatrices.size()));
        for (uint32_t joint : skin.joints)
            if (joint >= nodeCount)
                throw SceneError(fmt::format("{} has joint node {}, which does not exist (the scene has {} nodes)", label, joint, nodeCount));
        for (const glm::mat4& m : skin.inverseBindMatrices)
            if (!finiteValue(m)) throw SceneError(fmt::format("{} has a NaN or infinite inverse bind matrix", label));
    }

    // Per node, the morph-target count of its mesh instances (-1: none), for weights channels.
    std::vector<int64_t> nodeTargets(nodeCount, -1);
    for (size_t i = 0; i < scene.instances.size(); ++i) {
        const Instance& instance = scene.instances[i];
        if (instance.mesh >= scene.meshes.size())
            throw SceneError(fmt::format("instance {} uses mesh {} but the scene has {}", i, instance.mesh, scene.meshes.size()));
        const Mesh& mesh = scene.meshes[instance.mesh];
        if (instance.node < -1 || (instance.node >= 0 && size_t(instance.node) >= nodeCount))
            throw SceneError(fmt::format("instance {} has node {} but the scene has {} nodes", i, instance.node, nodeCount));
        if (instance.skin < -1 || (instance.skin >= 0 && size_t(instance.skin) >= scene.skins.size()))
            throw SceneError(fmt::format("instance {} has skin {} but the scene has {} skins", i, instance.skin, scene.skins.size()));
        if (mesh.joints.empty() != (instance.skin < 0))
            throw SceneError(mesh.joints.empty()
                                 ? fmt::format("instance {} has skin {} but its mesh {} has no joints and weights", i, instance.skin,
                                               instance.mesh)
                                 : fmt::format("instance {} has no skin but its mesh {} is skinned (has joints and weights)", i,
                                               instance.mesh));
        if (instance.node >= 0) {
            int64_t& targets = nodeTargets[size_t(instance.node)];
            if (targets >= 0 && targets != int64_t(mesh.morphTargets.size()))
                throw SceneError(fmt::format("the meshes of {} have different numbers of morph targets ({} and {})",
                                             nodeLabel(scene, size_t(instance.node)), targets, mesh.morphTargets.size()));
            targets = int64_t(mesh.morphTargets.size());
        }
    }

    for (size_t a = 0; a < scene.animations.size(); ++a) {
        const Animation& animation = scene.animations[a];
        for (size_t s = 0; s < animation.samplers.size(); ++s) {
            const AnimationSampler& sampler = animation.samplers[s];
            const std::string label = fmt::format("{} sampler {}", animationLabel(scene, a), s);
            if (sampler.times.empty()) throw SceneError(fmt::format("{} has no keyframes", label));
            for (size_t k = 0; k < sampler.times.size(); ++k) {
                const float t = sampler.times[k];
                if (!std::isfinite(t) || t < 0.0f)
                    throw SceneError(fmt::format("{} has keyframe time {} (keyframe {}); times must be finite and >= 0", label, t, k));
                if (k > 0 && !(t > sampler.times[k - 1]))
                    throw SceneError(fmt::format("{} input is not strictly increasing: keyframe {} at {} s follows {} s", label, k, t,
                                                 sampler.times[k - 1]));
            }
            if (sampler.components == 0) throw SceneError(fmt::format("{} has 0 components per value", label));
            const size_t perKey = size_t(sampler.components) * (sampler.interpolation == Interpolation::CubicSpline ? 3 : 1);
            if (sampler.values.size() != sampler.times.size() * perKey)
                throw SceneError(fmt::format("{} has {} output values for {} keyframes of {} floats", label, sampler.values.size(),
                                             sampler.times.size(), perKey));
            if (!finite(sampler.values.data(), sampler.values.size()))
                throw SceneError(fmt::format("{} has a NaN or infinite output value", label));
        }
        for (size_t c = 0; c < animation.channels.size(); ++c) {
            const AnimationChannel& channel = animation.channels[c];
            const std::string label = fmt::format("{} channel {}", animationLabel(scene, a), c);
            if (channel.sampler >= animation.samplers.size())
                throw SceneError(fmt::format("{} uses sampler {} but the animation has {}", label, channel.sampler,
                                             animation.samplers.size()));
            if (channel.node >= nodeCount)
                throw SceneError(fmt::format("{} targets node {} but the scene has {} nodes", label, channel.node, nodeCount));
            if (scene.nodes[channel.node].matrix)
                throw SceneError(fmt::format("{} animates {}, which has a 'matrix'; glTF animates only nodes given by translation, "
                                             "rotation and scale",
                                             label, nodeLabel(scene, channel.node)));
            const uint32_t components = animation.samplers[channel.sampler].components;
            int64_t expected = channel.path == AnimationPath::Rotation ? 4 : 3;
            if (channel.path == AnimationPath::Weights) {
                expected = nodeTargets[channel.node];
                if (expected <= 0)
                    throw SceneError(fmt::format("{} animates the morph weights of {}, which has no mesh with morph targets", label,
                                                 nodeLabel(scene, channel.node)));
            }
            if (int64_t(components) != expected)
                throw SceneError(fmt::format("{} animates the {} of {} with {} floats per keyframe; it needs {}", label,
                                             pathName(channel.path), nodeLabel(scene, channel.node), components, expected));
        }
    }
}

}  // namespace detail

size_t findAnimation(const Scene& scene, std::string_view nameOrIndex) {
    std::string list;
    for (size_t a = 0; a < scene.animations.size() && a < 32; ++a)
        list += fmt::format("{}{} '{}'", a == 0 ? "" : ", ", a, scene.animations[a].name);
    if (scene.animations.size() > 32) list += ", ...";
    if (scene.animations.empty()) throw SceneError(fmt::format("animation '{}': the scene has no animations", nameOrIndex));
    for (size_t a = 0; a < scene.animations.size(); ++a)
        if (scene.animations[a].name == nameOrIndex) return a;
    const bool digits =
        !nameOrIndex.empty() && std::all_of(nameOrIndex.begin(), nameOrIndex.end(), [](char c) { return c >= '0' && c <= '9'; });
    if (digits) {
        if (nameOrIndex.size() <= 9) {
            const size_t index = size_t(std::stoul(std::string(nameOrIndex)));
            if (index < scene.animations.size()) return index;
        }
        throw SceneError(fmt::format("animation index {} is out of range: the scene has {} animation{} ({})", nameOrIndex,
                                     scene.animations.size(), scene.animations.size() == 1 ? "" : "s", list));
    }
    throw SceneError(fmt::format("no animation is named '{}'; the scene's animations: {} (give a name or an index)", nameOrIndex, list));
}

void poseScene(Scene& scene, float time, std::optional<size_t> animation) {
    if (std::isnan(time) || time < 0.0f)
        throw SceneError(fmt::format("animation time {} is not allowed; give seconds >= 0", time));
    if (animation && *animation >= scene.animations.size())
        throw SceneError(fmt::format("animation {} does not exist: the scene has {}", *animation, scene.animations.size()));
    detail::validateAnimationData(scene);

    const size_t nodeCount = scene.nodes.size();
    std::vector<glm::vec3> translations(nodeCount), scales(nodeCount);
    std::vector<glm::quat> rotations(nodeCount);
    for (size_t n = 0; n < nodeCount; ++n) {
        translations[n] = scene.nodes[n].translation;
        rotations[n] = scene.nodes[n].rotation;
        scales[n] = scene.nodes[n].scale;
    }
    // Animated morph weights, per node (index into `weights`; -1: not animated).
    std::vector<int32_t> weightSlot(nodeCount, -1);
    std::vector<std::vector<float>> weights;
    if (animation) {
        const Animation& clip = scene.animations[*animation];
        std::vector<float> value;
        for (const AnimationChannel& channel : clip.channels) {
            const AnimationSampler& sampler = clip.samplers[channel.sampler];
            value.resize(sampler.components);
            detail::sampleAnimation(sampler, channel.path, time, value.data());
            switch (channel.path) {
                case AnimationPath::Translation: translations[channel.node] = glm::vec3(value[0], value[1], value[2]); break;
                case AnimationPath::Rotation: rotations[channel.node] = glm::quat(value[3], value[0], value[1], value[2]); break;
                case AnimationPath::Scale: scales[channel.node] = glm::vec3(value[0], value[1], value[2]); break;
                case AnimationPath::Weights:
                    if (weightSlot[channel.node] < 0) {
                        weightSlot[channel.node] = int32_t(weights.size());
                        weights.emplace_back();
                    }
                    weights[size_t(weightSlot[channel.node])] = value;
                    break;
            }
        }
    }

    // World matrices, parents first: a depth-first walk from each root with an explicit stack
    // (validateAnimationData has checked the hierarchy is a forest).
    std::vector<uint32_t> stack;
    for (size_t root = 0; root < nodeCount; ++root) {
        if (scene.nodes[root].parent != -1) continue;
        stack.push_back(uint32_t(root));
        while (!stack.empty()) {
            const uint32_t n = stack.back();
            stack.pop_back();
            Node& node = scene.nodes[n];
            const glm::mat4 local = detail::localMatrix(node, translations[n], rotations[n], scales[n]);
            node.world = node.parent < 0 ? local : scene.nodes[size_t(node.parent)].world * local;
            for (auto child = node.children.rbegin(); child != node.children.rend(); ++child) stack.push_back(*child);
        }
    }

    for (Instance& instance : scene.instances) {
        const Mesh& mesh = scene.meshes[instance.mesh];
        if (instance.node >= 0) {
            const size_t n = size_t(instance.node);
            // glTF ignores the transform of a skinned mesh's node: its joints place it.
            instance.world = instance.skin >= 0 ? glm::mat4(1.0f) : scene.nodes[n].world;
            if (weightSlot[n] >= 0) instance.morphWeights = weights[size_t(weightSlot[n])];
            else if (!scene.nodes[n].weights.empty() && scene.nodes[n].weights.size() == mesh.morphTargets.size())
                instance.morphWeights = scene.nodes[n].weights;
            else instance.morphWeights = mesh.morphWeights;
        } else if (instance.morphWeights.size() != mesh.morphTargets.size()) {
            instance.morphWeights = mesh.morphWeights;   // made in code without weights: the mesh's
        }
        if (instance.skin >= 0) {
            const Skin& skin = scene.skins[size_t(instance.skin)];
            instance.jointMatrices.resize(skin.joints.size());
            for (size_t j = 0; j < skin.joints.size(); ++j)
                instance.jointMatrices[j] = scene.nodes[skin.joints[j]].world * skin.inverseBindMatrices[j];
        } else {
            instance.jointMatrices.clear();
        }
    }
    for (Light& light : scene.lights)
        if (light.node >= 0 && size_t(light.node) < nodeCount) detail::placeLight(light, scene.nodes[size_t(light.node)].world);
    for (Marker& marker : scene.markers)
        if (marker.node >= 0 && size_t(marker.node) < nodeCount) marker.world = scene.nodes[size_t(marker.node)].world;
    if (scene.camera.node >= 0 && size_t(scene.camera.node) < nodeCount)
        detail::placeCamera(scene.camera, scene.nodes[size_t(scene.camera.node)].world);
    scene.posedAnimation = animation;
    scene.posedTime = time;
}

std::vector<Vertex> posedVertices(const Scene& scene, const Instance& instance) {
    if (instance.mesh >= scene.meshes.size())
        throw SceneError(fmt::format("posedVertices: the instance uses mesh {} but the scene has {}", instance.mesh, scene.meshes.size()));
    const Mesh& mesh = scene.meshes[instance.mesh];
    std::vector<Vertex> vertices = mesh.vertices;
    const size_t count = vertices.size();

    bool morphed = false;
    const size_t targets = std::min(mesh.morphTargets.size(), instance.morphWeights.size());
    for (size_t t = 0; t < targets; ++t) {
        const float w = instance.morphWeights[t];
        if (w == 0.0f) continue;
        const MorphTarget& target = mesh.morphTargets[t];
        if ((!target.positions.empty() && target.positions.size() != count) || (!target.normals.empty() && target.normals.size() != count) ||
            (!target.tangents.empty() && target.tangents.size() != count))
            throw SceneError(fmt::format("posedVertices: morph target {} of mesh {} does not have one entry per vertex", t, instance.mesh));
        morphed = true;
        for (size_t v = 0; v < count && !target.positions.empty(); ++v) vertices[v].position += w * target.positions[v];
        for (size_t v = 0; v < count && !target.normals.empty(); ++v) vertices[v].normal += w * target.normals[v];
        for (size_t v = 0; v < count && !target.tangents.empty(); ++v)
            vertices[v].tangent = glm::vec4(glm::vec3(vertices[v].tangent) + w * target.tangents[v], vertices[v].tangent.w);
    }

    const bool skinned = instance.skin >= 0 && !mesh.joints.empty();
    if (skinned) {
        if (mesh.joints.size() != count || mesh.weights.size() != count)
            throw SceneError(fmt::format("posedVertices: mesh {} does not have one joint set and weight set per vertex", instance.mesh));
        const std::vector<glm::mat4>& joints = instance.jointMatrices;
        for (size_t v = 0; v < count; ++v) {
            Vertex& vertex = vertices[v];
            glm::mat4 m(0.0f);
            for (int i = 0; i < 4; ++i) {
                const uint32_t joint = mesh.joints[v][i];
                if (joint >= joints.size())
                    throw SceneError(fmt::format("posedVertices: vertex {} of mesh {} uses joint {} but the instance has {} joint matrices",
                                                 v, instance.mesh, joint, joints.size()));
                m += mesh.weights[v][i] * joints[joint];
            }
            vertex.position = glm::vec3(m * glm::vec4(vertex.position, 1.0f));
            // Normals by the inverse transpose of the upper 3x3: its cofactor matrix (columns
            // c1 x c2, c2 x c0, c0 x c1) times the sign of its determinant, the same direction,
            // also defined when the blended matrix is singular.
            const glm::vec3 c0(m[0]), c1(m[1]), c2(m[2]);
            const glm::mat3 cofactor(glm::cross(c1, c2), glm::cross(c2, c0), glm::cross(c0, c1));
            const float sign = glm::dot(c0, glm::cross(c1, c2)) < 0.0f ? -1.0f : 1.0f;
            vertex.normal = sign * (cofactor * vertex.normal);
            vertex.tangent = glm::vec4(glm::mat3(m) * glm::vec3(vertex.tangent), vertex.tangent.w);
        }
    }
    if (morphed || skinned)
        for (Vertex& vertex : vertices) {
            vertex.normal = detail::normalizedOrZero(vertex.normal);
            vertex.tangent = glm::vec4(detail::normalizedOrZero(glm::vec3(vertex.tangent)), vertex.tangent.w);
        }
    return vertices;
}

}  // namespace janus::renderer
