// Scenes: glTF 2.0 content plus what glTF lacks (camera, environment, extra lights, quality),
// given by a small JSON scene file that references the glTF. See docs/SCENES.md.
#pragma once

#include <array>
#include <cstdint>
#include <filesystem>
#include <optional>
#include <stdexcept>
#include <string>
#include <string_view>
#include <vector>

#include <memory>

#include <glm/glm.hpp>
#include <glm/gtc/quaternion.hpp>
#include <nlohmann/json.hpp>

#include "janus/renderer/image.h"

namespace janus::renderer {

class SceneError : public std::runtime_error {
public:
    using std::runtime_error::runtime_error;
};

struct Vertex {
    glm::vec3 position;
    glm::vec3 normal;
    glm::vec2 uv;        // glTF TEXCOORD_0
    glm::vec4 tangent;   // xyz tangent, w handedness; zero when the mesh has none
    glm::vec2 uv1{0.0f}; // glTF TEXCOORD_1; zero when the mesh has none
    glm::vec4 color{1.0f};   // glTF COLOR_0 (linear RGBA, multiplies base colour and alpha); white when the mesh has none
    // Unused: pads a Vertex to five 16-byte texels, the unit the fallback mesh deformer writes
    // posed vertices in (docs/ARCHITECTURE.md, "Mesh deformation").
    glm::vec2 reserved{0.0f};
};

// A morph target (glTF primitive "targets"): displacements added to the base vertices, weighted
// by the instance's morph weights. Each list is empty (the target does not move that attribute)
// or has one entry per vertex. Tangent displacements move xyz; w is kept.
struct MorphTarget {
    std::vector<glm::vec3> positions, normals, tangents;
};
// The most morph targets one mesh may have; a file with more is a SceneError.
inline constexpr size_t kMaxMorphTargets = 64;
// The most joints one skin may have; a file with more is a SceneError.
inline constexpr size_t kMaxSkinJoints = 4096;

// What a mesh's indices list: glTF's strips, fans and loops are turned into these lists at load.
enum class MeshTopology { Triangles, Lines, Points };

struct Mesh {
    std::vector<Vertex> vertices;
    std::vector<uint32_t> indices;   // 3 per triangle, 2 per line, 1 per point
    int32_t material = -1;           // index into Scene::materials; -1 = default material
    MeshTopology topology = MeshTopology::Triangles;
    // Drawn unlit whatever its material says: points and lines without normals (glTF).
    bool unlit = false;
    // Skinning (glTF JOINTS_0/WEIGHTS_0, and _1 when present): per vertex the four strongest
    // influences, indices into the instance's skin joints, weights summing to 1. Both empty
    // when the mesh is not skinned, else one entry per vertex.
    std::vector<glm::u16vec4> joints;
    std::vector<glm::vec4> weights;
    // Morph targets (at most kMaxMorphTargets) and the mesh's default weights (glTF mesh.weights;
    // zeros when the file gives none), one per target.
    std::vector<MorphTarget> morphTargets;
    std::vector<float> morphWeights;
};

// How a texture is sampled (the glTF sampler of the texture that uses the image).
enum class TextureWrap { Repeat, MirroredRepeat, ClampToEdge };

struct TextureSampling {
    TextureWrap wrapU = TextureWrap::Repeat;
    TextureWrap wrapV = TextureWrap::Repeat;
    bool nearestMagnification = false;
    bool nearestMinification = false;
    bool nearestMip = false;
    bool mipmapped = true;     // false: minification reads mip 0 only (glTF NEAREST / LINEAR)

    bool operator==(const TextureSampling&) const = default;
};

// Decoded 8-bit RGBA texture (images from glTF, row 0 on top).
struct TextureImage {
    uint32_t width = 0, height = 0;
    std::vector<uint8_t> rgba;
    bool srgb = false;               // base colour and emissive are sRGB; data textures are not
    TextureSampling sampling;
    std::string name;
};

// glTF alphaMode. Mask discards fragments below alphaCutoff; Blend is drawn by the transparent
// pass, back to front, premultiplied alpha, casting no shadow (docs/LIGHTING.md, "Transparent
// surfaces").
enum class AlphaMode { Opaque, Mask, Blend };

// Where a material texture is sampled: which UV set (glTF texCoord) and the KHR_texture_transform
// applied to it: uv' = offset + R(rotation) * (scale * uv), R turning the UVs counter-clockwise as
// seen on the image (u right, v down), so the image appears turned clockwise (docs/SCENES.md).
struct TextureTransform {
    glm::vec2 offset{0.0f};
    float rotation = 0.0f;     // radians
    glm::vec2 scale{1.0f};
    uint32_t texCoord = 0;     // 0: Vertex::uv (TEXCOORD_0), 1: Vertex::uv1 (TEXCOORD_1)

    // translation * rotation * scale as KHR_texture_transform writes it: uv' = (matrix() * (uv, 1)).xy.
    glm::mat3 matrix() const;
    glm::vec2 apply(glm::vec2 uv) const { return glm::vec2(matrix() * glm::vec3(uv, 1.0f)); }
    // The UV set this transform reads, transformed.
    glm::vec2 uvOf(const Vertex& vertex) const { return apply(texCoord == 1 ? vertex.uv1 : vertex.uv); }
    bool operator==(const TextureTransform&) const = default;
};

struct Material {
    glm::vec4 baseColorFactor{1.0f};
    float metallicFactor = 1.0f;
    float roughnessFactor = 1.0f;
    glm::vec3 emissiveFactor{0.0f};
    int32_t baseColorTexture = -1;          // indices into Scene::textures
    int32_t metallicRoughnessTexture = -1;
    int32_t normalTexture = -1;
    int32_t occlusionTexture = -1;
    int32_t emissiveTexture = -1;
    float normalScale = 1.0f;               // glTF normalTexture.scale: multiplies the map's X and Y
    float occlusionStrength = 1.0f;         // glTF occlusionTexture.strength, in [0, 1]: 0 = no occlusion
    // Each texture's UV set and transform (identity on TEXCOORD_0 unless the glTF says otherwise).
    TextureTransform baseColorTransform;
    TextureTransform metallicRoughnessTransform;
    TextureTransform normalTransform;
    TextureTransform occlusionTransform;
    TextureTransform emissiveTransform;
    bool doubleSided = false;
    AlphaMode alphaMode = AlphaMode::Opaque;
    float alphaCutoff = 0.5f;               // Mask: fragments with alpha below it are discarded
    // KHR_materials_emissive_strength: multiplies emissiveFactor (which core glTF caps at 1); >= 0.
    float emissiveStrength = 1.0f;
    // KHR_materials_unlit: the surface shows its base colour (times vertex colour and texture),
    // lit by nothing, casting shadows as any other.
    bool unlit = false;
    // Dielectric specular (KHR_materials_ior, KHR_materials_specular factors): a non-metal reflects
    // F0 = min(((ior - 1) / (ior + 1))^2 * specularColorFactor, 1) * specularFactor at normal
    // incidence and F90 = specularFactor at grazing angles. The defaults give glTF's F0 = 0.04.
    float ior = 1.5f;                       // 0 (F0 = 1) or >= 1
    float specularFactor = 1.0f;            // in [0, 1]
    glm::vec3 specularColorFactor{1.0f};    // >= 0
    glm::vec3 dielectricF0() const;
    float dielectricF90() const { return specularFactor; }
    std::string name;

    // One texture reference: its glTF name ("baseColorTexture"...), index and UV set / transform.
    struct TextureSlot {
        const char* name;
        int32_t texture;
        const TextureTransform* transform;
    };
    // The five, in the order of forward_common.glsl's kTexture*: base colour, metallic-roughness,
    // normal, occlusion, emissive.
    std::array<TextureSlot, 5> textureSlots() const {
        return {{{"baseColorTexture", baseColorTexture, &baseColorTransform},
                 {"metallicRoughnessTexture", metallicRoughnessTexture, &metallicRoughnessTransform},
                 {"normalTexture", normalTexture, &normalTransform},
                 {"occlusionTexture", occlusionTexture, &occlusionTransform},
                 {"emissiveTexture", emissiveTexture, &emissiveTransform}}};
    }
};

// A mesh placed in the world (glTF node hierarchy flattened).
struct Instance {
    uint32_t mesh = 0;
    glm::mat4 world{1.0f};
    // 32 rendering layers: a local light lights this mesh only if (light & mesh layers) != 0.
    uint32_t renderingLayers = 1u;
    std::string nodeName;            // glTF node it came from (scene files address it by name)
    int32_t node = -1;               // index into Scene::nodes; -1 for instances made in code
    // Skinned instances (Mesh::joints not empty): index into Scene::skins, and per skin joint
    // the joint's world matrix times its inverse bind matrix at the posed time. A skinned vertex
    // is sum(weight_i * jointMatrices[joint_i]) * position, already in world space: `world` is
    // the identity for them (glTF ignores the transform of a skinned mesh's node).
    int32_t skin = -1;
    std::vector<glm::mat4> jointMatrices;
    // Current morph weights, one per Mesh::morphTargets (the node's or mesh's, then animated).
    std::vector<float> morphWeights;
};

// The glTF node hierarchy, kept so that animations can move it; Instance::world and
// Instance::jointMatrices are derived from it by poseScene.
struct Node {
    std::string name;
    int32_t parent = -1;
    std::vector<uint32_t> children;
    // Local transform: translation * rotation * scale (a glTF "matrix" node is decomposed; glTF
    // does not animate such nodes). These are the rest (file) values: poseScene does not change
    // them, it samples the animation over them, so posing at another time starts from the rest pose.
    glm::vec3 translation{0.0f};
    glm::quat rotation{1.0f, 0.0f, 0.0f, 0.0f};
    glm::vec3 scale{1.0f};
    // A glTF "matrix" node's matrix as the file gives it: its local transform (exact, shear
    // included), of which translation/rotation/scale above are the decomposition. Animations
    // may not target such nodes (SceneError at load, as glTF requires).
    std::optional<glm::mat4> matrix;
    // glTF node.weights: the morph weights of this node's mesh instances (the mesh's default
    // weights when empty), before any animation.
    std::vector<float> weights;
    glm::mat4 world{1.0f};           // at the posed time
};

enum class AnimationPath { Translation, Rotation, Scale, Weights };
enum class Interpolation { Step, Linear, CubicSpline };

// One glTF animation sampler: keyframe times (strictly increasing, seconds) and values,
// `components` floats per value (3 translation/scale, 4 rotation xyzw, one per morph target for
// weights); CUBICSPLINE stores (in-tangent, value, out-tangent) per keyframe.
struct AnimationSampler {
    std::vector<float> times;
    std::vector<float> values;
    uint32_t components = 0;
    Interpolation interpolation = Interpolation::Linear;
};
struct AnimationChannel {
    uint32_t sampler = 0;            // index into Animation::samplers
    uint32_t node = 0;               // index into Scene::nodes
    AnimationPath path = AnimationPath::Translation;
};
struct Animation {
    std::string name;
    std::vector<AnimationSampler> samplers;
    std::vector<AnimationChannel> channels;
    float duration = 0.0f;           // the last keyframe time of any sampler
};

struct Skin {
    std::string name;
    std::vector<uint32_t> joints;                 // indices into Scene::nodes
    std::vector<glm::mat4> inverseBindMatrices;   // one per joint (identity when the file gives none)
};

enum class LightType { Directional, Point, Spot };

struct Light {
    LightType type = LightType::Directional;
    glm::vec3 color{1.0f};
    float intensity = 1.0f;          // lux for directional, candela for point/spot (glTF units)
    glm::vec3 position{0.0f};
    glm::vec3 direction{0.0f, -1.0f, 0.0f};   // direction the light travels
    std::optional<float> range;
    // Spot cone half-angles in radians: 0 <= inner <= outer <= pi/2 (validateScene; equal: a hard edge).
    float innerConeAngle = 0.0f;
    float outerConeAngle = 0.7853982f;
    // Meshes this light lights: (renderingLayers & Instance::renderingLayers) != 0.
    uint32_t renderingLayers = 1u;
    // The glTF node it came from (index into Scene::nodes): poseScene moves it with that node's
    // world matrix. -1 for lights of scene files and scenes made in code (never moved).
    int32_t node = -1;
};

enum class CameraProjection : uint8_t {
    Perspective,    // fovYRadians; 0 < near < far
    Orthographic,   // orthographicHalfHeight; 0 <= near < far
};

struct Camera {
    glm::vec3 position{0.0f, 0.0f, 3.0f};
    glm::vec3 target{0.0f};
    glm::vec3 up{0.0f, 1.0f, 0.0f};
    CameraProjection projection = CameraProjection::Perspective;
    float fovYRadians = 0.8726646f;   // 50 degrees; perspective only
    // Orthographic only: half the view's height in world units (glTF's ymag). The width follows
    // from the image's aspect ratio, as a perspective camera's does (glTF's xmag is not used).
    float orthographicHalfHeight = 1.0f;
    float nearPlane = 0.05f;
    float farPlane = 100.0f;
    // The glTF node of a glTF camera (index into Scene::nodes): poseScene moves the camera with
    // that node. -1 when a scene file gives the camera or it frames the scene (never moved).
    int32_t node = -1;
};

struct Environment {
    glm::vec3 ambientColor{0.03f};    // uniform ambient radiance where no environment map lights the scene
    float exposure = 1.0f;
    // An equirectangular sky (.hdr Radiance RGBE or .exr), absolute or relative to the working
    // directory (scene files resolve theirs relative to themselves). Empty: no sky; the ambient
    // colour lights the scene. With one, it replaces the ambient colour: image-based diffuse (SH)
    // and specular (GGX-prefiltered) light, and the background (docs/IBL.md).
    std::filesystem::path map;
    // The same, already in memory (a procedural sky; the built-in probes scene's): used when
    // `map` is empty. Linear radiance, at least 2x1 texels, finite and >= 0.
    std::shared_ptr<const ImageRGBAF> image;
    float intensity = 1.0f;           // multiplies the map's radiance
};

// Named empty nodes from glTF (e.g. the cornell box's "IrradianceVolume", "ReflectionCubemap"),
// kept for features that place probes from them.
struct Marker {
    std::string name;
    glm::mat4 world{1.0f};
    int32_t node = -1;               // the glTF node (Scene::nodes), moved by poseScene; -1: not from glTF
};

// An axis-aligned box in world space.
struct Box {
    glm::vec3 min{0.0f}, max{0.0f};
    glm::vec3 center() const { return (min + max) * 0.5f; }
    glm::vec3 size() const { return max - min; }
    bool operator==(const Box&) const = default;
};

// When a reflection probe captures its surroundings (docs/PROBES.md).
enum class ProbeUpdate {
    Once,        // the first frames after the renderer is made, then never again
    EveryFrame,  // a new update starts as soon as the last one is shown
    OnRequest,   // when Renderer::requestProbeUpdate asks (the first update, too)
};
// How one update is spread over frames. Whatever the mode, shading sees a probe's new contents
// only when every face and mip of the update is done.
enum class ProbeTimeSlicing {
    None,               // capture, mips and prefilter in one frame
    AllFacesThenMips,   // 3 frames: the six faces; the first part of the prefiltered mips; the rest
    IndividualFaces,    // 8 frames: one face per frame, then the mips over two frames
};
const char* toString(ProbeUpdate update);             // "once", "every-frame", "on-request"
const char* toString(ProbeTimeSlicing slicing);       // "none", "all-faces-then-mips", "individual-faces"

inline constexpr size_t kMaxSceneReflectionProbes = 64;

// A realtime reflection probe: a cube capture of the scene at `position`, GGX-prefiltered, that
// gives glossy reflections to the surfaces inside its influence box (docs/PROBES.md).
struct ReflectionProbe {
    std::string name;
    glm::vec3 position{0.0f};
    // Surfaces inside this box use the probe; the weight falls linearly to 0 over the last
    // `blendDistance` inside each face, so overlapping probes blend (smaller boxes in front).
    Box influence{glm::vec3(-1.0f), glm::vec3(1.0f)};
    float blendDistance = 0.25f;
    // Box projection (parallax correction): reflections are looked up where the reflected ray
    // leaves this box, as if the room were this box. Empty: the probe is at infinity.
    std::optional<Box> parallax;
    uint32_t resolution = 128;       // face size of mip 0: a power of two in [8, 1024]
    float nearPlane = 0.05f, farPlane = 100.0f;
    ProbeUpdate update = ProbeUpdate::Once;
    ProbeTimeSlicing timeSlicing = ProbeTimeSlicing::None;
    // The capture's passes: the main light's shadow map (left out when false) and the meshes it
    // sees (rendering layers).
    bool shadows = true;
    uint32_t shadowMapSize = 0;      // 0 = the renderer's; else a power of two in [16, 8192]
    uint32_t renderingLayers = ~0u;
    // The prefilter (docs/PROBES.md, docs/IBL.md): GGX samples of mip 1, 2, ... (the last entry
    // repeats; empty = the renderer's default table), each in [1, 1024]; and the bright-texel split's
    // capacity (0 = off: 36 draws | 6 dispatches per update; on: a sun the capture sees is added
    // exactly instead of ghosting, for 7 draws | 2 dispatches more), at most 1023.
    std::vector<uint32_t> samplesPerMip;
    uint32_t brightTexels = 0;
    // Samples per pixel of the capture (1 = off, 2, 4, 8 or 16 where the device allows the count
    // for RGBA16F and D32F render targets; 4 is allowed everywhere): each face is shaded into
    // multisampled targets and resolved into the capture cube, so the edges a mirror-like
    // surface reflects (mip 0) lose their stairs. Alpha-masked materials get alpha to coverage as
    // in the main view (RenderSettings::alphaToCoverage). RenderSettings::probeMsaaSamples
    // overrides it for every probe.
    uint32_t msaaSamples = 1;
    // Whether the capture's surfaces reflect the probes as shading shows them now (every probe's
    // last complete update, its own included) instead of the sky alone: a second bounce of glossy
    // light, so a mirror in a room captures the room, not the sky behind it. It stays bounded over
    // updates (a reflection passes on at most what reaches it); a probe updated once sees
    // only the probes shown before its update (docs/PROBES.md, "Probes that see probes").
    bool seesProbes = false;
};

// Probe-based diffuse GI (docs/GI.md): a grid of irradiance probes over `bounds`. A bake renders a
// G-buffer cube at each probe and keeps `surfelsPerProbe` surface samples (surfels); surfels are
// grouped into bricks (cells of `brickSize` metres, split by normal direction), and a probe keeps
// per brick it sees the brick's SH transfer to it. A relight lights the bricks (direct light, the
// main light's shadow, emission, the sky for sky samples, and the last relight's irradiance for
// further bounces) and sums each probe's SH from its bricks; forward shading reads the probes'
// irradiance instead of the sky's or the ambient colour's diffuse term.
struct IrradianceVolume {
    std::string name = "irradiance volume";
    Box bounds{glm::vec3(-1.0f), glm::vec3(1.0f)};
    // Probes per axis, at the centres of the grid's cells (a 1x1x1 volume has one probe at the
    // centre); each in [1, 64], at most 4096 probes in all.
    glm::uvec3 probeCounts{4, 4, 4};
    uint32_t surfelsPerProbe = 256;    // stratified directions per probe, in [16, 4096]
    float brickSize = 0.5f;            // metres, > 0
    bool bricks = true;                // false: the per-surfel path (each surfel its own brick), for comparison
    // A brick's radiance is the mean over at most this many of its surfels (picked evenly): the
    // relight lights a brick in bounded time however many probes see it. In [1, 4096].
    uint32_t maxSurfelsPerBrick = 16;
    uint32_t bounces = 4;              // light bounces (1 = direct light reflected once), in [1, 8]
    uint32_t shOrder = 2;              // 1 (L1, 4 coefficients) or 2 (L2, 9)
    uint32_t probesPerFrame = 0;       // relit per frame, nearest to the camera first; 0 = all
    // false: the compute path's SH pass sums each probe in one invocation, serially, instead of a
    // workgroup's shared-memory reduction (for comparison, as `bricks`; the fallback path ignores it).
    bool parallelReduction = true;
    float normalBias = 0.1f;           // shading looks the volume up this far along the normal (metres, >= 0)
    // A probe with more than this fraction of its surface samples on back faces is inside
    // geometry: shading gives it no weight. In (0, 1].
    float invalidBackFaceFraction = 0.5f;
    // A probe found inside geometry is moved out at bake time, through the nearest inside face,
    // at most 45 % of a cell from its grid position, and kept there when it is valid then (it keeps
    // its grid weight in shading; docs/GI.md, "Relocation"). false: it stays, invalid.
    bool relocateProbes = true;
    // Shading weighs each probe by how likely it sees the point (DDGI's Chebyshev test on the
    // distances the probe saw at bake time; docs/GI.md, "Visibility"), so light does not leak
    // through walls from probes on their other side. false: the plain trilinear weights.
    bool visibility = true;
    float nearPlane = 0.01f, farPlane = 100.0f;   // of the bake's G-buffer cubes
};
inline constexpr uint32_t kMaxIrradianceProbes = 4096;

struct Scene {
    std::string name;
    std::vector<Mesh> meshes;
    std::vector<Material> materials;
    std::vector<TextureImage> textures;
    std::vector<Instance> instances;
    // The glTF node hierarchy, skins and animations (empty for scenes made in code).
    std::vector<Node> nodes;
    std::vector<Skin> skins;
    std::vector<Animation> animations;
    // What the scene is posed at (set by poseScene): the animation (none: the rest pose) and the
    // time in seconds. Loading poses a glTF at t = 0 of animation 0 when it has one, a scene file
    // at its "time" and "animation".
    std::optional<size_t> posedAnimation;
    float posedTime = 0.0f;
    std::vector<Light> lights;
    std::vector<Marker> markers;
    // From the scene file's "reflectionProbes", or one per glTF node named "ReflectionCubemap..."
    // (covering the scene's bounds) when the scene file gives none.
    std::vector<ReflectionProbe> reflectionProbes;
    // From the scene file's "irradianceVolume", or one over the scene's bounds for a glTF node
    // named "IrradianceVolume..." when the file gives none. Empty: no GI, no GI work.
    std::optional<IrradianceVolume> irradianceVolume;
    Camera camera;
    Environment environment;
    // What the loader ignored or changed and the user should know (a glTF extension Janus does
    // not implement, ...): one line each, without a "warning:" prefix. loadScene also prints them.
    std::vector<std::string> warnings;
    // Free-form settings from the scene file's "quality" object, kept for features that read
    // them (probe counts, light-grid sizes...); the skeleton renderer reads none.
    nlohmann::json quality = nlohmann::json::object();
};

// How loadScene treats what a glTF references (docs/SCENES.md, "Files a glTF may read").
struct SceneLoadOptions {
    // A glTF reads its buffers and images from its own folder and the folders below it: a URI
    // that leaves that folder ("../../etc/passwd") or is an absolute path is a SceneError naming
    // the URI. True allows both (for assets the user trusts). A scene file's own "gltf" and
    // environment "map" are not subject to the rule: the user wrote them.
    bool allowPathsOutsideSceneFolder = false;
    // Which glTF scene to load (index into the file's "scenes"); none: the file's "scene", else 0.
    std::optional<uint32_t> scene;
    // Which glTF camera to look through (index into the file's "cameras"), placed by the first
    // node of the loaded scene that uses it; none: the first camera met in the node walk
    // (perspective or orthographic), else a camera that frames the scene.
    std::optional<uint32_t> camera;
};

// Loads a .gltf / .glb file or a .json scene file. Throws SceneError naming the file and the
// problem (missing file, malformed glTF, missing texture, NaN in a transform or colour, a URI
// outside the glTF's folder, an image too large, ...).
Scene loadScene(const std::filesystem::path& path, const SceneLoadOptions& options = {});

// loadScene for a file's bytes already in memory (for loaders that get scenes from elsewhere, and
// for fuzzing without a file per input): `bytes` are loaded as if they were the file at `path`,
// whose extension picks the format and whose folder is where the buffers, images and glTF they
// reference are looked up (by the same rules). Nothing is read at `path` itself; errors name it.
Scene loadSceneFromMemory(std::string_view bytes, const std::filesystem::path& path, const SceneLoadOptions& options = {});

// Poses `scene` at `time` seconds (>= 0) of Scene::animations[animation] (none: the nodes keep
// their rest transforms): samples every channel (times past either end hold the end value),
// then updates every Node::world, Instance::world, Instance::jointMatrices and
// Instance::morphWeights, the lights, markers and camera that came from glTF nodes (their `node`),
// and Scene::posedAnimation / posedTime. Each call starts from the rest pose (Node's TRS and
// weights), so posing at any time in any order gives the same result. Loading poses the scene at
// t = 0 of animation 0 when it has one, as glTF viewers show it. Throws SceneError for a NaN or
// negative time, a bad index, or an inconsistent hierarchy, skin or animation (a scene made in code).
// Sampling (docs/SCENES.md, "Animations"): STEP holds each keyframe; LINEAR interpolates, rotations
// by slerp along the shortest arc; CUBICSPLINE is glTF's Hermite spline (tangents times the keyframe
// interval); rotations are normalised.
void poseScene(Scene& scene, float time, std::optional<size_t> animation);

// The index of the animation `nameOrIndex` names: an animation of that name (the first, when
// several share it), else a decimal index. Throws SceneError naming the problem (no animations,
// no such name, index out of range) and listing the scene's animations.
size_t findAnimation(const Scene& scene, std::string_view nameOrIndex);

// The CPU reference of skinning and morphing: `instance`'s mesh vertices with the morph targets
// added (weighted by Instance::morphWeights) and then skinned (Instance::jointMatrices), before
// Instance::world is applied (which is the identity for skinned instances). Normals and tangents
// are renormalised. The GPU paths must agree with it. Exactly:
//   morph:  p += sum_t w_t dp_t, n += sum_t w_t dn_t, tangent.xyz += sum_t w_t dt_t (w kept);
//   skin:   M = sum_i weights[i] * jointMatrices[joints[i]] (the four influences), p' = M (p, 1),
//           tangent.xyz' = M3 tangent.xyz with M3 M's upper 3x3, and n' = the inverse transpose of
//           M3 times n, computed as cofactor(M3) n * sign(det M3) (the same direction, also defined
//           for a singular M3; for rigid joints it is M3 n);
//   then n and tangent.xyz are normalised, a zero vector staying zero.
// A mesh with no non-zero morph weight and no skin comes back unchanged.
std::vector<Vertex> posedVertices(const Scene& scene, const Instance& instance);

// The built-in default scene: a closed room with coloured walls and objects of varied
// roughness and metalness, lit by a directional light. `janus render` with no scene uses it.
Scene defaultScene();

// A generated many-lights scene for Forward+ benchmarks and tests: a closed room (floor,
// walls, ceiling) with pillars and boxes of varied height and roughness, so depth varies a lot
// across screen tiles, lit by one dim directional light and `lightCount` coloured point and spot
// lights scattered through the volume. The same options always give the same scene.
struct ManyLightsOptions {
    uint32_t lightCount = 128;
    uint32_t seed = 1;
    float spotFraction = 0.3f;     // share of the local lights that are spots
    // Each light's range is this fraction of the room's width (so a light covers a modest part
    // of the room); 0 leaves the range unset, so the renderer derives it from intensityCutoff.
    float rangeFraction = 0.18f;
    float intensity = 1.5f;        // candela of each local light
};
Scene manyLightsScene(const ManyLightsOptions& options = {});

// The built-in reflection-probe scene (`janus render probes`): an open alcove with red and green
// walls on a glossy ground, chrome, gold and blue spheres, a sun and a procedural sky, and two
// overlapping probes: "left" (64^2, every frame, all faces then mips over 3 frames) and "right"
// (128^2, once, in one frame). The ground in front of the alcove is outside both: sky only.
Scene probesScene();

// The built-in probe-GI scene (`janus render gi-rooms`): two rooms under one roof, a wall with a
// doorway between them, a glowing panel in the left room as the only light (no lamp, no ambient
// light), and an 8 x 2 x 3 irradiance volume whose probes stand either side of the wall
// (docs/GI.md, "Visibility": what leaks through the wall without the visibility test).
Scene giRoomsScene();

// Throws SceneError when the scene holds NaN/Inf or out-of-range values (checked by loadScene
// and by the Renderer for scenes built in code). A light with range <= 0 is valid: it lights
// nothing (the renderer skips it).
void validateScene(const Scene& scene);

// Why a point or spot light lights nothing ("its range is <= 0", "its intensity is <= 0", "its
// colour is black"), or nullptr when it lights something. The renderer skips such lights
// (PackedLights::skipped counts them); loadScene names each in Scene::warnings with its file and
// its place there (a scene file's lights[i], a glTF light and node).
const char* darkLightReason(const Light& light);

}  // namespace janus::renderer
