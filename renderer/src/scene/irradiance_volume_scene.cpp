// The irradiance volume in scenes: the scene file's "irradianceVolume", the volume an
// "IrradianceVolume..." glTF marker places, and validation (docs/SCENES.md, docs/GI.md).
#include <cmath>

#include <fmt/format.h>

#include "scene/scene_internal.h"

namespace janus::renderer::detail {

using nlohmann::json;

namespace {

uint32_t readCount(const std::filesystem::path& file, const json& value, const std::string& where, const char* range) {
    if (!value.is_number_unsigned()) fail(file, fmt::format("{} must be an integer in {}, got {}", where, range, value.dump()));
    return uint32_t(std::min<uint64_t>(value.get<uint64_t>(), UINT32_MAX));
}

float readNumber(const std::filesystem::path& file, const json& value, const std::string& where) {
    if (!value.is_number()) fail(file, fmt::format("{} must be a number, got {}", where, value.dump()));
    return value.get<float>();
}

}  // namespace

std::span<const std::string_view> irradianceVolumeKeys() {
    static constexpr std::string_view kKeys[] = {"name",    "bounds",  "probes",         "spacing",    "surfelsPerProbe",         "brickSize",
                                                 "bricks",  "maxSurfelsPerBrick", "parallelReduction", "bounces", "shOrder", "probesPerFrame",
                                                 "normalBias", "invalidBackFaceFraction", "relocateProbes", "visibility", "near", "far"};
    return kKeys;
}

IrradianceVolume parseIrradianceVolume(const std::filesystem::path& file, const json& v, const Scene& scene) {
    const std::string where = "irradianceVolume";
    if (!v.is_object()) fail(file, "\"irradianceVolume\" must be an object");
    IrradianceVolume volume;
    volume.name = v.value("name", volume.name);
    volume.bounds = v.contains("bounds") ? readBox(file, v["bounds"], where + ".bounds") : sceneBounds(scene);
    if (v.contains("probes") && v.contains("spacing"))
        fail(file, "irradianceVolume: give \"probes\" (counts per axis) or \"spacing\" (metres between probes), not both");
    if (v.contains("probes")) {
        const json& counts = v["probes"];
        if (counts.is_number_unsigned()) {
            volume.probeCounts = glm::uvec3(readCount(file, counts, where + ".probes", "[1, 64]"));
        } else if (counts.is_array() && counts.size() == 3) {
            for (int axis = 0; axis < 3; ++axis)
                volume.probeCounts[axis] = readCount(file, counts[axis], fmt::format("{}.probes[{}]", where, axis), "[1, 64]");
        } else {
            fail(file, fmt::format("{}.probes must be a count or [x, y, z] counts, got {}", where, counts.dump()));
        }
    }
    if (v.contains("spacing")) {
        const float spacing = readNumber(file, v["spacing"], where + ".spacing");
        if (!(std::isfinite(spacing) && spacing > 0.0f))
            fail(file, fmt::format("{}.spacing must be a finite number of metres > 0, got {}", where, spacing));
        const glm::vec3 size = volume.bounds.size();
        for (int axis = 0; axis < 3; ++axis) {
            const double count = std::ceil(double(size[axis]) / double(spacing));
            volume.probeCounts[axis] = uint32_t(std::clamp(count, 1.0, 1e6));   // validation names counts above 64
        }
    }
    if (v.contains("surfelsPerProbe")) volume.surfelsPerProbe = readCount(file, v["surfelsPerProbe"], where + ".surfelsPerProbe", "[16, 4096]");
    if (v.contains("brickSize")) volume.brickSize = readNumber(file, v["brickSize"], where + ".brickSize");
    if (v.contains("bricks")) {
        if (!v["bricks"].is_boolean()) fail(file, fmt::format("{}.bricks must be true or false", where));
        volume.bricks = v["bricks"].get<bool>();
    }
    if (v.contains("maxSurfelsPerBrick"))
        volume.maxSurfelsPerBrick = readCount(file, v["maxSurfelsPerBrick"], where + ".maxSurfelsPerBrick", "[1, 4096]");
    if (v.contains("parallelReduction")) {
        if (!v["parallelReduction"].is_boolean()) fail(file, fmt::format("{}.parallelReduction must be true or false", where));
        volume.parallelReduction = v["parallelReduction"].get<bool>();
    }
    if (v.contains("bounces")) volume.bounces = readCount(file, v["bounces"], where + ".bounces", "[1, 8]");
    if (v.contains("shOrder")) volume.shOrder = readCount(file, v["shOrder"], where + ".shOrder", "{1, 2}");
    if (v.contains("probesPerFrame")) volume.probesPerFrame = readCount(file, v["probesPerFrame"], where + ".probesPerFrame", "[0, 4096]");
    if (v.contains("normalBias")) volume.normalBias = readNumber(file, v["normalBias"], where + ".normalBias");
    if (v.contains("invalidBackFaceFraction"))
        volume.invalidBackFaceFraction = readNumber(file, v["invalidBackFaceFraction"], where + ".invalidBackFaceFraction");
    if (v.contains("relocateProbes")) {
        if (!v["relocateProbes"].is_boolean()) fail(file, fmt::format("{}.relocateProbes must be true or false", where));
        volume.relocateProbes = v["relocateProbes"].get<bool>();
    }
    if (v.contains("visibility")) {
        if (!v["visibility"].is_boolean()) fail(file, fmt::format("{}.visibility must be true or false", where));
        volume.visibility = v["visibility"].get<bool>();
    }
    if (v.contains("near")) volume.nearPlane = readNumber(file, v["near"], where + ".near");
    if (v.contains("far")) volume.farPlane = readNumber(file, v["far"], where + ".far");
    return volume;
}

void addIrradianceVolumeFromMarkers(Scene& scene) {
    if (scene.irradianceVolume) return;
    for (const Marker& marker : scene.markers) {
        if (marker.name.rfind("IrradianceVolume", 0) != 0) continue;
        // The marker carries no extent (the cornell box's is a bare translation): the volume
        // covers the scene's bounds, shrunk by 1 % so no probe sits on the outer walls.
        const Box bounds = sceneBounds(scene);
        if (bounds.min == bounds.max) return;
        IrradianceVolume volume;
        volume.name = marker.name;
        const glm::vec3 margin = bounds.size() * 0.01f;
        volume.bounds = Box{bounds.min + margin, bounds.max - margin};
        volume.farPlane = std::max(2.0f * glm::length(bounds.size()), 1.0f);
        scene.irradianceVolume = volume;
        return;
    }
}

void validateIrradianceVolume(const Scene& scene) {
    if (!scene.irradianceVolume) return;
    const IrradianceVolume& v = *scene.irradianceVolume;
    const std::string name = fmt::format("irradiance volume '{}'", v.name);
    auto finite = [](glm::vec3 p) { return std::isfinite(p.x) && std::isfinite(p.y) && std::isfinite(p.z); };
    if (!finite(v.bounds.min) || !finite(v.bounds.max)) throw SceneError(fmt::format("{}: its bounds have a NaN or infinite corner", name));
    if (glm::any(glm::greaterThan(v.bounds.min, v.bounds.max)))
        throw SceneError(fmt::format("{}: its bounds have min ({}, {}, {}) above max ({}, {}, {}) on some axis", name, v.bounds.min.x,
                                     v.bounds.min.y, v.bounds.min.z, v.bounds.max.x, v.bounds.max.y, v.bounds.max.z));
    for (int axis = 0; axis < 3; ++axis)
        if (v.probeCounts[axis] < 1 || v.probeCounts[axis] > 64)
            throw SceneError(fmt::format("{}: {} probes along {}; each axis needs 1 to 64 (use a larger spacing)", name,
                                         v.probeCounts[axis], "xyz"[axis]));
    const uint64_t probes = uint64_t(v.probeCounts.x) * v.probeCounts.y * v.probeCounts.z;
    if (probes > kMaxIrradianceProbes)
        throw SceneError(fmt::format("{}: {}x{}x{} = {} probes; at most {} are supported", name, v.probeCounts.x, v.probeCounts.y,
                                     v.probeCounts.z, probes, kMaxIrradianceProbes));
    if (v.surfelsPerProbe < 16 || v.surfelsPerProbe > 4096)
        throw SceneError(fmt::format("{}: {} surfels per probe; give 16 to 4096", name, v.surfelsPerProbe));
    if (v.maxSurfelsPerBrick < 1 || v.maxSurfelsPerBrick > 4096)
        throw SceneError(fmt::format("{}: maxSurfelsPerBrick {}; give 1 to 4096", name, v.maxSurfelsPerBrick));
    if (!(std::isfinite(v.brickSize) && v.brickSize > 0.0f))
        throw SceneError(fmt::format("{}: brick size {} must be a finite number of metres > 0", name, v.brickSize));
    if (v.bounces < 1 || v.bounces > 8) throw SceneError(fmt::format("{}: {} bounces; give 1 to 8", name, v.bounces));
    if (v.shOrder != 1 && v.shOrder != 2)
        throw SceneError(fmt::format("{}: SH order {} is not supported; give 1 (L1, 4 coefficients) or 2 (L2, 9)", name, v.shOrder));
    if (v.probesPerFrame > kMaxIrradianceProbes)
        throw SceneError(fmt::format("{}: {} probes per frame is above the most, {} (0 = all)", name, v.probesPerFrame, kMaxIrradianceProbes));
    if (!(std::isfinite(v.normalBias) && v.normalBias >= 0.0f))
        throw SceneError(fmt::format("{}: normal bias {} must be finite and >= 0", name, v.normalBias));
    if (!(v.invalidBackFaceFraction > 0.0f && v.invalidBackFaceFraction <= 1.0f))
        throw SceneError(fmt::format("{}: invalidBackFaceFraction {} must be in (0, 1]", name, v.invalidBackFaceFraction));
    if (!(std::isfinite(v.nearPlane) && std::isfinite(v.farPlane) && v.nearPlane > 0.0f && v.nearPlane < v.farPlane))
        throw SceneError(fmt::format("{}: planes near {} and far {} must satisfy 0 < near < far", name, v.nearPlane, v.farPlane));
}

}  // namespace janus::renderer::detail
