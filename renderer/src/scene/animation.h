// Animation sampling and the checks poseScene relies on (renderer/src/scene/animation.cpp).
// Internal: the public entry points are poseScene and posedVertices in scene.h.
#pragma once

#include <glm/glm.hpp>
#include <glm/gtc/quaternion.hpp>

#include "janus/renderer/scene.h"

namespace janus::renderer::detail {

// The value of `sampler` at `time` seconds: sampler.components floats written to `out`. Times
// before the first keyframe give the first value, times after the last the last (glTF clamps).
// STEP holds a keyframe's value until the next; LINEAR interpolates linearly, rotations (`path`
// Rotation: xyzw quaternions) by spherical linear interpolation along the shortest arc;
// CUBICSPLINE is glTF's cubic Hermite spline, the tangents scaled by the keyframe interval.
// Rotations come back normalised. The sampler must be well formed (validateAnimationData).
void sampleAnimation(const AnimationSampler& sampler, AnimationPath path, float time, float* out);

// Spherical linear interpolation from `a` (t = 0) to `b` (t = 1) along the shortest arc: `b` is
// negated when the two are more than 180 degrees apart (dot < 0). Nearly parallel quaternions are
// interpolated linearly. The result is normalised.
glm::quat slerpShortest(glm::quat a, glm::quat b, float t);

// A node's local matrix: its `matrix` when it has one, else translation * rotation * scale.
glm::mat4 localMatrix(const Node& node, glm::vec3 translation, glm::quat rotation, glm::vec3 scale);

// Throws SceneError when the node hierarchy, skins, animations or the instances' node / skin /
// joint-matrix / morph-weight references are inconsistent: what poseScene and posedVertices
// need to never read out of bounds (also called by validateScene).
void validateAnimationData(const Scene& scene);

}  // namespace janus::renderer::detail
