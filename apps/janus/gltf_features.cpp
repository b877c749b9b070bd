#include "gltf_features.h"

#include <array>
#include <cctype>
#include <optional>
#include <cstdint>
#include <cstring>
#include <fstream>

#include <fmt/format.h>

namespace janus::cli {
namespace {

using nlohmann::json;

// Lookups that tolerate any shape: a malformed file (a number where an array belongs) reads as
// "not used", never as an exception; the loader reports what is wrong with it.
const json& member(const json& object, const char* key) {
    static const json kNull;
    if (!object.is_object()) return kNull;
    const auto it = object.find(key);
    return it == object.end() ? kNull : *it;
}

const json& arrayAt(const json& object, const char* key) {
    static const json kEmpty = json::array();
    const json& value = member(object, key);
    return value.is_array() ? value : kEmpty;
}

bool nonEmptyArray(const json& root, const char* key) { return !arrayAt(root, key).empty(); }

template <typename Predicate>
bool anyElement(const json& root, const char* key, Predicate predicate) {
    for (const json& element : arrayAt(root, key))
        if (predicate(element)) return true;
    return false;
}

template <typename Predicate>
bool anyPrimitive(const json& root, Predicate predicate) {
    return anyElement(root, "meshes", [&](const json& mesh) { return anyElement(mesh, "primitives", predicate); });
}

bool hasAttribute(const json& primitive, const char* name) {
    const json& attributes = member(primitive, "attributes");
    return attributes.is_object() && attributes.contains(name);
}

// glTF primitive.mode; absent means 4 (TRIANGLES).
template <int Mode>
bool usesMode(const json& root) {
    return anyPrimitive(root, [](const json& primitive) {
        const json& mode = member(primitive, "mode");
        return mode.is_number_integer() && mode.get<int64_t>() == Mode;
    });
}

template <const char* Attribute>
bool usesAttribute(const json& root) {
    return anyPrimitive(root, [](const json& primitive) { return hasAttribute(primitive, Attribute); });
}

// TEXCOORD_n with n >= 2: more UV sets than TEXCOORD_0 and TEXCOORD_1.
bool usesExtraTexcoords(const json& root) {
    return anyPrimitive(root, [](const json& primitive) {
        const json& attributes = member(primitive, "attributes");
        if (!attributes.is_object()) return false;
        for (const auto& [name, value] : attributes.items()) {
            constexpr std::string_view prefix = "TEXCOORD_";
            if (name.size() > prefix.size() && name.compare(0, prefix.size(), prefix) == 0 && name.substr(prefix.size()) != "0" &&
                name.substr(prefix.size()) != "1")
                return true;
        }
        return false;
    });
}

template <const char* Type>
bool usesCamera(const json& root) {
    return anyElement(root, "cameras", [](const json& camera) { return member(camera, "type") == Type; });
}

template <const char* Mode>
bool usesAlphaMode(const json& root) {
    return anyElement(root, "materials", [](const json& material) { return member(material, "alphaMode") == Mode; });
}

constexpr char kColor0[] = "COLOR_0";
constexpr char kTexcoord1[] = "TEXCOORD_1";
constexpr char kTangent[] = "TANGENT";
constexpr char kJoints1[] = "JOINTS_1";
constexpr char kPerspective[] = "perspective";
constexpr char kOrthographic[] = "orthographic";
constexpr char kBlend[] = "BLEND";
constexpr char kMask[] = "MASK";

// The table: add a row to detect one more feature (and say what it means).
const std::array kFeatures = {
    GltfFeature{"multiple-scenes", "more than one entry in scenes", [](const json& r) { return arrayAt(r, "scenes").size() > 1; }},
    GltfFeature{"perspective-camera", "a perspective camera", &usesCamera<kPerspective>},
    GltfFeature{"orthographic-camera", "an orthographic camera", &usesCamera<kOrthographic>},
    GltfFeature{"skins", "skinned meshes (skins, joints, inverse bind matrices)", [](const json& r) { return nonEmptyArray(r, "skins"); }},
    GltfFeature{"animations", "animations (samplers and channels)", [](const json& r) { return nonEmptyArray(r, "animations"); }},
    GltfFeature{"morph-targets", "a primitive with morph targets",
                [](const json& r) {
                    return anyPrimitive(r, [](const json& p) { return !arrayAt(p, "targets").empty(); });
                }},
    GltfFeature{"sparse-accessors", "an accessor with sparse storage",
                [](const json& r) { return anyElement(r, "accessors", [](const json& a) { return member(a, "sparse").is_object(); }); }},
    GltfFeature{"points", "a primitive of mode 0 (POINTS)", &usesMode<0>},
    GltfFeature{"lines", "a primitive of mode 1 (LINES)", &usesMode<1>},
    GltfFeature{"line-loop", "a primitive of mode 2 (LINE_LOOP)", &usesMode<2>},
    GltfFeature{"line-strip", "a primitive of mode 3 (LINE_STRIP)", &usesMode<3>},
    GltfFeature{"triangle-strip", "a primitive of mode 5 (TRIANGLE_STRIP)", &usesMode<5>},
    GltfFeature{"triangle-fan", "a primitive of mode 6 (TRIANGLE_FAN)", &usesMode<6>},
    GltfFeature{"COLOR_0", "vertex colours", &usesAttribute<kColor0>},
    GltfFeature{"TEXCOORD_1", "a second UV set", &usesAttribute<kTexcoord1>},
    GltfFeature{"TEXCOORD_2+", "a third or later UV set", &usesExtraTexcoords},
    GltfFeature{"TANGENT", "vertex tangents", &usesAttribute<kTangent>},
    GltfFeature{"JOINTS_1", "a second set of joint influences (more than 4 per vertex)", &usesAttribute<kJoints1>},
    GltfFeature{"textures", "textures", [](const json& r) { return nonEmptyArray(r, "textures"); }},
    GltfFeature{"alpha-mask", "a material with alphaMode MASK", &usesAlphaMode<kMask>},
    GltfFeature{"alpha-blend", "a material with alphaMode BLEND", &usesAlphaMode<kBlend>},
    GltfFeature{"double-sided", "a double-sided material",
                [](const json& r) { return anyElement(r, "materials", [](const json& m) { return member(m, "doubleSided") == true; }); }},
    GltfFeature{"byte-stride", "a buffer view with byteStride (interleaved or padded vertices)",
                [](const json& r) { return anyElement(r, "bufferViews", [](const json& v) { return member(v, "byteStride").is_number(); }); }},
};

std::vector<std::string> strings(const json& list) {
    std::vector<std::string> out;
    if (!list.is_array()) return out;
    for (const json& item : list)
        if (item.is_string()) out.push_back(item.get<std::string>());
    return out;
}

uint32_t readU32(const char* bytes) {
    uint32_t value;
    std::memcpy(&value, bytes, 4);   // glTF is little-endian, as is every platform janus builds for
    return value;
}

constexpr uint32_t kGlbHeaderBytes = 12;
constexpr uint32_t kChunkHeaderBytes = 8;
constexpr uint32_t kJsonChunkType = 0x4E4F534Au;   // "JSON"

GltfUsage failed(std::string error) {
    GltfUsage usage;
    usage.error = std::move(error);
    return usage;
}

}  // namespace

std::span<const GltfFeature> gltfFeatures() { return kFeatures; }

GltfUsage scanGltfJson(const nlohmann::json& root) {
    if (!root.is_object()) return failed("the glTF JSON is not an object");
    GltfUsage usage;
    usage.extensionsUsed = strings(member(root, "extensionsUsed"));
    usage.extensionsRequired = strings(member(root, "extensionsRequired"));
    for (const GltfFeature& feature : kFeatures)
        if (feature.used(root)) usage.features.emplace_back(feature.name);
    return usage;
}

namespace {

// The JSON text of a whole .gltf or of a .glb's JSON chunk; nullopt with `error` set otherwise.
std::optional<std::string_view> gltfJsonText(std::string_view bytes, std::string& error) {
    std::string_view text = bytes;
    if (bytes.size() >= 4 && std::memcmp(bytes.data(), "glTF", 4) == 0) {
        if (bytes.size() < kGlbHeaderBytes + kChunkHeaderBytes) return error = "the .glb is shorter than its header", std::nullopt;
        const uint32_t length = readU32(bytes.data() + kGlbHeaderBytes);
        if (readU32(bytes.data() + kGlbHeaderBytes + 4) != kJsonChunkType) return error = "the .glb's first chunk is not JSON", std::nullopt;
        if (uint64_t(kGlbHeaderBytes) + kChunkHeaderBytes + length > bytes.size())
            return error = "the .glb's JSON chunk runs past the end of the file", std::nullopt;
        text = bytes.substr(kGlbHeaderBytes + kChunkHeaderBytes, length);
    }
    return text;
}

// A .gltf whole, or a .glb's header and JSON chunk; nullopt with `error` when it cannot be read.
std::optional<std::string> readGltfHead(const std::filesystem::path& path, std::string& error) {
    std::ifstream in(path, std::ios::binary);
    if (!in) return error = fmt::format("cannot open '{}'", path.string()), std::nullopt;
    std::string bytes(kGlbHeaderBytes + kChunkHeaderBytes, '\0');
    in.read(bytes.data(), std::streamsize(bytes.size()));
    bytes.resize(size_t(in.gcount()));
    if (bytes.size() >= 4 && std::memcmp(bytes.data(), "glTF", 4) == 0) {
        // A .glb: read the JSON chunk only, not the (possibly large) binary chunk after it.
        if (bytes.size() == kGlbHeaderBytes + kChunkHeaderBytes) {
            std::error_code ec;
            const uint64_t fileSize = std::filesystem::file_size(path, ec);
            const uint64_t length = readU32(bytes.data() + kGlbHeaderBytes);
            if (!ec && bytes.size() + length <= fileSize) {
                const size_t header = bytes.size();
                bytes.resize(header + size_t(length));
                in.read(bytes.data() + header, std::streamsize(length));
                bytes.resize(header + size_t(in.gcount()));
            }
        }
    } else {
        bytes.append(std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>());
    }
    if (in.bad()) return error = fmt::format("cannot read '{}'", path.string()), std::nullopt;
    return bytes;
}

std::string percentDecoded(std::string_view uri) {
    std::string out;
    for (size_t i = 0; i < uri.size(); ++i) {
        if (uri[i] == '%' && i + 2 < uri.size() && std::isxdigit(static_cast<unsigned char>(uri[i + 1])) &&
            std::isxdigit(static_cast<unsigned char>(uri[i + 2]))) {
            out += char(std::stoi(std::string(uri.substr(i + 1, 2)), nullptr, 16));
            i += 2;
        } else {
            out += uri[i];
        }
    }
    return out;
}

}  // namespace

GltfUsage scanGltfUsage(std::string_view bytes) {
    std::string error;
    const std::optional<std::string_view> text = gltfJsonText(bytes, error);
    if (!text) return failed(error);
    const json root = json::parse(text->begin(), text->end(), nullptr, /*allow_exceptions=*/false);
    if (root.is_discarded()) return failed("the glTF JSON does not parse");
    return scanGltfJson(root);
}

GltfUsage scanGltfFile(const std::filesystem::path& path) {
    std::string error;
    const std::optional<std::string> bytes = readGltfHead(path, error);
    if (!bytes) return failed(error);
    return scanGltfUsage(*bytes);
}

std::vector<std::filesystem::path> gltfReferencedFiles(const std::filesystem::path& path) {
    std::vector<std::filesystem::path> files;
    std::string error;
    const std::optional<std::string> bytes = readGltfHead(path, error);
    if (!bytes) return files;
    const std::optional<std::string_view> text = gltfJsonText(*bytes, error);
    if (!text) return files;
    const json root = json::parse(text->begin(), text->end(), nullptr, /*allow_exceptions=*/false);
    if (!root.is_object()) return files;
    for (const char* list : {"buffers", "images"}) {
        const json& items = member(root, list);
        if (!items.is_array()) continue;
        for (const json& item : items) {
            const json& uri = member(item, "uri");
            if (!uri.is_string()) continue;
            const std::string& text = uri.get_ref<const std::string&>();
            if (text.empty() || text.rfind("data:", 0) == 0) continue;
            files.push_back(path.parent_path() / percentDecoded(text));
        }
    }
    return files;
}

}  // namespace janus::cli
