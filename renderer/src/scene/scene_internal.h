// Helpers shared by the scene sources (glTF loading, scene files, the built-in scene).
#pragma once

#include <span>
#include <string>
#include <string_view>
#include <vector>

#include <nlohmann/json.hpp>

#include "janus/renderer/scene.h"

namespace janus::renderer::detail {

// Fills Vertex::normal from the triangles: area-weighted average of the faces that share a
// vertex. Indexed meshes get smooth normals; unindexed ones (no shared vertices) get flat ones.
void generateNormals(Mesh& mesh);

// Fills Vertex::tangent from positions and the UV set `texCoord` (0: uv, 1: uv1; per-triangle
// dP/du, averaged per vertex), for normal-mapped meshes whose file has no tangents: the set the
// normal texture reads, as glTF relates tangents to the normal texture's UVs. w follows glTF:
// bitangent = cross(N, T) * w points towards decreasing v (up in the image).
void generateTangents(Mesh& mesh, uint32_t texCoord = 0);

// Places the camera so the bounding box of every instance fills the view, looking down -Z
// from slightly above. Used when neither the glTF nor the scene file has a camera.
void frameSceneBounds(Scene& scene);

// Loads the glTF part of a scene (.gltf / .glb). `hasCamera` tells whether it had a camera.
Scene loadGltf(const std::filesystem::path& path, bool& hasCamera, const SceneLoadOptions& options);
// The same for the bytes of such a file already in memory: `path` is where they would be (its
// extension picks .glb or .gltf, its folder anchors relative URIs, errors name it); nothing is
// read at `path` itself.
Scene loadGltfFromMemory(std::string_view bytes, const std::filesystem::path& path, bool& hasCamera, const SceneLoadOptions& options);

// Places a light (position, direction: down its local -Z) and a camera (position, target down
// its local -Z, up +Y) by a glTF node's world matrix; shared by the loader and poseScene.
void placeLight(Light& light, const glm::mat4& world);
void placeCamera(Camera& camera, const glm::mat4& world);

// Lighting added to scenes that bring none, so glTF sample models are not black.
Light defaultKeyLight();
// What is wrong with a light ("has a negative colour or intensity", ...), or nullptr when it can
// be rendered. One rule for validateScene (SceneError) and Renderer::setLights (RendererError).
const char* lightProblem(const Light& light);

// Geometry and material helpers for scenes built in code (default_scene.cpp).
Mesh makeQuad(int32_t material);                                   // 2x2 in XY, facing +Z
Mesh makeBox(int32_t material);                                    // -1..1 cube, faces outwards
Mesh makeSphere(int32_t material, uint32_t slices = 32, uint32_t stacks = 16);   // radius 1
int32_t addMaterial(Scene& scene, std::string name, glm::vec3 color, float metallic, float roughness, glm::vec3 emissive = {});
uint32_t addMesh(Scene& scene, Mesh mesh);

// Scene-file helpers (reflection_probe_scene.cpp): SceneError "<file>: <what>"; a 3-vector; a box
// given as {"min", "max"} or {"center", "size"}. `where` names the value in messages.
[[noreturn]] void fail(const std::filesystem::path& file, const std::string& what);
glm::vec3 readVec3(const std::filesystem::path& file, const nlohmann::json& value, const std::string& where);
Box readBox(const std::filesystem::path& file, const nlohmann::json& value, const std::string& where);

// Reflection probes (reflection_probe_scene.cpp): the scene file's "reflectionProbes" array;
// one probe per "ReflectionCubemap..." marker when the scene has none (influence and parallax
// box: the scene's bounds grown by 1%); validation (called by validateScene).
// World AABB of every instance (skinned and morphed ones as posed: posedVertices); an empty box when there is none.
Box sceneBounds(const Scene& scene);
// The world-space box of one instance as drawn: skinned and morphed meshes where the pose puts
// them (posedVertices), others as they are; none for an instance without vertices.
std::optional<Box> instanceBounds(const Scene& scene, const Instance& instance);
// Whether `instance` is drawn deformed (renderer/src/deform/): its mesh has vertices and morph
// targets, or joints and the instance a skin.
bool isDeformed(const Scene& scene, const Instance& instance);
std::vector<ReflectionProbe> parseReflectionProbes(const std::filesystem::path& file, const nlohmann::json& probes, const Scene& scene);
// The keys of one "reflectionProbes" entry; scene.cpp warns about any other (a misspelt key would
// otherwise change nothing unseen).
std::span<const std::string_view> reflectionProbeKeys();
void addProbesFromMarkers(Scene& scene);
void validateReflectionProbes(const Scene& scene);

// The irradiance volume (irradiance_volume_scene.cpp): the scene file's "irradianceVolume"; one
// over the scene's bounds for an "IrradianceVolume..." marker when the scene has none; validation.
IrradianceVolume parseIrradianceVolume(const std::filesystem::path& file, const nlohmann::json& volume, const Scene& scene);
std::span<const std::string_view> irradianceVolumeKeys();
void addIrradianceVolumeFromMarkers(Scene& scene);
void validateIrradianceVolume(const Scene& scene);

}  // namespace janus::renderer::detail
