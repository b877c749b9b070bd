// The glTF 2.0 schema check (renderer/src/scene/gltf_schema.*): a property of the wrong type,
// length, sign or enumeration is refused by name, in .gltf and .glb alike. Before it, tinygltf took
// each of these as absent or as given and the file rendered as something it does not say (a
// matrix of 3 numbers as the identity, "metallicFactor": "x" as 1, "byteOffset": -12 as 0, mode -1
// as triangles, "wrapS": 1234 as repeat, a glTF 1.0 file as an empty scene): found by exploratory
// testing of the CLI.
#include <gtest/gtest.h>

#include <functional>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "janus/renderer/scene.h"
#include "renderer/gltf_test_file.h"
#include "scene/gltf_schema.h"

namespace janus::renderer {
namespace {

using nlohmann::json;
using test_support::contains;
using test_support::sceneErrorOf;
using test_support::TinyGltf;

struct Malformed {
    const char* name;
    std::function<void(json&)> breakIt;
    std::vector<std::string> mentions;   // what the message must say
};

const std::vector<Malformed>& malformedFiles() {
    static const std::vector<Malformed> cases = {
        {"matrix of three numbers", [](json& g) { g["nodes"][0]["matrix"] = {1, 0, 0}; },
         {"nodes[0].matrix: must be an array of 16 numbers; it has 3"}},
        {"matrix as a string", [](json& g) { g["nodes"][0]["matrix"] = "identity"; },
         {"nodes[0].matrix: must be an array of 16 numbers; it is a string \"identity\""}},
        {"translation with a string", [](json& g) { g["nodes"][0]["translation"] = {0, "1", 0}; },
         {"nodes[0].translation: must be an array of 3 numbers; element 1 is a string \"1\""}},
        {"metallic factor as a string",
         [](json& g) { g["materials"][0]["pbrMetallicRoughness"]["metallicFactor"] = "x"; },
         {"materials[0].pbrMetallicRoughness.metallicFactor: must be a number; it is a string \"x\""}},
        {"base colour of three numbers",
         [](json& g) { g["materials"][0]["pbrMetallicRoughness"]["baseColorFactor"] = {1, 1, 1}; },
         {"materials[0].pbrMetallicRoughness.baseColorFactor: must be an array of 4 numbers; it has 3"}},
        {"unknown alpha mode", [](json& g) { g["materials"][0]["alphaMode"] = "CUTOUT"; },
         {"materials[0].alphaMode: must be one of \"OPAQUE\", \"MASK\", \"BLEND\"; it is a string \"CUTOUT\""}},
        {"double-sided as a number", [](json& g) { g["materials"][0]["doubleSided"] = 1; },
         {"materials[0].doubleSided: must be true or false; it is 1"}},
        {"negative accessor byte offset", [](json& g) { g["accessors"][0]["byteOffset"] = -12; },
         {"accessors[0].byteOffset: must be an integer >= 0; it is -12"}},
        {"fractional accessor count", [](json& g) { g["accessors"][0]["count"] = 2.5; },
         {"accessors[0].count: must be an integer >= 1; it is 2.5"}},
        {"unknown component type", [](json& g) { g["accessors"][1]["componentType"] = 5124; },
         {"accessors[1].componentType: must be one of 5120 (BYTE)", "it is 5124"}},
        {"byte stride below 4", [](json& g) { g["bufferViews"][0]["byteStride"] = 2; },
         {"bufferViews[0].byteStride: must be an integer in [4, 252]; it is 2"}},
        {"negative primitive mode", [](json& g) { g["meshes"][0]["primitives"][0]["mode"] = -1; },
         {"meshes[0].primitives[0] has mode -1; glTF primitive modes are 0 (POINTS) to 6 (TRIANGLE_FAN)"}},
        {"negative index", [](json& g) { g["meshes"][0]["primitives"][0]["indices"] = -1; },
         {"meshes[0].primitives[0].indices: must be an integer in [0, 4294967295]; it is -1"}},
        {"attribute as a string", [](json& g) { g["meshes"][0]["primitives"][0]["attributes"]["POSITION"] = "0"; },
         {"meshes[0].primitives[0].attributes.POSITION: must be an integer in [0, 4294967295]; it is a string \"0\""}},
        {"extensionsRequired as a string", [](json& g) { g["extensionsRequired"] = "KHR_x"; },
         {"extensionsRequired: must be an array of strings; it is a string \"KHR_x\""}},
        {"unknown wrap mode",
         [](json& g) {
             g["samplers"] = json::array({{{"wrapS", 1234}}});
         },
         {"samplers[0].wrapS: must be one of 33071 (CLAMP_TO_EDGE), 33648 (MIRRORED_REPEAT), 10497 (REPEAT); it is 1234"}},
        {"unknown min filter", [](json& g) { g["samplers"] = json::array({{{"minFilter", 9729.5}}}); },
         {"samplers[0].minFilter: must be one of 9728 (NEAREST)", "it is 9729.5"}},
        {"scene node as a string", [](json& g) { g["scenes"][0]["nodes"] = {"0"}; },
         {"scenes[0].nodes[0]: must be an index (an integer >= 0); it is a string \"0\""}},
        {"a node that is not an object", [](json& g) { g["nodes"].push_back(7); }, {"nodes[1]: must be an object; it is 7"}},
        {"glTF 1.0", [](json& g) { g["asset"]["version"] = "1.0"; },
         {"asset.version: is \"1.0\"; Janus reads glTF 2.0", "convert"}},
        {"no asset", [](json& g) { g.erase("asset"); }, {"asset: is required and missing"}},
        {"a light of no known type",
         [](json& g) {
             g["extensionsUsed"] = {"KHR_lights_punctual"};
             g["extensions"]["KHR_lights_punctual"]["lights"] = json::array({{{"type", "area"}}});
         },
         {"extensions.KHR_lights_punctual.lights[0].type: must be one of \"directional\", \"point\", \"spot\"; it is a string "
          "\"area\""}},
        {"spot cone wider than a half sphere",
         [](json& g) {
             g["extensionsUsed"] = {"KHR_lights_punctual"};
             g["extensions"]["KHR_lights_punctual"]["lights"] =
                 json::array({{{"type", "spot"}, {"spot", {{"innerConeAngle", 0.1}, {"outerConeAngle", 3.5}}}}});
         },
         {"extensions.KHR_lights_punctual.lights[0].spot.outerConeAngle: must be a number in [0, 1.5707963267948966]; it is 3.5"}},
        {"spot inner cone not inside the outer one",
         [](json& g) {
             g["extensionsUsed"] = {"KHR_lights_punctual"};
             g["extensions"]["KHR_lights_punctual"]["lights"] =
                 json::array({{{"type", "spot"}, {"spot", {{"innerConeAngle", 0.6}, {"outerConeAngle", 0.5}}}}});
         },
         {"extensions.KHR_lights_punctual.lights[0].spot.innerConeAngle: must be less than outerConeAngle (0.5); it is 0.6"}},
        {"texture index as a string",
         [](json& g) { g["materials"][0]["pbrMetallicRoughness"]["baseColorTexture"] = {{"index", "0"}}; },
         {"materials[0].pbrMetallicRoughness.baseColorTexture.index: must be an integer in [0, 4294967295]; it is a string "
          "\"0\""}},
    };
    return cases;
}

TEST(GltfSchema, EachMalformedPropertyIsRefusedByNameInGltfAndGlb) {
    for (const Malformed& c : malformedFiles()) {
        SCOPED_TRACE(c.name);
        TinyGltf file;
        c.breakIt(file.gltf);
        for (const auto& path : {file.write(), file.writeGlb()}) {
            const std::string message = sceneErrorOf([&] { loadScene(path); });
            EXPECT_TRUE(contains(message, path.string() + ": malformed glTF: ")) << message;
            for (const std::string& mention : c.mentions) EXPECT_TRUE(contains(message, mention)) << message;
        }
    }
}

// The same file, well-formed, loads: the check refuses only what the schema forbids, and properties
// Janus does not read (extras, unknown extensions) are not checked.
TEST(GltfSchema, WellFormedFilesPass) {
    TinyGltf file;
    EXPECT_EQ(detail::gltfSchemaProblem(file.gltf), "");
    file.gltf["nodes"][0]["matrix"] = {1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1};
    file.gltf["samplers"] = json::array({{{"magFilter", 9729}, {"minFilter", 9987}, {"wrapS", 33648}, {"wrapT", 10497}}});
    file.gltf["nodes"][0]["extras"] = {{"anything", "goes"}};
    file.gltf["materials"][0]["extensions"]["VENDOR_unknown"] = {{"scale", "not checked"}};
    file.gltf["asset"]["version"] = "2.1";   // a later 2.x is read as 2.0, as the specification says
    EXPECT_EQ(detail::gltfSchemaProblem(file.gltf), "");
    const Scene scene = loadScene(file.write());
    EXPECT_EQ(scene.meshes.size(), 1u);
}

}  // namespace
}  // namespace janus::renderer
