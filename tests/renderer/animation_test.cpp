// Animation sampling (STEP, LINEAR with slerp, CUBICSPLINE) against hand-computed values, posing
// (poseScene: rest pose kept, hierarchies parents first at any depth, skinned instances, errors)
// and the CPU reference of morphing and skinning (posedVertices) on scenes built in code.
#include <gtest/gtest.h>

#include <cmath>
#include <string>
#include <vector>

#include <glm/gtc/matrix_transform.hpp>

#include "gltf_test_file.h"
#include "janus/renderer/scene.h"
#include "scene/animation.h"

namespace janus::renderer {
namespace {

using test_support::sceneErrorOf;

constexpr float kPi = 3.14159265358979f;

using test_support::contains;

AnimationSampler samplerOf(Interpolation interpolation, std::vector<float> times, std::vector<float> values, uint32_t components) {
    AnimationSampler sampler;
    sampler.interpolation = interpolation;
    sampler.times = std::move(times);
    sampler.values = std::move(values);
    sampler.components = components;
    return sampler;
}

std::vector<float> sample(const AnimationSampler& sampler, AnimationPath path, float time) {
    std::vector<float> out(sampler.components);
    detail::sampleAnimation(sampler, path, time, out.data());
    return out;
}

float sample1(const AnimationSampler& sampler, float time) { return sample(sampler, AnimationPath::Weights, time)[0]; }

// A rotation of `degrees` about +Y as glTF's xyzw.
std::vector<float> yRotation(float degrees) {
    const float half = glm::radians(degrees) * 0.5f;
    return {0.0f, std::sin(half), 0.0f, std::cos(half)};
}

// The angle (degrees) and the axis' y of an xyzw rotation whose axis is +-Y.
float yDegrees(const std::vector<float>& q) { return glm::degrees(2.0f * std::atan2(q[1], q[3])); }

TEST(AnimationSampling, StepHoldsEachKeyframeUntilTheNextAndClamps) {
    const AnimationSampler step = samplerOf(Interpolation::Step, {1.0f, 2.0f, 4.0f}, {10.0f, 20.0f, 40.0f}, 1);
    EXPECT_EQ(sample1(step, 0.0f), 10.0f);    // before the first keyframe: the first value
    EXPECT_EQ(sample1(step, 1.0f), 10.0f);
    EXPECT_EQ(sample1(step, 1.999f), 10.0f);
    EXPECT_EQ(sample1(step, 2.0f), 20.0f);    // at a keyframe: that keyframe
    EXPECT_EQ(sample1(step, 3.5f), 20.0f);
    EXPECT_EQ(sample1(step, 4.0f), 40.0f);
    EXPECT_EQ(sample1(step, 100.0f), 40.0f);  // after the last: the last value
}

TEST(AnimationSampling, LinearInterpolatesVectorsAndClamps) {
    const AnimationSampler linear = samplerOf(Interpolation::Linear, {1.0f, 3.0f}, {0, 0, 0, 2, 4, -6}, 3);
    EXPECT_EQ(sample(linear, AnimationPath::Translation, 0.25f), std::vector<float>({0, 0, 0}));
    EXPECT_EQ(sample(linear, AnimationPath::Translation, 2.0f), std::vector<float>({1, 2, -3}));
    EXPECT_EQ(sample(linear, AnimationPath::Translation, 2.5f), std::vector<float>({1.5f, 3, -4.5f}));
    EXPECT_EQ(sample(linear, AnimationPath::Translation, 3.0f), std::vector<float>({2, 4, -6}));
    EXPECT_EQ(sample(linear, AnimationPath::Scale, 7.0f), std::vector<float>({2, 4, -6}));
    // Morph weights: one float per target per keyframe.
    const AnimationSampler weights = samplerOf(Interpolation::Linear, {0.0f, 1.0f}, {0, 1, 1, 0}, 2);
    EXPECT_EQ(sample(weights, AnimationPath::Weights, 0.25f), std::vector<float>({0.25f, 0.75f}));
}

TEST(AnimationSampling, LinearRotationsAreSlerped) {
    std::vector<float> values = yRotation(0.0f);
    for (float v : yRotation(90.0f)) values.push_back(v);
    const AnimationSampler rotation = samplerOf(Interpolation::Linear, {0.0f, 3.0f}, values, 4);
    // Slerp turns at a constant rate: a third of the time, a third of the angle (nlerp would give 28.1 degrees).
    EXPECT_NEAR(yDegrees(sample(rotation, AnimationPath::Rotation, 1.0f)), 30.0f, 1e-4f);
    EXPECT_NEAR(yDegrees(sample(rotation, AnimationPath::Rotation, 1.5f)), 45.0f, 1e-4f);
    const std::vector<float> q = sample(rotation, AnimationPath::Rotation, 2.0f);
    EXPECT_NEAR(q[0] * q[0] + q[1] * q[1] + q[2] * q[2] + q[3] * q[3], 1.0f, 1e-6f);
    EXPECT_NEAR(q[1], std::sin(glm::radians(30.0f)), 1e-6f);   // 60 degrees: (0, sin 30, 0, cos 30)
    EXPECT_NEAR(q[3], std::cos(glm::radians(30.0f)), 1e-6f);
}

// q and -q are the same rotation; slerp must take the short way (flip one when their dot < 0).
TEST(AnimationSampling, LinearRotationsTakeTheShortestArcAcrossASignFlip) {
    std::vector<float> values = yRotation(170.0f);
    std::vector<float> target = yRotation(-170.0f);   // 20 degrees further on, the short way round (dot < 0)
    values.insert(values.end(), target.begin(), target.end());
    const AnimationSampler rotation = samplerOf(Interpolation::Linear, {0.0f, 1.0f}, values, 4);
    const glm::quat start(values[3], values[0], values[1], values[2]), end(target[3], target[0], target[1], target[2]);
    ASSERT_LT(glm::dot(start, end), 0.0f);
    const std::vector<float> half = sample(rotation, AnimationPath::Rotation, 0.5f);
    // Halfway is 180 degrees about Y (either sign), not 0 degrees (the long way round).
    EXPECT_NEAR(std::abs(half[1]), 1.0f, 1e-5f);
    EXPECT_NEAR(half[3], 0.0f, 1e-5f);
    const std::vector<float> quarter = sample(rotation, AnimationPath::Rotation, 0.25f);
    const glm::vec3 turned = glm::quat(quarter[3], quarter[0], quarter[1], quarter[2]) * glm::vec3(1, 0, 0);
    const glm::vec3 expected = glm::angleAxis(glm::radians(175.0f), glm::vec3(0, 1, 0)) * glm::vec3(1, 0, 0);
    EXPECT_NEAR(glm::length(turned - expected), 0.0f, 1e-5f);

    // The same rotation given as its negative at the second keyframe: nothing turns.
    std::vector<float> same = yRotation(30.0f);
    for (float v : yRotation(30.0f)) same.push_back(-v);
    const AnimationSampler still = samplerOf(Interpolation::Linear, {0.0f, 1.0f}, same, 4);
    EXPECT_NEAR(std::abs(yDegrees(sample(still, AnimationPath::Rotation, 0.5f))), 30.0f, 1e-4f);
}

// glTF 2.0 Appendix C: p(s) = (2s^3-3s^2+1) v0 + td (s^3-2s^2+s) b0 + (-2s^3+3s^2) v1 + td (s^3-s^2) a1.
TEST(AnimationSampling, CubicSplineIsTheHermiteSplineWithTangentsScaledByTheInterval) {
    // Keyframes at 0 and 2 s (td = 2), each (in-tangent a, value v, out-tangent b).
    const AnimationSampler cubic = samplerOf(Interpolation::CubicSpline, {0.0f, 2.0f}, {9.0f, 1.0f, 2.0f, -1.0f, 3.0f, 7.0f}, 1);
    // t = 1: s = 0.5, h = (0.5, 0.125, 0.5, -0.125): 0.5 * 1 + 2 * 0.125 * 2 + 0.5 * 3 + 2 * -0.125 * -1 = 2.75
    EXPECT_FLOAT_EQ(sample1(cubic, 1.0f), 2.75f);
    // t = 0.5: s = 0.25, h = (0.84375, 0.140625, 0.15625, -0.046875): 0.84375 + 0.5625 + 0.46875 + 0.09375 = 1.96875
    EXPECT_FLOAT_EQ(sample1(cubic, 0.5f), 1.96875f);
    // Outside the keyframes: the values, never the tangents.
    EXPECT_EQ(sample1(cubic, 0.0f), 1.0f);
    EXPECT_EQ(sample1(cubic, 2.0f), 3.0f);
    EXPECT_EQ(sample1(cubic, 5.0f), 3.0f);

    // Three components (a translation): each is its own spline; the layout is a(3) v(3) b(3) per keyframe.
    const AnimationSampler cubic3 = samplerOf(Interpolation::CubicSpline, {1.0f, 3.0f},
                                              {0, 0, 0, 1, 0, -1, 2, 0, 0, /**/ -1, 0, 0, 3, 0, 1, 0, 0, 0}, 3);
    const std::vector<float> mid = sample(cubic3, AnimationPath::Translation, 2.0f);
    EXPECT_FLOAT_EQ(mid[0], 2.75f);   // as above, shifted by 1 s
    EXPECT_FLOAT_EQ(mid[1], 0.0f);
    EXPECT_FLOAT_EQ(mid[2], 0.0f);    // -1 -> 1 with zero tangents: halfway is 0
}

TEST(AnimationSampling, CubicSplineRotationsAreNormalised) {
    // Two keyframes 0 and 90 degrees about Y with zero tangents: halfway the spline gives the
    // average of the two, which is not unit length.
    std::vector<float> values = {0, 0, 0, 0};
    for (float v : yRotation(0.0f)) values.push_back(v);
    values.insert(values.end(), {0, 0, 0, 0, 0, 0, 0, 0});
    for (float v : yRotation(90.0f)) values.push_back(v);
    values.insert(values.end(), {0, 0, 0, 0});
    const AnimationSampler cubic = samplerOf(Interpolation::CubicSpline, {0.0f, 1.0f}, values, 4);
    const std::vector<float> q = sample(cubic, AnimationPath::Rotation, 0.5f);
    EXPECT_NEAR(q[0] * q[0] + q[1] * q[1] + q[2] * q[2] + q[3] * q[3], 1.0f, 1e-6f);
    EXPECT_NEAR(yDegrees(q), 45.0f, 1e-4f);
}

TEST(AnimationSampling, SlerpOfNearlyEqualRotationsIsStable) {
    const glm::quat a = glm::angleAxis(0.001f, glm::vec3(0, 0, 1));
    const glm::quat b = glm::angleAxis(0.002f, glm::vec3(0, 0, 1));
    const glm::quat half = detail::slerpShortest(a, b, 0.5f);
    EXPECT_NEAR(glm::angle(half), 0.0015f, 1e-5f);
    EXPECT_NEAR(glm::length(half), 1.0f, 1e-6f);
}

// --- poseScene on scenes built in code ---------------------------------------------------------

// A root node at the origin with a child at +1 X that holds a one-vertex mesh; animation 0
// ("slide") moves the root from x = 0 to x = 4 over 2 s, animation 1 ("turn") turns the child
// 90 degrees about Z.
Scene twoNodeScene() {
    Scene scene;
    Mesh mesh;
    mesh.vertices.push_back(Vertex{glm::vec3(1, 0, 0), glm::vec3(0, 0, 1), glm::vec2(0), glm::vec4(0)});
    mesh.indices = {0};
    mesh.topology = MeshTopology::Points;
    scene.meshes.push_back(mesh);
    scene.nodes.resize(2);
    scene.nodes[0].name = "root";
    scene.nodes[0].children = {1};
    scene.nodes[1].name = "child";
    scene.nodes[1].parent = 0;
    scene.nodes[1].translation = glm::vec3(1, 0, 0);
    Instance instance{0, glm::mat4(1.0f)};
    instance.node = 1;
    scene.instances.push_back(instance);
    Animation slide;
    slide.name = "slide";
    slide.samplers.push_back(samplerOf(Interpolation::Linear, {0.0f, 2.0f}, {0, 0, 0, 4, 0, 0}, 3));
    slide.channels.push_back(AnimationChannel{0, 0, AnimationPath::Translation});
    slide.duration = 2.0f;
    Animation turn;
    turn.name = "turn";
    std::vector<float> values = {0, 0, 0, 1};
    const glm::quat q = glm::angleAxis(kPi / 2.0f, glm::vec3(0, 0, 1));
    values.insert(values.end(), {q.x, q.y, q.z, q.w});
    turn.samplers.push_back(samplerOf(Interpolation::Linear, {0.0f, 1.0f}, values, 4));
    turn.channels.push_back(AnimationChannel{0, 1, AnimationPath::Rotation});
    turn.duration = 1.0f;
    scene.animations = {slide, turn};
    return scene;
}

glm::vec3 originOf(const glm::mat4& m) { return glm::vec3(m[3]); }

TEST(PoseScene, NodeAnimationsMoveInstancesAndPosingAgainStartsFromTheRestPose) {
    Scene scene = twoNodeScene();
    poseScene(scene, 1.0f, 0);
    EXPECT_EQ(originOf(scene.nodes[0].world), glm::vec3(2, 0, 0));
    EXPECT_EQ(originOf(scene.instances[0].world), glm::vec3(3, 0, 0));   // child: parent's world * its own
    EXPECT_EQ(scene.nodes[0].translation, glm::vec3(0));                 // the rest transform is kept
    EXPECT_EQ(scene.posedAnimation, std::optional<size_t>(0));
    EXPECT_EQ(scene.posedTime, 1.0f);
    poseScene(scene, 5.0f, 0);                                           // past the end: holds the end
    EXPECT_EQ(originOf(scene.instances[0].world), glm::vec3(5, 0, 0));

    poseScene(scene, 0.5f, 1);   // the other animation: the root is back at rest
    EXPECT_EQ(originOf(scene.nodes[0].world), glm::vec3(0));
    const glm::vec3 x = glm::mat3(scene.instances[0].world) * glm::vec3(1, 0, 0);
    EXPECT_NEAR(x.x, std::cos(kPi / 4.0f), 1e-6f);
    EXPECT_NEAR(x.y, std::sin(kPi / 4.0f), 1e-6f);

    poseScene(scene, 0.0f, std::nullopt);   // no animation: the rest pose
    EXPECT_EQ(scene.instances[0].world, glm::translate(glm::mat4(1.0f), glm::vec3(1, 0, 0)));
    EXPECT_FALSE(scene.posedAnimation.has_value());
}

TEST(PoseScene, BadTimesAndIndicesAreSceneErrors) {
    Scene scene = twoNodeScene();
    EXPECT_TRUE(contains(sceneErrorOf([&] { poseScene(scene, -0.5f, 0); }), "-0.5")) << "negative time";
    EXPECT_TRUE(contains(sceneErrorOf([&] { poseScene(scene, std::nanf(""), 0); }), "nan"));
    EXPECT_TRUE(contains(sceneErrorOf([&] { poseScene(scene, 0.0f, 2); }), "animation 2 does not exist"));
    scene.nodes[1].parent = 1;   // a broken hierarchy made in code
    EXPECT_TRUE(contains(sceneErrorOf([&] { poseScene(scene, 0.0f, 0); }), "node 0 ('root') lists node 1 ('child') as a child"));
}

TEST(PoseScene, FindAnimationByNameOrIndex) {
    const Scene scene = twoNodeScene();
    EXPECT_EQ(findAnimation(scene, "turn"), 1u);
    EXPECT_EQ(findAnimation(scene, "0"), 0u);
    EXPECT_TRUE(contains(sceneErrorOf([&] { findAnimation(scene, "walk"); }), "no animation is named 'walk'; the scene's animations: 0 'slide', 1 'turn'"));
    EXPECT_TRUE(contains(sceneErrorOf([&] { findAnimation(scene, "2"); }), "animation index 2 is out of range: the scene has 2 animations"));
    EXPECT_TRUE(contains(sceneErrorOf([&] { findAnimation(scene, "99999999999999"); }), "out of range"));
    EXPECT_TRUE(contains(sceneErrorOf([&] { findAnimation(Scene{}, "0"); }), "the scene has no animations"));
}

// World matrices are computed parents first without recursion: any depth.
TEST(PoseScene, AHundredThousandDeepHierarchyPoses) {
    constexpr size_t kDepth = 100000;
    Scene scene;
    scene.nodes.resize(kDepth);
    for (size_t n = 0; n < kDepth; ++n) {
        scene.nodes[n].translation = glm::vec3(0.0f, 0.0f, 0.5f);
        if (n > 0) scene.nodes[n].parent = int32_t(n - 1);
        if (n + 1 < kDepth) scene.nodes[n].children = {uint32_t(n + 1)};
    }
    Animation lift;
    lift.samplers.push_back(samplerOf(Interpolation::Step, {0.0f}, {0.0f, 3.0f, 0.5f}, 3));
    lift.channels.push_back(AnimationChannel{0, 0, AnimationPath::Translation});
    scene.animations.push_back(lift);
    poseScene(scene, 0.0f, 0);
    EXPECT_EQ(originOf(scene.nodes.back().world), glm::vec3(0.0f, 3.0f, 0.5f * kDepth));
}

// --- skinning and morphing: posedVertices -------------------------------------------------------

// One skinned vertex and the skin's two joints (nodes 0 and 1, roots).
Scene skinnedScene() {
    Scene scene;
    Mesh mesh;
    mesh.vertices.push_back(Vertex{glm::vec3(1, 2, 3), glm::normalize(glm::vec3(1, 1, 0)), glm::vec2(0), glm::vec4(1, 1, 0, -1)});
    mesh.vertices.push_back(Vertex{glm::vec3(0), glm::vec3(0), glm::vec2(0), glm::vec4(0, 0, 0, 1)});   // no normal, no tangent
    mesh.indices = {0, 1};
    mesh.topology = MeshTopology::Points;
    mesh.joints = {glm::u16vec4(0, 1, 0, 0), glm::u16vec4(1, 0, 0, 0)};
    mesh.weights = {glm::vec4(0.25f, 0.75f, 0, 0), glm::vec4(1, 0, 0, 0)};
    scene.meshes.push_back(mesh);
    scene.nodes.resize(2);
    scene.skins.push_back(Skin{"skin", {0, 1}, {glm::mat4(1.0f), glm::mat4(1.0f)}});
    Instance instance{0, glm::mat4(1.0f)};
    instance.skin = 0;
    scene.instances.push_back(instance);
    return scene;
}

TEST(PosedVertices, SkinningBlendsTheJointMatricesByWeight) {
    Scene scene = skinnedScene();
    scene.nodes[0].translation = glm::vec3(4, 0, 0);
    scene.nodes[1].scale = glm::vec3(2, 1, 1);   // non-uniform: normals need the inverse transpose
    scene.skins[0].inverseBindMatrices[1] = glm::translate(glm::mat4(1.0f), glm::vec3(0, -1, 0));
    poseScene(scene, 0.0f, std::nullopt);
    ASSERT_EQ(scene.instances[0].jointMatrices.size(), 2u);
    EXPECT_EQ(scene.instances[0].world, glm::mat4(1.0f));
    const std::vector<Vertex> posed = posedVertices(scene, scene.instances[0]);
    // Joint 0: translate (4, 0, 0); joint 1: scale (2, 1, 1) after translate (0, -1, 0).
    // M = 0.25 J0 + 0.75 J1 = [diag(1.75, 1, 1) | (1, -0.75, 0)]: (1, 2, 3) -> (2.75, 1.25, 3).
    EXPECT_NEAR(glm::length(posed[0].position - glm::vec3(2.75f, 1.25f, 3.0f)), 0.0f, 1e-6f);
    // Normal (1, 1, 0) by the inverse transpose diag(1/1.75, 1, 1): (0.5714, 1, 0), normalised.
    EXPECT_NEAR(glm::length(posed[0].normal - glm::normalize(glm::vec3(1.0f / 1.75f, 1.0f, 0.0f))), 0.0f, 1e-6f);
    // Tangent (1, 1, 0) by M itself: (1.75, 1, 0), normalised; w kept.
    EXPECT_NEAR(glm::length(glm::vec3(posed[0].tangent) - glm::normalize(glm::vec3(1.75f, 1.0f, 0.0f))), 0.0f, 1e-6f);
    EXPECT_EQ(posed[0].tangent.w, -1.0f);
    // The second vertex: all weight on joint 1; a zero normal and tangent stay zero.
    EXPECT_NEAR(glm::length(posed[1].position - glm::vec3(0, -1, 0)), 0.0f, 1e-6f);
    EXPECT_EQ(posed[1].normal, glm::vec3(0));
    EXPECT_EQ(posed[1].tangent, glm::vec4(0, 0, 0, 1));
}

TEST(PosedVertices, AMirroringJointKeepsNormalsFacingOut) {
    Scene scene = skinnedScene();
    scene.nodes[0].scale = scene.nodes[1].scale = glm::vec3(-1, 1, 1);   // both joints mirror X
    poseScene(scene, 0.0f, std::nullopt);
    const std::vector<Vertex> posed = posedVertices(scene, scene.instances[0]);
    // The inverse transpose of diag(-1, 1, 1) is itself: (1, 1, 0) -> (-1, 1, 0).
    EXPECT_NEAR(glm::length(posed[0].normal - glm::normalize(glm::vec3(-1, 1, 0))), 0.0f, 1e-6f);
}

TEST(PosedVertices, MorphTargetsAreAddedByWeightBeforeSkinning) {
    Scene scene = skinnedScene();
    Mesh& mesh = scene.meshes[0];
    MorphTarget up, out;
    up.positions = {glm::vec3(0, 1, 0), glm::vec3(0, 1, 0)};
    out.positions = {glm::vec3(2, 0, 0), glm::vec3(0)};
    out.normals = {glm::vec3(-1, -1, 1), glm::vec3(0)};   // the first normal turns to +Z at weight 1
    mesh.morphTargets = {up, out};
    mesh.morphWeights = {0.0f, 0.0f};
    scene.nodes[0].translation = scene.nodes[1].translation = glm::vec3(0, 0, 10);   // both joints: +10 Z
    poseScene(scene, 0.0f, std::nullopt);
    EXPECT_EQ(scene.instances[0].morphWeights, std::vector<float>({0.0f, 0.0f}));   // the mesh's defaults
    scene.instances[0].morphWeights = {0.5f, 1.0f};
    const std::vector<Vertex> posed = posedVertices(scene, scene.instances[0]);
    EXPECT_NEAR(glm::length(posed[0].position - glm::vec3(1 + 2, 2 + 0.5f, 3 + 10)), 0.0f, 1e-6f);
    EXPECT_NEAR(glm::length(posed[1].position - glm::vec3(0, 0.5f, 10)), 0.0f, 1e-6f);
    EXPECT_NEAR(glm::length(posed[0].normal - glm::normalize(glm::normalize(glm::vec3(1, 1, 0)) + glm::vec3(-1, -1, 1))), 0.0f, 1e-6f);
}

TEST(PosedVertices, AnUnposedRigidMeshComesBackUnchanged) {
    Scene scene = twoNodeScene();
    poseScene(scene, 0.0f, std::nullopt);
    const std::vector<Vertex> posed = posedVertices(scene, scene.instances[0]);
    ASSERT_EQ(posed.size(), 1u);
    EXPECT_EQ(posed[0].position, scene.meshes[0].vertices[0].position);   // world is not applied
    EXPECT_EQ(posed[0].normal, scene.meshes[0].vertices[0].normal);
}

TEST(PosedVertices, ValidateSceneChecksWhatThePosingNeeds) {
    Scene scene = skinnedScene();
    poseScene(scene, 0.0f, std::nullopt);
    EXPECT_NO_THROW(validateScene(scene));
    Scene tooFew = scene;
    tooFew.instances[0].jointMatrices.pop_back();
    EXPECT_TRUE(contains(sceneErrorOf([&] { validateScene(tooFew); }), "1 joint matrices but its skin 0 has 2 joints"));
    Scene pastTheSkin = scene;
    pastTheSkin.meshes[0].joints[1].x = 2;
    EXPECT_TRUE(contains(sceneErrorOf([&] { validateScene(pastTheSkin); }), "vertex 1 of mesh 0 uses joint 2, but skin 0 has 2 joints"));
    Scene noSkin = scene;
    noSkin.instances[0].skin = -1;
    EXPECT_TRUE(contains(sceneErrorOf([&] { validateScene(noSkin); }), "has no skin but its mesh 0 is skinned"));
    Scene badWeights = scene;
    badWeights.meshes[0].morphTargets.resize(1);
    EXPECT_TRUE(contains(sceneErrorOf([&] { validateScene(badWeights); }), "0 morph weights for 1 morph targets"));
}

}  // namespace
}  // namespace janus::renderer
