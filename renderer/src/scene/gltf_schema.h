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
// not read, extensions included (but KHR_lights_punctual), are not checked.
std::string gltfSchemaProblem(const nlohmann::json& root);

}  // namespace janus::renderer::detail
