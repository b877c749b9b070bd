// Reflection probes in scenes: the scene file's "reflectionProbes", probes placed by glTF
// "ReflectionCubemap..." markers, and their validation (docs/SCENES.md, docs/PROBES.md).
#include <algorithm>
#include <cmath>
#include <limits>

#include <fmt/format.h>

#include "ibl/ggx_samples.h"
#include "msaa/msaa_settings.h"
#include "scene/scene_internal.h"

namespace janus::renderer {

const char* toString(ProbeUpdate update) {
    switch (update) {
        case ProbeUpdate::Once: return "once";
        case ProbeUpdate::EveryFrame: return "every-frame";
        case ProbeUpdate::OnRequest: return "on-request";
    }
    return "?";
}

const char* toString(ProbeTimeSlicing slicing) {
    switch (slicing) {
        case ProbeTimeSlicing::None: return "none";
        case ProbeTimeSlicing::AllFacesThenMips: return "all-faces-then-mips";
        case ProbeTimeSlicing::IndividualFaces: return "individual-faces";
    }
    return "?";
}

namespace detail {

using nlohmann::json;

[[noreturn]] void fail(const std::filesystem::path& file, const std::string& what) {
    throw SceneError(fmt::format("{}: {}", file.string(), what));
}

glm::vec3 readVec3(const std::filesystem::path& file, const json& value, const std::string& where) {
    if (!value.is_array() || value.size() != 3 || !value[0].is_number() || !value[1].is_number() || !value[2].is_number())
        fail(file, fmt::format("{} must be an array of 3 numbers, got {}", where, value.dump()));
    return glm::vec3(value[0].get<float>(), value[1].get<float>(), value[2].get<float>());
}

// {"min": [..], "max": [..]} or {"center": [..], "size": [..]}.
Box readBox(const std::filesystem::path& file, const json& value, const std::string& where) {
    if (value.is_object() && value.contains("min") && value.contains("max"))
        return Box{readVec3(file, value["min"], where + ".min"), readVec3(file, value["max"], where + ".max")};
    if (value.is_object() && value.contains("center") && value.contains("size")) {
        const glm::vec3 center = readVec3(file, value["center"], where + ".center");
        const glm::vec3 half = readVec3(file, value["size"], where + ".size") * 0.5f;
        return Box{center - half, center + half};
    }
    fail(file, fmt::format("{} must be a box: {{\"min\": [x,y,z], \"max\": [x,y,z]}} or {{\"center\": [x,y,z], \"size\": [x,y,z]}}; got {}",
                           where, value.dump()));
}

namespace {

template <typename Enum, size_t N>
Enum readEnum(const std::filesystem::path& file, const json& value, const std::string& where, const std::array<Enum, N>& options) {
    std::string names;
    for (Enum option : options) names += fmt::format("{}\"{}\"", names.empty() ? "" : " | ", toString(option));
    if (value.is_string())
        for (Enum option : options)
            if (value.get<std::string>() == toString(option)) return option;
    fail(file, fmt::format("{} must be one of {}, got {}", where, names, value.dump()));
}

}  // namespace

std::optional<Box> instanceBounds(const Scene& scene, const Instance& instance) {
    if (instance.mesh >= scene.meshes.size()) return std::nullopt;
    // Skinned and morphed meshes where the pose puts them (posedVertices), others as they are.
    std::vector<Vertex> posed;
    if (isDeformed(scene, instance)) {
        try {
            posed = posedVertices(scene, instance);
        } catch (const SceneError&) {
            posed.clear();   // not posed consistently (a scene made in code): the mesh as it is
        }
    }
    glm::vec3 lo(std::numeric_limits<float>::max()), hi(-std::numeric_limits<float>::max());
    for (const Vertex& v : posed.empty() ? scene.meshes[instance.mesh].vertices : posed) {
        const glm::vec3 p = glm::vec3(instance.world * glm::vec4(v.position, 1.0f));
        lo = glm::min(lo, p);
        hi = glm::max(hi, p);
    }
    if (lo.x > hi.x) return std::nullopt;
    return Box{lo, hi};
}

bool isDeformed(const Scene& scene, const Instance& instance) {
    if (instance.mesh >= scene.meshes.size()) return false;
    const Mesh& mesh = scene.meshes[instance.mesh];
    if (mesh.vertices.empty() || mesh.indices.empty()) return false;
    return !mesh.morphTargets.empty() || (!mesh.joints.empty() && instance.skin >= 0);
}

Box sceneBounds(const Scene& scene) {
    std::optional<Box> bounds;
    for (const Instance& instance : scene.instances)
        if (const std::optional<Box> box = instanceBounds(scene, instance))
            bounds = bounds ? Box{glm::min(bounds->min, box->min), glm::max(bounds->max, box->max)} : *box;
    return bounds.value_or(Box{});
}

std::span<const std::string_view> reflectionProbeKeys() {
    static constexpr std::string_view kKeys[] = {"name",    "position",     "influence", "blendDistance", "parallax",      "resolution", "update",
                                                 "timeSlicing", "shadows", "shadowMapSize", "layers",   "samplesPerMip", "brightTexels", "msaa", "seesProbes"};
    return kKeys;
}

std::vector<ReflectionProbe> parseReflectionProbes(const std::filesystem::path& file, const json& probes, const Scene& scene) {
    if (!probes.is_array()) fail(file, "\"reflectionProbes\" must be an array");
    std::vector<ReflectionProbe> result;
    for (size_t i = 0; i < probes.size(); ++i) {
        const json& p = probes[i];
        const std::string where = fmt::format("reflectionProbes[{}]", i);
        if (!p.is_object()) fail(file, fmt::format("{} must be an object", where));
        ReflectionProbe probe;
        probe.name = p.value("name", fmt::format("probe {}", i));
        probe.influence = p.contains("influence") ? readBox(file, p["influence"], where + ".influence") : sceneBounds(scene);
        probe.position = p.contains("position") ? readVec3(file, p["position"], where + ".position") : probe.influence.center();
        if (p.contains("blendDistance")) {
            if (!p["blendDistance"].is_number()) fail(file, fmt::format("{}.blendDistance must be a number", where));
            probe.blendDistance = p["blendDistance"].get<float>();
        }
        if (p.contains("parallax")) {
            const json& parallax = p["parallax"];
            if (parallax.is_boolean()) {
                if (parallax.get<bool>()) probe.parallax = probe.influence;
            } else {
                probe.parallax = readBox(file, parallax, where + ".parallax");
            }
        }
        if (p.contains("resolution")) {
            if (!p["resolution"].is_number_unsigned()) fail(file, fmt::format("{}.resolution must be a power of two in [8, 1024], got {}", where, p["resolution"].dump()));
            probe.resolution = uint32_t(std::min<uint64_t>(p["resolution"].get<uint64_t>(), UINT32_MAX));
        }
        for (const auto& [key, member] : {std::pair{"near", &probe.nearPlane}, std::pair{"far", &probe.farPlane}}) {
            if (!p.contains(key)) continue;
            if (!p[key].is_number()) fail(file, fmt::format("{}.{} must be a number, got {}", where, key, p[key].dump()));
            *member = p[key].get<float>();
        }
        if (p.contains("update"))
            probe.update = readEnum(file, p["update"], where + ".update",
                                    std::array{ProbeUpdate::Once, ProbeUpdate::EveryFrame, ProbeUpdate::OnRequest});
        if (p.contains("timeSlicing"))
            probe.timeSlicing = readEnum(file, p["timeSlicing"], where + ".timeSlicing",
                                         std::array{ProbeTimeSlicing::None, ProbeTimeSlicing::AllFacesThenMips,
                                                    ProbeTimeSlicing::IndividualFaces});
        if (p.contains("shadows")) {
            if (!p["shadows"].is_boolean()) fail(file, fmt::format("{}.shadows must be true or false", where));
            probe.shadows = p["shadows"].get<bool>();
        }
        if (p.contains("shadowMapSize")) {
            if (!p["shadowMapSize"].is_number_unsigned())
                fail(file, fmt::format("{}.shadowMapSize must be 0 (the renderer's) or a power of two in [16, 8192], got {}", where,
                                       p["shadowMapSize"].dump()));
            probe.shadowMapSize = uint32_t(std::min<uint64_t>(p["shadowMapSize"].get<uint64_t>(), UINT32_MAX));
        }
        if (p.contains("layers")) {
            const json& layers = p["layers"];
            if (!layers.is_number_integer() || layers.get<int64_t>() < 0 || layers.get<int64_t>() > int64_t(UINT32_MAX))
                fail(file, fmt::format("{}.layers must be an integer layer mask in [0, 4294967295], got {}", where, layers.dump()));
            probe.renderingLayers = uint32_t(layers.get<int64_t>());
        }
        if (p.contains("samplesPerMip")) {
            const json& samples = p["samplesPerMip"];
            const std::string expected = fmt::format("{}.samplesPerMip must be a sample count in [1, {}] or a non-empty array of them", where,
                                                     kMaxGgxSamples);
            if (samples.is_number_unsigned()) {
                probe.samplesPerMip = {uint32_t(std::min<uint64_t>(samples.get<uint64_t>(), UINT32_MAX))};
            } else if (samples.is_array() && !samples.empty()) {
                for (const json& count : samples) {
                    if (!count.is_number_unsigned()) fail(file, fmt::format("{}, got {}", expected, samples.dump()));
                    probe.samplesPerMip.push_back(uint32_t(std::min<uint64_t>(count.get<uint64_t>(), UINT32_MAX)));
                }
            } else {
                fail(file, fmt::format("{}, got {}", expected, samples.dump()));
            }
        }
        if (p.contains("brightTexels")) {
            if (!p["brightTexels"].is_number_unsigned())
                fail(file, fmt::format("{}.brightTexels must be 0 (off) or a count up to {}, got {}", where, kMaxGgxBrightTexels,
                                       p["brightTexels"].dump()));
            probe.brightTexels = uint32_t(std::min<uint64_t>(p["brightTexels"].get<uint64_t>(), UINT32_MAX));
        }
        if (p.contains("seesProbes")) {
            if (!p["seesProbes"].is_boolean()) fail(file, fmt::format("{}.seesProbes must be true or false, got {}", where, p["seesProbes"].dump()));
            probe.seesProbes = p["seesProbes"].get<bool>();
        }
        if (p.contains("msaa")) {
            if (!p["msaa"].is_number_unsigned())
                fail(file, fmt::format("{}.msaa must be the capture's samples per pixel, 1, 2, 4, 8 or 16, got {}", where, p["msaa"].dump()));
            probe.msaaSamples = uint32_t(std::min<uint64_t>(p["msaa"].get<uint64_t>(), UINT32_MAX));
        }
        result.push_back(std::move(probe));
    }
    return result;
}

void addProbesFromMarkers(Scene& scene) {
    if (!scene.reflectionProbes.empty()) return;
    const Box bounds = sceneBounds(scene);
    for (const Marker& marker : scene.markers) {
        if (marker.name.rfind("ReflectionCubemap", 0) != 0) continue;
        ReflectionProbe probe;
        probe.name = marker.name;
        probe.position = glm::vec3(marker.world[3]);
        // The scene's bounds, a little larger so surfaces on its faces are inside: a probe placed
        // in a room by a marker lights the room and projects onto its walls.
        const glm::vec3 margin = glm::max(bounds.size() * 0.01f, glm::vec3(1e-3f));
        probe.influence = Box{bounds.min - margin, bounds.max + margin};
        probe.parallax = probe.influence;
        probe.farPlane = std::max(2.0f * glm::length(bounds.size()), 1.0f);
        scene.reflectionProbes.push_back(std::move(probe));
    }
}

void validateReflectionProbes(const Scene& scene) {
    if (scene.reflectionProbes.size() > kMaxSceneReflectionProbes)
        throw SceneError(fmt::format("the scene has {} reflection probes; at most {} are supported", scene.reflectionProbes.size(),
                                     kMaxSceneReflectionProbes));
    for (size_t i = 0; i < scene.reflectionProbes.size(); ++i) {
        const ReflectionProbe& p = scene.reflectionProbes[i];
        const std::string name = p.name.empty() ? fmt::format("#{}", i) : fmt::format("'{}'", p.name);
        auto finite = [](glm::vec3 v) { return std::isfinite(v.x) && std::isfinite(v.y) && std::isfinite(v.z); };
        auto checkBox = [&](const Box& box, const char* what) {
            if (!finite(box.min) || !finite(box.max))
                throw SceneError(fmt::format("reflection probe {}: its {} box has a NaN or infinite corner", name, what));
            if (glm::any(glm::greaterThan(box.min, box.max)))
                throw SceneError(fmt::format("reflection probe {}: its {} box has min ({}, {}, {}) above max ({}, {}, {}) on some axis",
                                             name, what, box.min.x, box.min.y, box.min.z, box.max.x, box.max.y, box.max.z));
        };
        if (!finite(p.position)) throw SceneError(fmt::format("reflection probe {}: its position is NaN or infinite", name));
        checkBox(p.influence, "influence");
        if (p.parallax) checkBox(*p.parallax, "parallax");
        if (!std::isfinite(p.blendDistance) || p.blendDistance < 0.0f)
            throw SceneError(fmt::format("reflection probe {}: blend distance {} must be finite and >= 0", name, p.blendDistance));
        if (p.resolution < 8 || p.resolution > 1024 || (p.resolution & (p.resolution - 1)) != 0)
            throw SceneError(fmt::format("reflection probe {}: resolution {} must be a power of two in [8, 1024]", name, p.resolution));
        if (p.shadowMapSize != 0 && (p.shadowMapSize < 16 || p.shadowMapSize > 8192 || (p.shadowMapSize & (p.shadowMapSize - 1)) != 0))
            throw SceneError(fmt::format("reflection probe {}: shadow map size {} must be 0 (the renderer's) or a power of two in [16, 8192]",
                                         name, p.shadowMapSize));
        for (uint32_t count : p.samplesPerMip)
            if (count < 1 || count > kMaxGgxSamples)
                throw SceneError(fmt::format("reflection probe {}: {} GGX samples per mip; each entry must be in [1, {}]", name, count,
                                             kMaxGgxSamples));
        if (p.brightTexels > kMaxGgxBrightTexels)
            throw SceneError(fmt::format("reflection probe {}: {} bright texels is above the most, {} (0 turns the split off)", name,
                                         p.brightTexels, kMaxGgxBrightTexels));
        if (!isMsaaSampleCount(p.msaaSamples))
            throw SceneError(fmt::format("reflection probe {}: msaa {} must be 1 (off), 2, 4, 8 or 16 samples per pixel", name,
                                         p.msaaSamples));
        if (!(std::isfinite(p.nearPlane) && std::isfinite(p.farPlane) && p.nearPlane > 0.0f && p.nearPlane < p.farPlane))
            throw SceneError(fmt::format("reflection probe {}: planes near {} and far {} must satisfy 0 < near < far", name, p.nearPlane,
                                         p.farPlane));
    }
}

}  // namespace detail
}  // namespace janus::renderer
