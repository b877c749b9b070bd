// loadScene (glTF or JSON scene file), validateScene and the geometry helpers they share.
// The scene-file format is documented in docs/SCENES.md.
#include <algorithm>
#include <cctype>
#include <cmath>
#include <fstream>
#include <iterator>
#include <limits>

#include <fmt/format.h>
#include <glm/gtc/matrix_transform.hpp>
#include <glm/gtc/type_ptr.hpp>
#include <nlohmann/json.hpp>

#include "animation.h"
#include "forward/lighting_settings.h"
#include "msaa/msaa_settings.h"
#include "janus/renderer/settings.h"
#include "scene_internal.h"

namespace janus::renderer {

namespace {
// The largest finite half-float: colours above it would turn the RGBA16F targets to Inf.
constexpr float kMaxColorValue = 65504.0f;
}  // namespace

glm::mat3 TextureTransform::matrix() const {
    const float c = std::cos(rotation), s = std::sin(rotation);
    // The UVs turn counter-clockwise as seen on the image (v grows downwards), so the image turns
    // clockwise, as the extension's text and its TextureTransformTest model say: u' = c u + s v,
    // v' = -s u + c v. The extension's GLSL sample, mat3(c, s, 0, -s, c, 0, 0, 0, 1), gives that
    // only when read row by row; GLSL's column-major reading turns the other way (the model's red
    // marker), so glm's columns here are its rows.
    const glm::mat3 translation(1.0f, 0.0f, 0.0f, 0.0f, 1.0f, 0.0f, offset.x, offset.y, 1.0f);
    const glm::mat3 turn(c, -s, 0.0f, s, c, 0.0f, 0.0f, 0.0f, 1.0f);
    const glm::mat3 scaling(scale.x, 0.0f, 0.0f, 0.0f, scale.y, 0.0f, 0.0f, 0.0f, 1.0f);
    return translation * turn * scaling;
}

glm::vec3 Material::dielectricF0() const {
    // In double, so the default ior 1.5 gives float(0.04), the value glTF's core model names.
    const double reflectance = (double(ior) - 1.0) / (double(ior) + 1.0);   // ior 0: -1, F0 1
    return glm::vec3(glm::min(glm::dvec3(reflectance * reflectance) * glm::dvec3(specularColorFactor), glm::dvec3(1.0)) *
                     double(specularFactor));
}

namespace detail {

void generateNormals(Mesh& mesh) {
    for (Vertex& v : mesh.vertices) v.normal = glm::vec3(0.0f);
    for (size_t i = 0; i + 2 < mesh.indices.size(); i += 3) {
        Vertex& a = mesh.vertices[mesh.indices[i]];
        Vertex& b = mesh.vertices[mesh.indices[i + 1]];
        Vertex& c = mesh.vertices[mesh.indices[i + 2]];
        // Not normalised: the cross product's length weights each face by its area.
        const glm::vec3 face = glm::cross(b.position - a.position, c.position - a.position);
        a.normal += face;
        b.normal += face;
        c.normal += face;
    }
    for (Vertex& v : mesh.vertices) {
        const float length = glm::length(v.normal);
        v.normal = length > 0.0f && std::isfinite(length) ? v.normal / length : glm::vec3(0.0f, 1.0f, 0.0f);
    }
}

void generateTangents(Mesh& mesh, uint32_t texCoord) {
    auto uvOf = [texCoord](const Vertex& v) { return texCoord == 1 ? v.uv1 : v.uv; };
    std::vector<glm::vec3> alongU(mesh.vertices.size(), glm::vec3(0.0f)), alongV(mesh.vertices.size(), glm::vec3(0.0f));
    for (size_t i = 0; i + 2 < mesh.indices.size(); i += 3) {
        const uint32_t ia = mesh.indices[i], ib = mesh.indices[i + 1], ic = mesh.indices[i + 2];
        const Vertex &a = mesh.vertices[ia], &b = mesh.vertices[ib], &c = mesh.vertices[ic];
        const glm::vec3 e1 = b.position - a.position, e2 = c.position - a.position;
        const glm::vec2 d1 = uvOf(b) - uvOf(a), d2 = uvOf(c) - uvOf(a);
        const float det = d1.x * d2.y - d2.x * d1.y;
        if (std::abs(det) < 1e-12f) continue;   // no uv area: says nothing about the tangent
        const glm::vec3 dPdu = (e1 * d2.y - e2 * d1.y) / det;
        const glm::vec3 dPdv = (e2 * d1.x - e1 * d2.x) / det;
        for (uint32_t v : {ia, ib, ic}) {
            alongU[v] += dPdu;
            alongV[v] += dPdv;
        }
    }
    for (size_t v = 0; v < mesh.vertices.size(); ++v) {
        Vertex& vertex = mesh.vertices[v];
        glm::vec3 t = alongU[v] - vertex.normal * glm::dot(vertex.normal, alongU[v]);
        if (glm::length(t) < 1e-8f || !std::isfinite(glm::length(t))) {
            // Any direction perpendicular to the normal keeps the shading frame valid.
            t = glm::cross(vertex.normal, std::abs(vertex.normal.x) < 0.9f ? glm::vec3(1, 0, 0) : glm::vec3(0, 1, 0));
        }
        t = glm::normalize(t);
        // glTF's v grows downwards in the image, so the bitangent (image up) opposes dP/dv.
        const float w = glm::dot(glm::cross(vertex.normal, t), alongV[v]) > 0.0f ? -1.0f : 1.0f;
        vertex.tangent = glm::vec4(t, w);
    }
}

void frameSceneBounds(Scene& scene) {
    const Box bounds = sceneBounds(scene);
    if (bounds == Box{}) return;   // nothing to frame: keep the default camera
    const glm::vec3 lo = bounds.min, hi = bounds.max;
    const glm::vec3 center = (lo + hi) * 0.5f;
    const float radius = std::max(glm::length(hi - lo) * 0.5f, 1e-3f);
    Camera& camera = scene.camera;
    const float distance = radius / std::sin(camera.fovYRadians * 0.5f);
    if (!std::isfinite(center.x + center.y + center.z) || !std::isfinite(distance * 2.0f + radius * 2.0f))
        throw SceneError(fmt::format("the scene is too large to frame with a camera: its bounds ({}, {}, {}) to ({}, {}, {}) overflow "
                                     "float math; scale its nodes down, or give it a camera",
                                     lo.x, lo.y, lo.z, hi.x, hi.y, hi.z));
    // A little above the centre so floors and tops read as such.
    const glm::vec3 direction = glm::normalize(glm::vec3(0.0f, 0.25f, 1.0f));
    camera.target = center;
    camera.position = center + direction * distance;
    camera.up = glm::vec3(0.0f, 1.0f, 0.0f);
    camera.nearPlane = std::max(distance - radius, distance * 0.01f) * 0.5f;
    camera.farPlane = (distance + radius) * 2.0f;
}

Light defaultKeyLight() {
    Light light;
    light.type = LightType::Directional;
    light.color = glm::vec3(1.0f, 0.97f, 0.92f);
    light.intensity = 3.0f;
    light.direction = glm::normalize(glm::vec3(-0.4f, -1.0f, -0.6f));
    return light;
}

}  // namespace detail

namespace {

using nlohmann::json;

[[noreturn]] void fail(const std::filesystem::path& file, const std::string& what) {
    throw SceneError(fmt::format("{}: {}", file.string(), what));
}

float number(const std::filesystem::path& file, const json& object, const char* key, float fallback) {
    if (!object.contains(key)) return fallback;
    const json& value = object.at(key);
    if (!value.is_number()) fail(file, fmt::format("\"{}\" must be a number, got {}", key, value.dump()));
    return value.get<float>();
}

glm::vec3 vec3(const std::filesystem::path& file, const json& object, const char* key, glm::vec3 fallback) {
    if (!object.contains(key)) return fallback;
    const json& value = object.at(key);
    if (!value.is_array() || value.size() != 3 || !value[0].is_number() || !value[1].is_number() || !value[2].is_number())
        fail(file, fmt::format("\"{}\" must be an array of 3 numbers, got {}", key, value.dump()));
    return glm::vec3(value[0].get<float>(), value[1].get<float>(), value[2].get<float>());
}

// A 32-bit rendering-layer mask: an integer in [0, 2^32).
uint32_t layerMask(const std::filesystem::path& file, const json& value, const std::string& where) {
    if (!value.is_number_integer() || value.get<int64_t>() < 0 || value.get<int64_t>() > int64_t(UINT32_MAX))
        fail(file, fmt::format("{} must be an integer layer mask in [0, 4294967295], got {}", where, value.dump()));
    return uint32_t(value.get<int64_t>());
}

const json& objectAt(const std::filesystem::path& file, const json& parent, const char* key) {
    const json& value = parent.at(key);
    if (!value.is_object()) fail(file, fmt::format("\"{}\" must be an object", key));
    return value;
}

// Why `map` cannot be an environment map, or "" when it can: the extension must be .hdr or .exr
// (any case) and the file must exist. Shared by the scene-file loader and validateScene.
std::string environmentMapProblem(const std::filesystem::path& map) {
    const std::string extension = lowerCaseExtension(map);
    if (extension != ".hdr" && extension != ".exr")
        return fmt::format("environment map '{}' is not a supported sky; use an equirectangular .hdr (Radiance RGBE) or .exr image",
                           map.string());
    std::error_code ec;
    if (!std::filesystem::exists(map, ec)) return fmt::format("environment map '{}' does not exist", map.string());
    if (std::filesystem::is_directory(map, ec)) return fmt::format("environment map '{}' is a directory, not an image", map.string());
    if (!std::filesystem::is_regular_file(map, ec))
        return fmt::format("environment map '{}' is not a regular file (a FIFO or device); give an image file", map.string());
    return {};
}

// Edits (insertions, deletions, substitutions) between two keys, case ignored: how far a typo is.
size_t editDistance(std::string_view a, std::string_view b) {
    std::vector<size_t> row(b.size() + 1);
    for (size_t j = 0; j <= b.size(); ++j) row[j] = j;
    for (size_t i = 1; i <= a.size(); ++i) {
        size_t diagonal = row[0];
        row[0] = i;
        for (size_t j = 1; j <= b.size(); ++j) {
            const size_t above = row[j];
            const bool same = std::tolower(static_cast<unsigned char>(a[i - 1])) == std::tolower(static_cast<unsigned char>(b[j - 1]));
            row[j] = std::min({row[j] + 1, row[j - 1] + 1, diagonal + (same ? 0 : 1)});
            diagonal = above;
        }
    }
    return row[b.size()];
}

// The keys each object of a scene file may have (docs/SCENES.md); the probes' and the volume's
// live with their parsers.
constexpr std::string_view kSceneFileKeys[] = {"gltf",       "name",         "time",    "animation",        "camera",
                                               "environment", "lights",      "meshLayers", "defaultLight",   "markers",
                                               "reflectionProbes", "irradianceVolume", "quality"};
constexpr std::string_view kCameraKeys[] = {"type", "position", "target", "up", "fovYDegrees", "ymag", "near", "far"};
constexpr std::string_view kEnvironmentKeys[] = {"ambientColor", "exposure", "intensity", "map"};
constexpr std::string_view kLightKeys[] = {"type",     "color",           "intensity",        "position", "direction",
                                           "range",    "innerConeDegrees", "outerConeDegrees", "layers"};
constexpr std::string_view kMarkerKeys[] = {"name", "position"};

// Every key of the scene file that Janus does not read, object by object (all of them checked for
// their types by then), as warnings.
void warnUnknownSceneFileKeys(const std::filesystem::path& file, const json& root, std::vector<std::string>& warnings) {
    // A key not in `known` changes nothing: a warning, naming the key Janus reads that it most
    // likely meant (at most a quarter of its letters off, at least one), the closest.
    auto check = [&](const json& object, const std::string& where, std::span<const std::string_view> known,
                     std::string_view consequence = "it changes nothing") {
        if (!object.is_object()) return;
        for (const auto& [key, value] : object.items()) {
            if (std::find(known.begin(), known.end(), key) != known.end()) continue;
            std::string_view closest;
            size_t best = std::max<size_t>(1, key.size() / 4) + 1;
            for (std::string_view candidate : known)
                if (const size_t distance = editDistance(key, candidate); distance < best) best = distance, closest = candidate;
            warnings.push_back(fmt::format("{}: {} has a key Janus does not read, \"{}\"{}; {}", file.string(), where, key,
                                           closest.empty() ? std::string() : fmt::format(" (did you mean \"{}\"?)", closest),
                                           consequence));
        }
    };
    check(root, "the scene file", kSceneFileKeys);
    if (root.contains("camera")) check(root["camera"], "\"camera\"", kCameraKeys);
    if (root.contains("environment")) check(root["environment"], "\"environment\"", kEnvironmentKeys);
    auto checkEach = [&](const char* array, std::span<const std::string_view> known) {
        if (!root.contains(array) || !root[array].is_array()) return;
        for (size_t i = 0; i < root[array].size(); ++i) check(root[array][i], fmt::format("{}[{}]", array, i), known);
    };
    checkEach("lights", kLightKeys);
    checkEach("markers", kMarkerKeys);
    checkEach("reflectionProbes", detail::reflectionProbeKeys());
    if (root.contains("irradianceVolume")) check(root["irradianceVolume"], "\"irradianceVolume\"", detail::irradianceVolumeKeys());
    if (root.contains("quality"))
        check(root["quality"], "\"quality\"", kQualityKeys, "it stays in Scene::quality for code of your own");
}

Light parseLight(const std::filesystem::path& file, const json& j, size_t index) {
    if (!j.is_object()) fail(file, fmt::format("lights[{}] must be an object", index));
    Light light;
    if (j.contains("type") && !j["type"].is_string())
        fail(file, fmt::format("lights[{}].type must be a string (directional, point or spot), got {}", index, j["type"].dump()));
    const std::string type = j.value("type", "directional");
    if (type == "directional") light.type = LightType::Directional;
    else if (type == "point") light.type = LightType::Point;
    else if (type == "spot") light.type = LightType::Spot;
    else fail(file, fmt::format("lights[{}].type is '{}'; use directional, point or spot", index, type));
    light.color = vec3(file, j, "color", light.color);
    light.intensity = number(file, j, "intensity", light.intensity);
    light.position = vec3(file, j, "position", light.position);
    const glm::vec3 direction = vec3(file, j, "direction", light.direction);
    if (glm::length(direction) <= 0.0f) fail(file, fmt::format("lights[{}].direction must not be zero", index));
    light.direction = glm::normalize(direction);
    if (j.contains("range")) light.range = number(file, j, "range", 0.0f);
    light.innerConeAngle = glm::radians(number(file, j, "innerConeDegrees", glm::degrees(light.innerConeAngle)));
    light.outerConeAngle = glm::radians(number(file, j, "outerConeDegrees", glm::degrees(light.outerConeAngle)));
    // KHR_lights_punctual's rule, which the glTF loader checks too.
    if (light.type == LightType::Spot && (j.contains("innerConeDegrees") || j.contains("outerConeDegrees"))) {
        const float inner = glm::degrees(light.innerConeAngle), outer = glm::degrees(light.outerConeAngle);
        if (!(inner >= 0.0f && inner < outer && outer <= 90.0f))
            fail(file, fmt::format("lights[{}] has innerConeDegrees {} and outerConeDegrees {}; a spot light needs "
                                   "0 <= innerConeDegrees < outerConeDegrees <= 90",
                                   index, inner, outer));
    }
    if (j.contains("layers")) light.renderingLayers = layerMask(file, j["layers"], fmt::format("lights[{}].layers", index));
    return light;
}

Scene loadSceneFile(std::string_view bytes, const std::filesystem::path& path, const SceneLoadOptions& options) {
    json root;
    try {
        root = json::parse(bytes);
    } catch (const json::exception& e) {
        // Not only parse_error: a number beyond double's range (1e400) is an out_of_range.
        fail(path, fmt::format("malformed JSON: {}", e.what()));
    }
    try {
        if (!root.is_object()) fail(path, "a scene file must be a JSON object (see docs/SCENES.md)");
        if (!root.contains("gltf") || !root["gltf"].is_string())
            fail(path, "missing \"gltf\": the path of the glTF/GLB to load, relative to the scene file");
        const std::filesystem::path gltfPath = path.parent_path() / root["gltf"].get<std::string>();
        bool hasCamera = false;
        Scene scene;
        try {
            scene = detail::loadGltf(gltfPath, hasCamera, options);
        } catch (const SceneError& e) {
            fail(path, fmt::format("its \"gltf\" could not be loaded: {}", e.what()));   // name both files
        }
        if (root.contains("name") && !root["name"].is_string())
            fail(path, fmt::format("\"name\" must be a string, got {}", root["name"].dump()));
        scene.name = root.value("name", path.stem().string());
        // The pose, before the camera frames the scene: "animation" (a name or an index) and
        // "time" (seconds >= 0); either defaults to the glTF's (animation 0 at t = 0).
        if (root.contains("time") || root.contains("animation")) {
            std::optional<size_t> animation = scene.posedAnimation;
            if (root.contains("animation")) {
                const json& value = root["animation"];
                if (!value.is_string() && !value.is_number_unsigned())
                    fail(path, fmt::format("\"animation\" must be an animation's name or index, got {}", value.dump()));
                try {
                    animation = findAnimation(scene, value.is_string() ? value.get<std::string>() : std::to_string(value.get<uint64_t>()));
                } catch (const SceneError& e) {
                    fail(path, fmt::format("\"animation\": {}", e.what()));
                }
            }
            float time = scene.posedTime;
            if (root.contains("time")) {
                const json& value = root["time"];
                if (!value.is_number() || !std::isfinite(value.get<double>()) || value.get<double>() < 0.0)
                    fail(path, fmt::format("\"time\" must be a number of seconds >= 0, got {}", value.dump()));
                time = value.get<float>();
            }
            poseScene(scene, time, animation);
        }

        if (root.contains("camera")) {
            const json& c = objectAt(path, root, "camera");
            Camera& camera = scene.camera;
            camera = Camera{};   // replaces the glTF camera: missing fields are the defaults
            if (c.contains("type")) {
                const json& type = c["type"];
                if (type == "perspective") camera.projection = CameraProjection::Perspective;
                else if (type == "orthographic") camera.projection = CameraProjection::Orthographic;
                else fail(path, fmt::format("camera \"type\" is {}; use \"perspective\" or \"orthographic\"", type.dump()));
            }
            camera.orthographicHalfHeight = number(path, c, "ymag", camera.orthographicHalfHeight);
            camera.position = vec3(path, c, "position", camera.position);
            camera.target = vec3(path, c, "target", camera.target);
            camera.up = vec3(path, c, "up", camera.up);
            camera.fovYRadians = glm::radians(number(path, c, "fovYDegrees", glm::degrees(camera.fovYRadians)));
            camera.nearPlane = number(path, c, "near", camera.nearPlane);
            camera.farPlane = number(path, c, "far", camera.farPlane);
            camera.node = -1;   // placed by the scene file: animations do not move it
            hasCamera = true;
        }
        if (!hasCamera) {
            try {
                detail::frameSceneBounds(scene);
            } catch (const SceneError& e) {
                fail(path, e.what());
            }
        }
        if (root.contains("environment")) {
            const json& e = objectAt(path, root, "environment");
            scene.environment.ambientColor = vec3(path, e, "ambientColor", scene.environment.ambientColor);
            scene.environment.exposure = number(path, e, "exposure", scene.environment.exposure);
            scene.environment.intensity = number(path, e, "intensity", scene.environment.intensity);
            if (!std::isfinite(scene.environment.intensity) || scene.environment.intensity < 0)
                fail(path, fmt::format("environment \"intensity\" must be a finite number >= 0, got {}", e.at("intensity").dump()));
            if (e.contains("map")) {
                const json& map = e.at("map");
                if (!map.is_string() || map.get<std::string>().empty())
                    fail(path, fmt::format("\"map\" must be the path of an .hdr or .exr image, relative to the scene file; got {}",
                                           map.dump()));
                // Stored absolute, so the renderer need not know where the scene file was.
                scene.environment.map = std::filesystem::absolute(path.parent_path() / map.get<std::string>()).lexically_normal();
                if (const std::string problem = environmentMapProblem(scene.environment.map); !problem.empty())
                    fail(path, fmt::format("{} (\"map\": {}, relative to the scene file)", problem, map.dump()));
            }
        }
        if (root.contains("lights")) {
            if (!root["lights"].is_array()) fail(path, "\"lights\" must be an array");
            for (size_t i = 0; i < root["lights"].size(); ++i) {
                scene.lights.push_back(parseLight(path, root["lights"][i], i));
                if (const char* why = darkLightReason(scene.lights.back()))
                    scene.warnings.push_back(fmt::format("{}: lights[{}] lights nothing ({}); the renderer skips it", path.string(), i, why));
            }
        }
        if (root.contains("meshLayers")) {
            // Keyed by glTF node name; every instance of that node's mesh gets the mask.
            for (const auto& [node, mask] : objectAt(path, root, "meshLayers").items()) {
                const uint32_t layers = layerMask(path, mask, fmt::format("meshLayers[\"{}\"]", node));
                bool found = false;
                for (Instance& instance : scene.instances)
                    if (instance.nodeName == node) instance.renderingLayers = layers, found = true;
                if (!found) fail(path, fmt::format("meshLayers names node '{}', but no mesh node of the glTF has that name", node));
            }
        }
        if (root.contains("defaultLight") && !root["defaultLight"].is_boolean())
            fail(path, fmt::format("\"defaultLight\" must be true or false, got {}", root["defaultLight"].dump()));
        if (scene.lights.empty() && root.value("defaultLight", true)) scene.lights.push_back(detail::defaultKeyLight());
        if (root.contains("markers")) {
            if (!root["markers"].is_array()) fail(path, "\"markers\" must be an array");
            for (const json& m : root["markers"]) {
                if (!m.is_object() || !m.contains("name") || !m["name"].is_string())
                    fail(path, "every marker needs a \"name\" string and a \"position\"");
                scene.markers.push_back(Marker{m["name"].get<std::string>(),
                                               glm::translate(glm::mat4(1.0f), vec3(path, m, "position", glm::vec3(0.0f)))});
            }
        }
        if (root.contains("reflectionProbes")) scene.reflectionProbes = detail::parseReflectionProbes(path, root["reflectionProbes"], scene);
        detail::addProbesFromMarkers(scene);
        if (root.contains("irradianceVolume")) scene.irradianceVolume = detail::parseIrradianceVolume(path, root["irradianceVolume"], scene);
        detail::addIrradianceVolumeFromMarkers(scene);
        if (root.contains("quality")) {
            scene.quality = objectAt(path, root, "quality");
            // The lighting and msaa keys are checked now, naming the file, not when a renderer is made.
            try {
                (void)resolveLighting(LightingSettings{}, scene.quality);
                (void)resolveMsaaSamples(0, scene.quality);
                (void)resolveAlphaToCoverage(std::nullopt, scene.quality);
            } catch (const RendererError& e) {
                fail(path, fmt::format("\"quality\": {}", e.what()));
            }
        }
        warnUnknownSceneFileKeys(path, root, scene.warnings);
        return scene;
    } catch (const json::exception& e) {
        fail(path, fmt::format("invalid scene file: {}", e.what()));
    }
}

template <typename... Values>
bool allFinite(const Values&... values) {
    auto finiteVector = [](const auto& v) {
        if constexpr (std::is_arithmetic_v<std::decay_t<decltype(v)>>) {
            return std::isfinite(v);
        } else {
            const float* p = glm::value_ptr(v);
            for (size_t i = 0; i < sizeof(v) / sizeof(float); ++i)
                if (!std::isfinite(p[i])) return false;
            return true;
        }
    };
    return (finiteVector(values) && ...);
}

bool allFiniteRange(const std::vector<float>& values) {
    for (float v : values)
        if (!std::isfinite(v)) return false;
    return true;
}

std::string label(const std::string& name, size_t index) { return name.empty() ? fmt::format("#{}", index) : fmt::format("'{}'", name); }

// What a .gltf / .glb loaded on its own lacks and a scene file would give: a camera, a light, probes,
// an irradiance volume.
void finishGltfScene(Scene& scene, bool hasCamera) {
    if (!hasCamera) detail::frameSceneBounds(scene);
    if (scene.lights.empty()) scene.lights.push_back(detail::defaultKeyLight());
    detail::addProbesFromMarkers(scene);
    detail::addIrradianceVolumeFromMarkers(scene);
}

// Validates a loaded scene and prints its warnings (Scene::warnings) on stderr.
void validateLoaded(const std::filesystem::path& path, const Scene& scene) {
    try {
        validateScene(scene);
    } catch (const SceneError& e) {
        fail(path, e.what());
    }
    for (const std::string& warning : scene.warnings) fmt::print(stderr, "janus: warning: {}\n", warning);
}

}  // namespace

Scene loadSceneFromMemory(std::string_view bytes, const std::filesystem::path& path, const SceneLoadOptions& options) {
    Scene scene;
    const std::string extension = lowerCaseExtension(path);
    if (extension == ".json") {
        scene = loadSceneFile(bytes, path, options);
    } else if (extension == ".gltf" || extension == ".glb") {
        bool hasCamera = false;
        scene = detail::loadGltfFromMemory(bytes, path, hasCamera, options);
        try {
            finishGltfScene(scene, hasCamera);
        } catch (const SceneError& e) {
            fail(path, e.what());
        }
    } else {
        fail(path, "unknown scene type; use a .gltf, .glb or .json scene file (see docs/SCENES.md)");
    }
    validateLoaded(path, scene);
    return scene;
}

Scene loadScene(const std::filesystem::path& path, const SceneLoadOptions& options) {
    Scene scene;
    const std::string extension = lowerCaseExtension(path);
    if (extension == ".json") {
        std::error_code ec;
        if (std::filesystem::exists(path, ec) && !std::filesystem::is_regular_file(path, ec))
            fail(path, "not a regular file (a directory, FIFO or device); give a scene file");
        std::ifstream in(path, std::ios::binary);
        if (!in) fail(path, "no such file or not readable");
        const std::string bytes((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
        if (in.bad()) fail(path, "no such file or not readable");
        scene = loadSceneFile(bytes, path, options);
    } else if (extension == ".gltf" || extension == ".glb") {
        bool hasCamera = false;
        scene = detail::loadGltf(path, hasCamera, options);
        try {
            finishGltfScene(scene, hasCamera);
        } catch (const SceneError& e) {
            fail(path, e.what());
        }
    } else {
        std::error_code ec;
        if (!std::filesystem::exists(path, ec)) fail(path, "no such file");
        fail(path, "unknown scene type; use a .gltf, .glb or .json scene file (see docs/SCENES.md)");
    }
    validateLoaded(path, scene);
    return scene;
}

namespace detail {

const char* lightProblem(const Light& light) {
    if (!allFinite(light.color, light.intensity, light.position, light.direction, light.innerConeAngle, light.outerConeAngle) ||
        (light.range && !std::isfinite(*light.range)))
        return "has a NaN or infinite colour, intensity, position or direction";
    if (light.intensity < 0 || light.color.r < 0 || light.color.g < 0 || light.color.b < 0) return "has a negative colour or intensity";
    // range <= 0 is allowed: such a light lights nothing and the renderer skips it.
    if (glm::length(light.direction) < 1e-6f) return "has a zero direction";
    // glTF's rule (KHR_lights_punctual), which loaded lights follow already, but for equal angles:
    // a hard-edged cone made in code (LightHardCases keeps it finite). Outside it the angles do not
    // mean what they say: the shading uses their cosines (a negative angle acts as its absolute
    // value, one past pi as a narrower cone), and inner > outer has no falloff to make.
    if (light.type == LightType::Spot &&
        !(light.innerConeAngle >= 0.0f && light.innerConeAngle <= light.outerConeAngle &&
          light.outerConeAngle <= glm::half_pi<float>()))
        return "is a spot light whose cone angles are not 0 <= innerConeAngle <= outerConeAngle <= pi/2 (radians)";
    return nullptr;
}

}  // namespace detail

const char* darkLightReason(const Light& light) {
    if (light.type == LightType::Directional) return nullptr;
    if (light.range && !(*light.range > 0.0f)) return "its range is <= 0";
    if (!(light.intensity > 0.0f)) return "its intensity is <= 0";
    if (!(std::max({light.color.r, light.color.g, light.color.b}) > 0.0f)) return "its colour is black";
    return nullptr;
}

void validateScene(const Scene& scene) {
    for (size_t m = 0; m < scene.meshes.size(); ++m) {
        const Mesh& mesh = scene.meshes[m];
        const size_t perPrimitive = mesh.topology == MeshTopology::Triangles ? 3 : mesh.topology == MeshTopology::Lines ? 2 : 1;
        if (mesh.indices.size() % perPrimitive != 0)
            throw SceneError(fmt::format("mesh {} has {} indices, not whole {}", m, mesh.indices.size(),
                                         mesh.topology == MeshTopology::Triangles ? "triangles" : "lines"));
        for (uint32_t index : mesh.indices)
            if (index >= mesh.vertices.size())
                throw SceneError(fmt::format("mesh {} has bad indices: {} is out of range ({} vertices)", m, index, mesh.vertices.size()));
        for (const Vertex& v : mesh.vertices)
            if (!allFinite(v.position, v.normal, v.uv, v.tangent, v.uv1, v.color))
                throw SceneError(fmt::format("mesh {} has a NaN or infinite vertex attribute", m));
        for (const Vertex& v : mesh.vertices)
            if (glm::any(glm::lessThan(v.color, glm::vec4(0.0f))) || glm::any(glm::greaterThan(v.color, glm::vec4(kMaxColorValue))))
                throw SceneError(fmt::format("mesh {} has a vertex colour ({}, {}, {}, {}) outside [0, {}]", m, v.color.r, v.color.g,
                                             v.color.b, v.color.a, kMaxColorValue));
        if (mesh.material < -1 || mesh.material >= int32_t(scene.materials.size()))
            throw SceneError(fmt::format("mesh {} uses material {} but the scene has {} (-1 = the default material)", m, mesh.material,
                                         scene.materials.size()));
        if (mesh.joints.size() != mesh.weights.size() || (!mesh.joints.empty() && mesh.joints.size() != mesh.vertices.size()))
            throw SceneError(fmt::format("mesh {} has {} joint sets and {} weight sets for {} vertices; skinned meshes have one of each "
                                         "per vertex",
                                         m, mesh.joints.size(), mesh.weights.size(), mesh.vertices.size()));
        for (const glm::vec4& w : mesh.weights)
            if (!allFinite(w) || glm::any(glm::lessThan(w, glm::vec4(0.0f))))
                throw SceneError(fmt::format("mesh {} has a NaN, infinite or negative skin weight", m));
        if (mesh.morphTargets.size() > kMaxMorphTargets)
            throw SceneError(fmt::format("mesh {} has {} morph targets; at most {}", m, mesh.morphTargets.size(), kMaxMorphTargets));
        if (mesh.morphWeights.size() != mesh.morphTargets.size() || !allFiniteRange(mesh.morphWeights))
            throw SceneError(fmt::format("mesh {} has {} morph weights for {} morph targets (one finite weight per target)", m,
                                         mesh.morphWeights.size(), mesh.morphTargets.size()));
        for (size_t t = 0; t < mesh.morphTargets.size(); ++t) {
            const MorphTarget& target = mesh.morphTargets[t];
            for (const std::vector<glm::vec3>* list : {&target.positions, &target.normals, &target.tangents}) {
                if (!list->empty() && list->size() != mesh.vertices.size())
                    throw SceneError(fmt::format("mesh {} morph target {} has {} displacements for {} vertices", m, t, list->size(),
                                                 mesh.vertices.size()));
                for (const glm::vec3& d : *list)
                    if (!allFinite(d)) throw SceneError(fmt::format("mesh {} morph target {} has a NaN or infinite displacement", m, t));
            }
        }
    }
    for (size_t i = 0; i < scene.materials.size(); ++i) {
        const Material& material = scene.materials[i];
        const std::string name = label(material.name, i);
        if (!allFinite(material.baseColorFactor, material.emissiveFactor, material.metallicFactor, material.roughnessFactor,
                       material.alphaCutoff))
            throw SceneError(fmt::format("material {} has a NaN or infinite colour or factor", name));
        // Colours feed fp16 targets: beyond 65504 (or below 0) they become Inf (or negative light).
        for (float v : {material.baseColorFactor.r, material.baseColorFactor.g, material.baseColorFactor.b, material.baseColorFactor.a,
                        material.emissiveFactor.r, material.emissiveFactor.g, material.emissiveFactor.b})
            if (v < 0.0f || v > kMaxColorValue)
                throw SceneError(fmt::format("material {} has a base colour or emissive value {} outside [0, {}]", name, v, kMaxColorValue));
        if (material.metallicFactor < 0 || material.metallicFactor > 1 || material.roughnessFactor < 0 || material.roughnessFactor > 1)
            throw SceneError(fmt::format("material {} has metallic/roughness outside [0, 1]", name));
        if (!(material.emissiveStrength >= 0.0f && material.emissiveStrength <= kMaxColorValue))
            throw SceneError(fmt::format("material {} has emissive strength {}; it must be in [0, {}] (KHR_materials_emissive_strength)",
                                         name, material.emissiveStrength, kMaxColorValue));
        for (float v : {material.emissiveFactor.r, material.emissiveFactor.g, material.emissiveFactor.b})
            if (v * material.emissiveStrength > kMaxColorValue)
                throw SceneError(fmt::format("material {} has emissive {} x strength {}, beyond the half-float targets' {}", name, v,
                                             material.emissiveStrength, kMaxColorValue));
        if (!(material.ior == 0.0f || (material.ior >= 1.0f && std::isfinite(material.ior))))
            throw SceneError(fmt::format("material {} has ior {}; it must be 0 or a finite value >= 1 (KHR_materials_ior)", name, material.ior));
        if (!(material.specularFactor >= 0.0f && material.specularFactor <= 1.0f))
            throw SceneError(fmt::format("material {} has specularFactor {} outside [0, 1] (KHR_materials_specular)", name,
                                         material.specularFactor));
        for (float v : {material.specularColorFactor.r, material.specularColorFactor.g, material.specularColorFactor.b})
            if (!(v >= 0.0f && v <= kMaxColorValue))
                throw SceneError(fmt::format("material {} has a specularColorFactor value {} outside [0, {}] (KHR_materials_specular)", name,
                                             v, kMaxColorValue));
        if (!allFinite(material.normalScale))
            throw SceneError(fmt::format("material {} has a NaN or infinite normalTexture.scale", name));
        if (!(material.occlusionStrength >= 0.0f && material.occlusionStrength <= 1.0f))
            throw SceneError(fmt::format("material {} has occlusionTexture.strength {} outside [0, 1]", name, material.occlusionStrength));
        for (const Material::TextureSlot& slot : material.textureSlots()) {
            if (slot.texture < -1 || slot.texture >= int32_t(scene.textures.size()))
                throw SceneError(fmt::format("material {} {} is texture {} but the scene has {} (-1 = none)", name, slot.name,
                                             slot.texture, scene.textures.size()));
            const TextureTransform& transform = *slot.transform;
            if (!allFinite(transform.offset, transform.rotation, transform.scale))
                throw SceneError(fmt::format("material {} {} has a NaN or infinite texture transform", name, slot.name));
            if (transform.texCoord > 1)
                throw SceneError(fmt::format("material {} {} uses texCoord {}; Janus reads TEXCOORD_0 and TEXCOORD_1 only", name, slot.name,
                                             transform.texCoord));
        }
    }
    for (size_t t = 0; t < scene.textures.size(); ++t) {
        const TextureImage& texture = scene.textures[t];
        if (texture.width == 0 || texture.height == 0 || texture.rgba.size() != size_t(texture.width) * texture.height * 4)
            throw SceneError(fmt::format("texture {} has {} bytes for {}x{} RGBA8", label(texture.name, t), texture.rgba.size(),
                                         texture.width, texture.height));
    }
    for (size_t i = 0; i < scene.instances.size(); ++i) {
        if (scene.instances[i].mesh >= scene.meshes.size())
            throw SceneError(fmt::format("instance {} uses mesh {} but the scene has {}", i, scene.instances[i].mesh, scene.meshes.size()));
        if (!allFinite(scene.instances[i].world))
            throw SceneError(fmt::format("instance {} (mesh {}) has a NaN or infinite transform", i, scene.instances[i].mesh));
    }
    // Nodes, skins, animations and the instances' references to them (as poseScene needs them),
    // then what poseScene derives: joint matrices and morph weights.
    detail::validateAnimationData(scene);
    for (size_t i = 0; i < scene.instances.size(); ++i) {
        const Instance& instance = scene.instances[i];
        const Mesh& mesh = scene.meshes[instance.mesh];
        if (instance.morphWeights.size() != mesh.morphTargets.size() || !allFiniteRange(instance.morphWeights))
            throw SceneError(fmt::format("instance {} has {} morph weights but its mesh {} has {} morph targets (poseScene sets them)", i,
                                         instance.morphWeights.size(), instance.mesh, mesh.morphTargets.size()));
        if (instance.skin < 0) continue;
        const size_t joints = scene.skins[size_t(instance.skin)].joints.size();
        if (instance.jointMatrices.size() != joints)
            throw SceneError(fmt::format("instance {} has {} joint matrices but its skin {} has {} joints (poseScene sets them)", i,
                                         instance.jointMatrices.size(), instance.skin, joints));
        for (const glm::mat4& m : instance.jointMatrices)
            if (!allFinite(m)) throw SceneError(fmt::format("instance {} has a NaN or infinite joint matrix", i));
        for (size_t v = 0; v < mesh.joints.size(); ++v)
            for (int c = 0; c < 4; ++c)
                if (mesh.joints[v][c] >= joints)
                    throw SceneError(fmt::format("instance {}: vertex {} of mesh {} uses joint {}, but skin {} has {} joints", i, v,
                                                 instance.mesh, mesh.joints[v][c], instance.skin, joints));
    }
    for (size_t i = 0; i < scene.lights.size(); ++i)
        if (const char* problem = detail::lightProblem(scene.lights[i])) throw SceneError(fmt::format("light {} {}", i, problem));
    const size_t localLights = size_t(std::count_if(scene.lights.begin(), scene.lights.end(), [](const Light& light) {
        return light.type != LightType::Directional && light.intensity > 0.0f && std::max({light.color.r, light.color.g, light.color.b}) > 0.0f &&
               !(light.range && *light.range <= 0.0f);
    }));
    if (localLights > kMaxLocalLights)
        throw SceneError(fmt::format("the scene has {} point/spot lights that light something; at most {} are supported (dim the others "
                                     "to intensity 0)",
                                     localLights, kMaxLocalLights));
    for (size_t i = 0; i < scene.markers.size(); ++i)
        if (!allFinite(scene.markers[i].world))
            throw SceneError(fmt::format("marker {} has a NaN or infinite transform", label(scene.markers[i].name, i)));
    const Camera& camera = scene.camera;
    if (!allFinite(camera.position, camera.target, camera.up, camera.fovYRadians, camera.orthographicHalfHeight, camera.nearPlane,
                   camera.farPlane))
        throw SceneError("camera has a NaN or infinite value");
    if (camera.projection == CameraProjection::Orthographic) {
        if (!(camera.orthographicHalfHeight > 0))
            throw SceneError(fmt::format("orthographic camera half height (ymag) {} must be > 0", camera.orthographicHalfHeight));
        // Depth [0, 1] spans near..far linearly: a far plane too close to near for float depth
        // (or beyond float's range of (far - near)) would leave no depth resolution.
        if (camera.nearPlane < 0 || !(camera.farPlane - camera.nearPlane > 1e-6f * std::max(1.0f, std::abs(camera.farPlane))) ||
            !std::isfinite(camera.farPlane - camera.nearPlane))
            throw SceneError(fmt::format("orthographic camera planes near={} far={} need 0 <= near < far", camera.nearPlane,
                                         camera.farPlane));
    } else {
        if (camera.fovYRadians <= 0 || camera.fovYRadians >= 3.14159f)
            throw SceneError(fmt::format("camera field of view {} degrees must be in (0, 180)", glm::degrees(camera.fovYRadians)));
        if (camera.nearPlane <= 0 || camera.farPlane <= camera.nearPlane)
            throw SceneError(fmt::format("camera planes near={} far={} need 0 < near < far", camera.nearPlane, camera.farPlane));
    }
    if (glm::length(camera.target - camera.position) <= 0 || glm::length(glm::cross(camera.target - camera.position, camera.up)) <= 0)
        throw SceneError("camera target must differ from its position and not be along its up vector");
    if (!allFinite(scene.environment.ambientColor, scene.environment.exposure))
        throw SceneError("environment has a NaN or infinite ambient colour or exposure");
    if (scene.environment.exposure <= 0) throw SceneError(fmt::format("environment exposure {} must be > 0", scene.environment.exposure));
    for (float v : {scene.environment.ambientColor.r, scene.environment.ambientColor.g, scene.environment.ambientColor.b})
        if (v < 0.0f || v > kMaxColorValue)
            throw SceneError(fmt::format("environment ambient colour value {} is outside [0, {}] (the HDR target is half-float)", v,
                                         kMaxColorValue));
    if (!std::isfinite(scene.environment.intensity) || scene.environment.intensity < 0)
        throw SceneError(fmt::format("environment intensity {} must be finite and >= 0", scene.environment.intensity));
    if (!scene.environment.map.empty())
        if (const std::string problem = environmentMapProblem(scene.environment.map); !problem.empty()) throw SceneError(problem);
    if (const std::shared_ptr<const ImageRGBAF>& sky = scene.environment.image; sky && scene.environment.map.empty()) {
        if (sky->width < 2 || sky->height < 1 || sky->pixels.size() != size_t(sky->width) * sky->height * 4)
            throw SceneError(fmt::format("environment image is {}x{} with {} floats; an equirectangular sky needs at least 2x1 texels "
                                         "and width * height * 4 floats", sky->width, sky->height, sky->pixels.size()));
        for (float v : sky->pixels)
            if (!std::isfinite(v) || v < 0.0f)
                throw SceneError(fmt::format("environment image holds {}; sky radiance must be finite and >= 0", v));
    }
    detail::validateReflectionProbes(scene);
    detail::validateIrradianceVolume(scene);
}

}  // namespace janus::renderer
