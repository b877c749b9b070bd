// The glTF 2.0 schema checks of gltf_schema.h, property by property as the specification's JSON
// schema gives them (https://registry.khronos.org/glTF/specs/2.0/glTF-2.0.html, "Properties
// Reference"). Only what the schema states is checked; what a valid file may still get wrong (an
// index past the end of its array, a buffer view outside its buffer) is left to the loader, which
// names those problems itself.
#include "scene/gltf_schema.h"

#include <fmt/format.h>

#include <cmath>
#include <cstdint>
#include <initializer_list>
#include <string_view>
#include <utility>

namespace janus::renderer::detail {
namespace {

using nlohmann::json;

struct Problem {
    std::string text;
};

const char* typeName(const json& value) {
    switch (value.type()) {
        case json::value_t::null: return "null";
        case json::value_t::boolean: return "a boolean";
        case json::value_t::string: return "a string";
        case json::value_t::array: return "an array";
        case json::value_t::object: return "an object";
        case json::value_t::discarded: return "invalid";
        default: return "a number";
    }
}

// A value in a message: numbers and short strings as written, longer things by their type.
std::string shown(const json& value) {
    if (value.is_number() || value.is_boolean()) return value.dump();
    if (value.is_string() && value.get_ref<const std::string&>().size() <= 40) return fmt::format("{} {}", typeName(value), value.dump());
    return typeName(value);
}

bool isInteger(const json& value) {
    if (value.is_number_integer()) return true;
    if (!value.is_number_float()) return false;
    const double d = value.get<double>();
    return std::isfinite(d) && d == std::floor(d) && std::fabs(d) < 9.0e15;   // 44.0 is 44
}

int64_t integerOf(const json& value) {
    if (value.is_number_unsigned()) return value.get<uint64_t>() > uint64_t(INT64_MAX) ? INT64_MAX : int64_t(value.get<uint64_t>());
    if (value.is_number_integer()) return value.get<int64_t>();
    return int64_t(value.get<double>());
}

// One object of the file and where it is ("materials[0].pbrMetallicRoughness").
class At {
public:
    At(const json& value, std::string where) : m_value(value), m_where(std::move(where)) {}

    [[noreturn]] void fail(std::string_view key, const std::string& what) const {
        throw Problem{fmt::format("{}{}{}: {}", m_where, m_where.empty() ? "" : ".", key, what)};
    }
    const json* find(const char* key) const {
        auto it = m_value.find(key);
        return it == m_value.end() ? nullptr : &*it;
    }
    std::string path(const char* key) const { return m_where.empty() ? key : fmt::format("{}.{}", m_where, key); }
    const std::string& where() const { return m_where; }

    // An optional object member, checked to be an object.
    const json* object(const char* key) const {
        const json* value = find(key);
        if (value && !value->is_object()) fail(key, fmt::format("must be an object; it is {}", shown(*value)));
        return value;
    }
    // An optional array member whose elements are all objects, each checked by `each`.
    template <class Each>
    void objects(const char* key, Each&& each) const {
        const json* value = find(key);
        if (!value) return;
        if (!value->is_array()) fail(key, fmt::format("must be an array of objects; it is {}", shown(*value)));
        for (size_t i = 0; i < value->size(); ++i) {
            const std::string where = fmt::format("{}[{}]", path(key), i);
            if (!(*value)[i].is_object()) throw Problem{fmt::format("{}: must be an object; it is {}", where, shown((*value)[i]))};
            each(At((*value)[i], where));
        }
    }
    void integer(const char* key, int64_t min, int64_t max = INT64_MAX, bool required = false) const {
        const json* value = find(key);
        if (!value) {
            if (required) fail(key, "is required and missing");
            return;
        }
        const std::string range = max == INT64_MAX ? fmt::format(">= {}", min) : fmt::format("in [{}, {}]", min, max);
        if (!isInteger(*value)) fail(key, fmt::format("must be an integer {}; it is {}", range, shown(*value)));
        const int64_t v = integerOf(*value);
        if (v < min || v > max) fail(key, fmt::format("must be an integer {}; it is {}", range, shown(*value)));
    }
    // An index into another array (the loader checks that it lies inside it).
    void index(const char* key, bool required = false) const { integer(key, 0, UINT32_MAX, required); }
    void indices(const char* key) const {
        const json* value = find(key);
        if (!value) return;
        if (!value->is_array()) fail(key, fmt::format("must be an array of indices; it is {}", shown(*value)));
        for (size_t i = 0; i < value->size(); ++i)
            if (!isInteger((*value)[i]) || integerOf((*value)[i]) < 0 || integerOf((*value)[i]) > int64_t(UINT32_MAX))
                fail(fmt::format("{}[{}]", key, i), fmt::format("must be an index (an integer >= 0); it is {}", shown((*value)[i])));
    }
    void oneOf(const char* key, std::initializer_list<std::pair<int64_t, const char*>> values) const {
        const json* value = find(key);
        if (!value) return;
        if (isInteger(*value))
            for (const auto& [v, name] : values)
                if (integerOf(*value) == v) return;
        std::string allowed;
        for (const auto& [v, name] : values) allowed += fmt::format("{}{} ({})", allowed.empty() ? "" : ", ", v, name);
        fail(key, fmt::format("must be one of {}; it is {}", allowed, shown(*value)));
    }
    void oneOfStrings(const char* key, std::initializer_list<const char*> values, bool required = false) const {
        const json* value = find(key);
        if (!value) {
            if (required) fail(key, "is required and missing");
            return;
        }
        if (value->is_string())
            for (const char* v : values)
                if (value->get_ref<const std::string&>() == v) return;
        std::string allowed;
        for (const char* v : values) allowed += fmt::format("{}\"{}\"", allowed.empty() ? "" : ", ", v);
        fail(key, fmt::format("must be one of {}; it is {}", allowed, shown(*value)));
    }
    void number(const char* key, double min = -HUGE_VAL, double max = HUGE_VAL) const {
        const json* value = find(key);
        if (!value) return;
        if (!value->is_number()) fail(key, fmt::format("must be a number; it is {}", shown(*value)));
        const double v = value->get<double>();
        if (v < min || v > max) {
            const std::string range = max == HUGE_VAL ? fmt::format(">= {}", min) : fmt::format("in [{}, {}]", min, max);
            fail(key, fmt::format("must be a number {}; it is {}", range, shown(*value)));
        }
    }
    // An array of numbers: exactly `count` of them, or at least one when count is 0.
    void numbers(const char* key, size_t count) const {
        const json* value = find(key);
        if (!value) return;
        const std::string want = count ? fmt::format("an array of {} numbers", count) : std::string("an array of numbers");
        if (!value->is_array()) fail(key, fmt::format("must be {}; it is {}", want, shown(*value)));
        if (count && value->size() != count) fail(key, fmt::format("must be {}; it has {}", want, value->size()));
        for (size_t i = 0; i < value->size(); ++i)
            if (!(*value)[i].is_number()) fail(key, fmt::format("must be {}; element {} is {}", want, i, shown((*value)[i])));
    }
    void boolean(const char* key) const {
        const json* value = find(key);
        if (value && !value->is_boolean()) fail(key, fmt::format("must be true or false; it is {}", shown(*value)));
    }
    void string(const char* key) const {
        const json* value = find(key);
        if (value && !value->is_string()) fail(key, fmt::format("must be a string; it is {}", shown(*value)));
    }
    void strings(const char* key) const {
        const json* value = find(key);
        if (!value) return;
        if (!value->is_array()) fail(key, fmt::format("must be an array of strings; it is {}", shown(*value)));
        for (size_t i = 0; i < value->size(); ++i)
            if (!(*value)[i].is_string()) fail(key, fmt::format("must be an array of strings; element {} is {}", i, shown((*value)[i])));
    }
    // A textureInfo (and the normal and occlusion kinds' extra factor).
    void textureInfo(const char* key, const char* factor = nullptr) const {
        if (const json* info = object(key)) {
            At texture(*info, path(key));
            texture.index("index", true);
            texture.index("texCoord");
            if (factor) texture.number(factor);
        }
    }

private:
    const json& m_value;
    std::string m_where;
};

void checkAccessor(const At& a) {
    a.index("bufferView");
    a.integer("byteOffset", 0);
    a.oneOf("componentType", {{5120, "BYTE"}, {5121, "UNSIGNED_BYTE"}, {5122, "SHORT"}, {5123, "UNSIGNED_SHORT"},
                              {5125, "UNSIGNED_INT"}, {5126, "FLOAT"}});
    a.boolean("normalized");
    a.integer("count", 1);
    a.oneOfStrings("type", {"SCALAR", "VEC2", "VEC3", "VEC4", "MAT2", "MAT3", "MAT4"});
    a.numbers("max", 0);
    a.numbers("min", 0);
    if (const json* sparse = a.object("sparse")) {
        At s(*sparse, a.path("sparse"));
        s.integer("count", 1, INT64_MAX, true);
        if (const json* indices = s.object("indices")) {
            At i(*indices, s.path("indices"));
            i.index("bufferView", true);
            i.integer("byteOffset", 0);
        }
        if (const json* values = s.object("values")) {
            At v(*values, s.path("values"));
            v.index("bufferView", true);
            v.integer("byteOffset", 0);
        }
    }
}

void checkMaterial(const At& m) {
    if (const json* pbr = m.object("pbrMetallicRoughness")) {
        At p(*pbr, m.path("pbrMetallicRoughness"));
        p.numbers("baseColorFactor", 4);
        p.textureInfo("baseColorTexture");
        p.number("metallicFactor");
        p.number("roughnessFactor");
        p.textureInfo("metallicRoughnessTexture");
    }
    m.textureInfo("normalTexture", "scale");
    m.textureInfo("occlusionTexture", "strength");
    m.textureInfo("emissiveTexture");
    m.numbers("emissiveFactor", 3);
    m.oneOfStrings("alphaMode", {"OPAQUE", "MASK", "BLEND"});
    m.number("alphaCutoff", 0.0);
    m.boolean("doubleSided");
}

void checkMesh(const At& mesh) {
    if (!mesh.find("primitives")) mesh.fail("primitives", "is required and missing (a mesh has at least one primitive)");
    mesh.objects("primitives", [](const At& p) {
        if (const json* attributes = p.object("attributes")) {
            At a(*attributes, p.path("attributes"));
            for (const auto& [name, value] : attributes->items()) a.index(name.c_str());
        } else {
            p.fail("attributes", "is required and missing");
        }
        p.index("indices");
        p.index("material");
        // A negative mode tinygltf takes as absent (triangles); the loader names the mesh for one
        // above 6. Worded as the loader words that.
        if (const json* mode = p.find("mode"); mode && (!isInteger(*mode) || integerOf(*mode) < 0))
            throw Problem{fmt::format("{} has mode {}; glTF primitive modes are 0 (POINTS) to 6 (TRIANGLE_FAN)", p.where(), shown(*mode))};
        p.objects("targets", [](const At& target) {
            for (const char* key : {"POSITION", "NORMAL", "TANGENT"}) target.index(key);
        });
    });
    mesh.numbers("weights", 0);
}

void checkNode(const At& n) {
    n.index("camera");
    n.indices("children");
    n.index("skin");
    n.numbers("matrix", 16);
    n.index("mesh");
    n.numbers("rotation", 4);
    n.numbers("scale", 3);
    n.numbers("translation", 3);
    n.numbers("weights", 0);
    if (const json* extensions = n.object("extensions"))
        if (const json* light = At(*extensions, n.path("extensions")).object("KHR_lights_punctual"))
            At(*light, n.path("extensions.KHR_lights_punctual")).index("light", true);
}

void checkCamera(const At& c) {
    c.oneOfStrings("type", {"perspective", "orthographic"}, true);
    if (const json* perspective = c.object("perspective")) {
        At p(*perspective, c.path("perspective"));
        p.number("aspectRatio");
        p.number("yfov");
        p.number("zfar");
        p.number("znear");
    }
    if (const json* orthographic = c.object("orthographic")) {
        At o(*orthographic, c.path("orthographic"));
        for (const char* key : {"xmag", "ymag", "zfar", "znear"}) o.number(key);
    }
}

void checkAnimation(const At& a) {
    a.objects("channels", [](const At& c) {
        c.index("sampler", true);
        if (const json* target = c.object("target")) {
            At t(*target, c.path("target"));
            t.index("node");
            t.string("path");
        } else {
            c.fail("target", "is required and missing");
        }
    });
    a.objects("samplers", [](const At& s) {
        s.index("input", true);
        s.index("output", true);   // the loader names a bad interpolation with its animation
    });
}

void checkRoot(const json& root) {
    if (!root.is_object()) throw Problem{fmt::format("the glTF JSON must be an object; it is {}", shown(root))};
    const At r(root, "");
    const json* asset = r.object("asset");
    if (!asset) r.fail("asset", "is required and missing (a glTF 2.0 file has \"asset\": {\"version\": \"2.0\"})");
    const At a(*asset, "asset");
    const json* version = a.find("version");
    if (!version) a.fail("version", "is required and missing (glTF 2.0 files say \"2.0\")");
    if (!version->is_string()) a.fail("version", fmt::format("must be a string such as \"2.0\"; it is {}", shown(*version)));
    const std::string& v = version->get_ref<const std::string&>();
    if (v.rfind("2.", 0) != 0)
        a.fail("version", fmt::format("is \"{}\"; Janus reads glTF 2.0 (convert a glTF 1.0 file to 2.0 first, e.g. with the "
                                      "Khronos glTF-Pipeline or Blender)",
                                      v));
    r.strings("extensionsUsed");
    r.strings("extensionsRequired");
    r.index("scene");

    r.objects("accessors", checkAccessor);
    r.objects("animations", checkAnimation);
    r.objects("buffers", [](const At& b) {
        b.string("uri");
        b.integer("byteLength", 1, INT64_MAX, true);
    });
    r.objects("bufferViews", [](const At& v) {
        v.index("buffer", true);
        v.integer("byteOffset", 0);
        v.integer("byteLength", 1, INT64_MAX, true);
        v.integer("byteStride", 4, 252);
        v.oneOf("target", {{34962, "ARRAY_BUFFER"}, {34963, "ELEMENT_ARRAY_BUFFER"}});
    });
    r.objects("cameras", checkCamera);
    r.objects("images", [](const At& i) {
        i.string("uri");
        i.string("mimeType");
        i.index("bufferView");
    });
    r.objects("materials", checkMaterial);
    r.objects("meshes", checkMesh);
    r.objects("nodes", checkNode);
    r.objects("samplers", [](const At& s) {
        s.oneOf("magFilter", {{9728, "NEAREST"}, {9729, "LINEAR"}});
        s.oneOf("minFilter", {{9728, "NEAREST"}, {9729, "LINEAR"}, {9984, "NEAREST_MIPMAP_NEAREST"},
                              {9985, "LINEAR_MIPMAP_NEAREST"}, {9986, "NEAREST_MIPMAP_LINEAR"}, {9987, "LINEAR_MIPMAP_LINEAR"}});
        for (const char* wrap : {"wrapS", "wrapT"})
            s.oneOf(wrap, {{33071, "CLAMP_TO_EDGE"}, {33648, "MIRRORED_REPEAT"}, {10497, "REPEAT"}});
    });
    r.objects("scenes", [](const At& s) { s.indices("nodes"); });
    r.objects("skins", [](const At& s) {
        s.index("inverseBindMatrices");
        s.index("skeleton");
        if (!s.find("joints")) s.fail("joints", "is required and missing");
        s.indices("joints");
    });
    r.objects("textures", [](const At& t) {
        t.index("sampler");
        t.index("source");
    });
    if (const json* extensions = r.object("extensions"))
        if (const json* lights = At(*extensions, "extensions").object("KHR_lights_punctual"))
            At(*lights, "extensions.KHR_lights_punctual").objects("lights", [](const At& l) {
                l.oneOfStrings("type", {"directional", "point", "spot"}, true);
                l.numbers("color", 3);
                l.number("intensity");
                l.number("range");
                if (const json* spot = l.object("spot")) {
                    // The extension's schema and text: 0 <= innerConeAngle < outerConeAngle <= pi / 2.
                    At s(*spot, l.path("spot"));
                    constexpr double kHalfPi = 1.57079632679489661923;
                    s.number("innerConeAngle", 0.0, kHalfPi);
                    s.number("outerConeAngle", 0.0, kHalfPi);
                    const double inner = s.find("innerConeAngle") ? s.find("innerConeAngle")->get<double>() : 0.0;
                    const double outer = s.find("outerConeAngle") ? s.find("outerConeAngle")->get<double>() : kHalfPi / 2.0;
                    if (!(inner < outer))
                        s.fail("innerConeAngle", fmt::format("must be less than outerConeAngle ({}); it is {}", outer, inner));
                }
            });
}

}  // namespace

std::string gltfSchemaProblem(const json& root) {
    try {
        checkRoot(root);
    } catch (const Problem& problem) {
        return problem.text;
    }
    return {};
}

}  // namespace janus::renderer::detail
