// The glTF 2.0 schema's types, lengths, integer ranges and enumerations for the properties Janus
// reads, checked on the JSON before tinygltf reads it. tinygltf takes a value of the wrong type
// or length as absent ("matrix": [1, 0, 0] as the identity, "metallicFactor": "x" as 1, a
// negative byteOffset as 0, "mode": -1 as triangles) and accepts integers outside an enumeration
// ("wrapS": 1234), so without this a malformed file renders as something it does not say.
#pragma once

#include <string>

#include <nlohmann/json.hpp>

namespace janus::renderer::detail {

// The first problem as "<where>: <what is wrong and what the schema wants>" (where is a path such
// as "nodes[2].matrix"), or "" when every checked property is well-formed. Properties Janus does
// not read are not checked, and neither are the ones the loader checks itself with the mesh's or
// material's name (the material extensions and KHR_texture_transform, a sparse index type, a
// primitive mode above 6, an animation's interpolation); of the extensions, only
// KHR_lights_punctual is.
std::string gltfSchemaProblem(const nlohmann::json& root);

}  // namespace janus::renderer::detail
