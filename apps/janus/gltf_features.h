// What a glTF file uses, read from its JSON alone (no buffers, no images, no loader): the
// extensions it declares and the glTF features in kGltfFeatures. `janus check` reports it per file,
// so a user sees what their assets need before porting. Independent of the renderer's loader on
// purpose: it describes the file, also the files the loader refuses.
#pragma once

#include <filesystem>
#include <span>
#include <string>
#include <string_view>
#include <vector>

#include <nlohmann/json.hpp>

namespace janus::cli {

// One row of the feature table: a short stable name (what check.json lists), what it means, and
// whether the glTF's root object uses it.
struct GltfFeature {
    std::string_view name;
    std::string_view description;
    bool (*used)(const nlohmann::json& root);
};

// Every feature detected, in the order they are reported.
std::span<const GltfFeature> gltfFeatures();

struct GltfUsage {
    std::vector<std::string> extensionsUsed;       // as the file lists them (strings only), in its order
    std::vector<std::string> extensionsRequired;
    std::vector<std::string> features;             // names from gltfFeatures(), in table order
    std::string error;                             // why the JSON could not be read; then all lists are empty
};

// From a whole .gltf (JSON text) or .glb (told apart by the "glTF" magic, not by the name).
GltfUsage scanGltfUsage(std::string_view bytes);
// The root object of a glTF's JSON, already parsed.
GltfUsage scanGltfJson(const nlohmann::json& root);
// Reads only what is needed: the whole .gltf, or a .glb's header and JSON chunk. A file that cannot
// be read gives `error`, never an exception.
GltfUsage scanGltfFile(const std::filesystem::path& path);

// The files a glTF's JSON names (buffers[].uri and images[].uri that are not data: URIs,
// percent-decoded), resolved against the glTF's folder; empty when its JSON cannot be read.
// For refusing an output that would overwrite an input.
std::vector<std::filesystem::path> gltfReferencedFiles(const std::filesystem::path& path);

}  // namespace janus::cli
