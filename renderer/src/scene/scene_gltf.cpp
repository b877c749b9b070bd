// glTF 2.0 (.gltf / .glb) -> Scene, through Debian's libtinygltf (the .so carries the
// implementation and stb_image, so we only include the header).
#include <algorithm>
#include <array>
#include <cctype>
#include <cmath>
#include <cstring>
#include <fstream>
#include <map>
#include <memory>
#include <optional>
#include <string_view>
#include <tuple>
#include <vector>

#include <fmt/format.h>
#include <glm/gtc/matrix_transform.hpp>
#include <glm/gtc/quaternion.hpp>
#include <glm/gtc/type_ptr.hpp>
#define GLM_ENABLE_EXPERIMENTAL
#include <glm/gtx/matrix_decompose.hpp>
#include <nlohmann/json.hpp>
#include <stb/stb_image.h>
#include <tiny_gltf.h>
#include <turbojpeg.h>

#include "core/parallel.h"
#include "scene/gltf_schema.h"
#include "scene_internal.h"

namespace janus::renderer::detail {
namespace {

// The most one accessor may decode to. Sized for the largest assets we expect (a few million
// vertices) with room to spare; a count beyond it is a wrong or hostile file, refused before
// anything is allocated.
constexpr uint64_t kMaxAccessorBytes = uint64_t(1) << 30;

// The largest image a glTF may bring: at most this many pixels on a side and in all (64 Mi
// pixels, 256 MiB as RGBA8: an 8192x8192 texture fits). Checked from the image header before
// anything is decoded; a larger image is a SceneError.
constexpr int kMaxImageSide = 16384;
constexpr uint64_t kMaxImagePixels = uint64_t(1) << 26;

// The most joint matrices all skinned instances together may need (4 Mi matrices, 256 MiB): each
// skinned instance holds one per joint of its skin, so a few bytes of JSON (many nodes sharing a
// large skin) could otherwise ask for gigabytes.
constexpr uint64_t kMaxJointMatrices = uint64_t(1) << 22;

// glTF extensions the loader implements.
constexpr std::string_view kSupportedExtensions[] = {"KHR_lights_punctual",
                                                     "KHR_mesh_quantization",
                                                     "KHR_texture_transform",
                                                     "KHR_materials_emissive_strength",
                                                     "KHR_materials_unlit",
                                                     "KHR_materials_ior",
                                                     "KHR_materials_specular"};

bool isSupportedExtension(std::string_view name) {
    for (std::string_view supported : kSupportedExtensions)
        if (name == supported) return true;
    return false;
}

std::string supportedExtensionList() {
    std::string list;
    for (std::string_view supported : kSupportedExtensions) list += (list.empty() ? "" : ", ") + std::string(supported);
    return list;
}

// --- what a glTF may read: URIs, data: URIs, image sizes ---------------------------------------

// An image loadImage checked and sized, decoded once tinygltf's parse is done (decodeImages).
struct PendingImage {
    size_t index = 0;                  // in Model::images
    std::string label;                 // "image 3 ('albedo.jpg')"
    std::vector<unsigned char> bytes;  // the encoded file (tinygltf's copy of it does not outlive the callback)
    bool jpeg = false;
};

// What tinygltf's file-system callbacks and image loader share while one file loads.
struct LoadContext {
    std::filesystem::path folder;   // the glTF's folder, absolute and normalised
    std::string uriPrefix;          // how tinygltf joins that folder and a URI: folder + '/'
    bool allowOutside = false;      // SceneLoadOptions::allowPathsOutsideSceneFolder
    std::string refusal;            // the first URI or image refused (a SceneError message without the file)
    std::vector<PendingImage> pendingImages;

    void refuse(std::string why) {
        if (refusal.empty()) refusal = std::move(why);
    }
};

// A URI for a message: data: URIs can be megabytes long, so only their start is shown.
std::string shown(std::string_view uri) {
    constexpr size_t kShown = 48;
    return uri.size() <= kShown ? std::string(uri) : std::string(uri.substr(0, kShown)) + "...";
}

bool startsWithNoCase(std::string_view text, std::string_view prefix) {
    if (text.size() < prefix.size()) return false;
    for (size_t i = 0; i < prefix.size(); ++i)
        if (std::tolower(static_cast<unsigned char>(text[i])) != std::tolower(static_cast<unsigned char>(prefix[i]))) return false;
    return true;
}

// The URI's scheme ("http", "file", "data"), or "" for a path. RFC 3986: a letter, then letters,
// digits, '+', '-', '.', then ':'. One letter is a Windows drive ("C:"), not a scheme.
std::string schemeOf(std::string_view uri) {
    if (uri.empty() || !std::isalpha(static_cast<unsigned char>(uri[0]))) return {};
    for (size_t i = 1; i < uri.size(); ++i) {
        const char c = uri[i];
        if (c == ':') return i >= 2 ? std::string(uri.substr(0, i)) : std::string();
        if (!std::isalnum(static_cast<unsigned char>(c)) && c != '+' && c != '-' && c != '.') return {};
    }
    return {};
}

const char* const kAllowHint =
    "Janus reads buffers and images only from the glTF's folder and the folders below it; if you trust the file, allow "
    "it with SceneLoadOptions::allowPathsOutsideSceneFolder (janus: --allow-outside-paths)";

// Why the file-path URI `uri` (already percent-decoded) may not be read, or "" when it may. The
// rule is lexical: ".." and absolute paths are refused, symbolic links are not looked at.
std::string pathUriProblem(std::string_view uri, const LoadContext& context) {
    if (uri.empty()) return {};
    if (startsWithNoCase(uri, "data:"))
        return fmt::format("'{}' is a data: URI Janus cannot decode (see the base64 data: URI rules in docs/SCENES.md)", shown(uri));
    if (const std::string scheme = schemeOf(uri); !scheme.empty())
        return fmt::format("URI '{}' uses the '{}:' scheme; Janus reads relative file paths and base64 data: URIs only", shown(uri),
                           scheme);
    if (context.allowOutside) return {};
    const std::filesystem::path path(uri);
    if (path.has_root_path() || uri.front() == '/' || uri.front() == '\\')
        return fmt::format("URI '{}' is an absolute path; {}", uri, kAllowHint);
    const std::filesystem::path relative = (context.folder / path).lexically_normal().lexically_relative(context.folder);
    if (relative.empty() || *relative.begin() == "..")
        return fmt::format("URI '{}' leaves the glTF's folder '{}'; {}", uri, context.folder.string(), kAllowHint);
    return {};
}

// tinygltf looks a file up as ExpandFilePath(JoinPath(dir, uri)) for dir = the glTF's folder,
// then the working directory. This applies the URI rule to the first and never searches the
// second; the path it returns (empty: refused) is what FileExists and ReadWholeFile get.
std::string expandFilePath(const std::string& joined, void* user) {
    LoadContext& context = *static_cast<LoadContext*>(user);
    if (joined.compare(0, context.uriPrefix.size(), context.uriPrefix) != 0) return {};   // the working directory
    const std::string uri = joined.substr(context.uriPrefix.size());
    if (std::string problem = pathUriProblem(uri, context); !problem.empty()) {
        context.refuse(std::move(problem));
        return {};
    }
    const std::filesystem::path path(uri);
    return (path.has_root_path() ? path : context.folder / path).lexically_normal().string();
}

bool fileExists(const std::string& path, void*) {
    std::error_code ec;
    return !path.empty() && std::filesystem::is_regular_file(path, ec);   // not directories, devices or pipes
}

// Why the data: URI `uri` cannot be decoded, or "" when tinygltf will decode it exactly.
// `byteLength` is the buffer's (buffers must decode to exactly that many bytes); none for images.
std::string dataUriProblem(std::string_view uri, std::optional<uint64_t> byteLength) {
    // The headers tinygltf decodes (tinygltf::IsDataURI), each followed by the base64 data.
    static constexpr std::string_view kHeaders[] = {
        "data:application/octet-stream;base64,", "data:application/gltf-buffer;base64,", "data:image/png;base64,",
        "data:image/jpeg;base64,",                "data:image/bmp;base64,",               "data:image/gif;base64,",
        "data:text/plain;base64,"};
    const size_t comma = uri.find(',');
    if (comma == std::string_view::npos) return fmt::format("data: URI '{}' has no ',' before its data", shown(uri));
    const std::string_view header = uri.substr(0, comma + 1);
    if (header.size() < 8 || !startsWithNoCase(header.substr(header.size() - 8), ";base64,"))
        return fmt::format("data: URI '{}' is not base64-encoded; Janus decodes only ';base64,' data: URIs", shown(uri));
    if (std::find(std::begin(kHeaders), std::end(kHeaders), header) == std::end(kHeaders))
        return fmt::format("data: URI '{}' has media type '{}', which Janus does not decode; use application/octet-stream or "
                           "application/gltf-buffer for buffers, image/png or image/jpeg for images",
                           shown(uri), header.substr(5, header.size() - 13));
    const std::string_view data = uri.substr(comma + 1);
    size_t padding = 0;
    for (size_t i = 0; i < data.size(); ++i) {
        const unsigned char c = static_cast<unsigned char>(data[i]);
        if (c == '=' && i + 2 >= data.size()) {
            ++padding;
            continue;
        }
        if (padding > 0 || !(std::isalnum(c) || c == '+' || c == '/'))
            return fmt::format("data: URI '{}' is not valid base64: {} at offset {} of its data", shown(uri),
                               std::isprint(c) ? fmt::format("character '{}'", char(c)) : fmt::format("byte 0x{:02x}", c), i);
    }
    if (data.empty()) return fmt::format("data: URI '{}' holds no data", shown(uri));
    if (data.size() % 4 != 0)
        return fmt::format("data: URI '{}' is not valid base64: {} characters of data, not a multiple of 4 (padding missing or data "
                           "cut short)",
                           shown(uri), data.size());
    const uint64_t decoded = data.size() / 4 * 3 - padding;
    if (byteLength && decoded != *byteLength)
        return fmt::format("data: URI '{}' decodes to {} bytes, but the buffer's byteLength is {}", shown(uri), decoded, *byteLength);
    return {};
}

// The JSON of a .glb (its first chunk), or nothing when the header is not one: tinygltf then
// reports what is wrong.
std::optional<std::string_view> glbJson(std::string_view bytes) {
    auto u32 = [&](size_t at) {
        uint32_t v;
        std::memcpy(&v, bytes.data() + at, 4);
        return v;
    };
    if (bytes.size() < 20 || std::memcmp(bytes.data(), "glTF", 4) != 0 || u32(16) != 0x4E4F534Au) return std::nullopt;
    const uint64_t length = u32(12);
    if (20 + length > bytes.size()) return std::nullopt;
    return std::string_view(bytes.data() + 20, size_t(length));
}

// A non-negative integer member (also written as 44.0), or nothing.
std::optional<uint64_t> unsignedAt(const nlohmann::json& object, const char* key) {
    if (!object.is_object() || !object.contains(key)) return std::nullopt;
    const nlohmann::json& value = object[key];
    if (value.is_number_unsigned()) return value.get<uint64_t>();
    if (value.is_number_float()) {
        const double d = value.get<double>();
        if (d >= 0.0 && d < 1.8e19 && d == std::floor(d)) return uint64_t(d);
    }
    return std::nullopt;
}

// Checks what tinygltf would read before it reads anything, so each problem is refused by name:
// every buffer and image URI (path rule, data: URIs) and the bytes of images stored in buffer
// views (tinygltf does not bounds-check them). A JSON that does not parse is left to tinygltf.
void checkReferences(const nlohmann::json& root, LoadContext& context) {
    if (!root.is_object()) return;
    auto array = [&](const char* key) -> const nlohmann::json& {
        static const nlohmann::json empty = nlohmann::json::array();
        return root.contains(key) && root[key].is_array() ? root[key] : empty;
    };
    const nlohmann::json& buffers = array("buffers");
    const nlohmann::json& views = array("bufferViews");
    auto checkUri = [&](const nlohmann::json& object, const std::string& what, std::optional<uint64_t> byteLength) {
        if (!object.is_object() || !object.contains("uri") || !object["uri"].is_string()) return;
        const std::string& uri = object["uri"].get_ref<const std::string&>();
        std::string problem = startsWithNoCase(uri, "data:") ? dataUriProblem(uri, byteLength) : pathUriProblem(uri, context);
        if (!problem.empty()) context.refuse(fmt::format("{}: {}", what, problem));
    };
    for (size_t i = 0; i < buffers.size(); ++i) checkUri(buffers[i], fmt::format("buffer {}", i), unsignedAt(buffers[i], "byteLength"));
    const nlohmann::json& images = array("images");
    for (size_t i = 0; i < images.size(); ++i) {
        const nlohmann::json& image = images[i];
        checkUri(image, fmt::format("image {}", i), std::nullopt);
        if (!image.is_object() || !image.contains("bufferView")) continue;
        const uint64_t view = unsignedAt(image, "bufferView").value_or(UINT64_MAX);
        if (view >= views.size()) continue;   // tinygltf names it
        const uint64_t buffer = unsignedAt(views[size_t(view)], "buffer").value_or(UINT64_MAX);
        const uint64_t offset = unsignedAt(views[size_t(view)], "byteOffset").value_or(0);
        const uint64_t length = unsignedAt(views[size_t(view)], "byteLength").value_or(0);
        uint64_t end = 0;
        if (buffer >= buffers.size() || __builtin_add_overflow(offset, length, &end) ||
            end > unsignedAt(buffers[size_t(buffer)], "byteLength").value_or(0) || length == 0 || length > uint64_t(INT32_MAX))
            context.refuse(fmt::format("image {}: its buffer view {} (byteOffset {}, byteLength {}, buffer {}) is empty or does not lie "
                                       "inside its buffer",
                                       i, view, offset, length, buffer));
    }
}

// glTF lets an animation channel's target have no node (KHR_animation_pointer targets a JSON
// pointer instead); tinygltf drops such channels without a word. One warning each (the file
// loads without them). Later channels of that animation are numbered as tinygltf keeps them.
std::vector<std::string> nodelessChannels(const nlohmann::json& root) {
    std::vector<std::string> warnings;
    if (!root.is_object() || !root.contains("animations") || !root["animations"].is_array()) return warnings;
    const nlohmann::json& animations = root["animations"];
    for (size_t a = 0; a < animations.size(); ++a) {
        const nlohmann::json& animation = animations[a];
        if (!animation.is_object() || !animation.contains("channels") || !animation["channels"].is_array()) continue;
        const nlohmann::json& channels = animation["channels"];
        for (size_t c = 0; c < channels.size(); ++c) {
            const nlohmann::json& channel = channels[c];
            if (!channel.is_object() || !channel.contains("target") || !channel["target"].is_object() || channel["target"].contains("node"))
                continue;
            const nlohmann::json& target = channel["target"];
            const std::string path = target.contains("path") && target["path"].is_string() ? target["path"].get<std::string>() : "";
            const std::string name = animation.contains("name") && animation["name"].is_string()
                                         ? fmt::format("animation {} ('{}')", a, animation["name"].get<std::string>())
                                         : fmt::format("animation {}", a);
            warnings.push_back(fmt::format("{} channel {}: ignoring a channel without a target node (path '{}'{}); Janus animates nodes' "
                                           "translation, rotation, scale and weights",
                                           name, c, path, path == "pointer" ? ", KHR_animation_pointer" : ""));
        }
    }
    return warnings;
}

bool isJpeg(const unsigned char* bytes, size_t size) { return size >= 3 && bytes[0] == 0xFF && bytes[1] == 0xD8 && bytes[2] == 0xFF; }

// Why a JPEG's Huffman tables are invalid, or "" when they are not: more than 256 codes, which
// JPEG forbids. Found by fuzzing when stb decoded JPEG (it wrote past its 257-entry arrays);
// libjpeg-turbo refuses such tables too, but this names the table and keeps the message the same.
// stb finds DHT segments between scans too, so the whole file is walked as stb reads it: segments
// by their length, entropy-coded data byte by byte up to the next marker. Where this walk and stb's
// could differ (stb stops at an unknown marker or a bad length), this one goes on: it checks every
// table stb could reach, and more.
std::string jpegHuffmanProblem(const unsigned char* bytes, size_t size) {
    size_t at = 2;   // after SOI
    while (at + 4 <= size) {
        if (bytes[at] != 0xFF || bytes[at + 1] == 0xFF) {   // data between markers, or fill bytes
            ++at;
            continue;
        }
        const unsigned marker = bytes[at + 1];
        if (marker == 0x00 || marker == 0x01 || (marker >= 0xD0 && marker <= 0xD9)) {   // stuffed 0, TEM, RSTn, SOI, EOI: no length
            at += 2;
            continue;
        }
        const size_t length = size_t(bytes[at + 2]) << 8 | bytes[at + 3];
        if (length < 2) return {};   // stb stops here
        if (marker == 0xC4) {
            // stb reads 0 past the end of the data, so a table cut short by the end of the file
            // still gets its counts, the missing ones as 0 (found by fuzzing: such a table was
            // skipped here and overflowed in stb).
            auto byteAt = [&](size_t i) -> size_t { return i < size ? bytes[i] : 0u; };
            size_t table = at + 4;
            for (size_t left = length - 2; left > 0 && table < size;) {
                if ((byteAt(table) >> 4) > 1 || (byteAt(table) & 15) > 3) break;   // stb refuses the table
                size_t codes = 0;
                for (size_t i = 1; i <= 16; ++i) codes += byteAt(table + i);
                if (codes > 256)
                    return fmt::format("its Huffman table at byte {} declares {} codes; JPEG allows at most 256 (the file is corrupt)",
                                       table, codes);
                if (17 + codes > left) break;
                left -= 17 + codes;
                table += 17 + codes;
            }
        }
        at += 2 + length;
    }
    return {};
}

// Why the image bytes must not be decoded, or "" when they may. glTF 2.0 textures are PNG (stb_image)
// or JPEG (libjpeg-turbo); stb would also decode GIF, BMP, PSD, TGA, PIC, PNM and Radiance files, decoders no glTF
// needs and whose versions in Debian's stb have known memory-safety bugs, so other formats are
// refused by their signature.
std::string textureBytesProblem(const unsigned char* bytes, size_t size) {
    static constexpr unsigned char kPng[8] = {0x89, 'P', 'N', 'G', '\r', '\n', 0x1A, '\n'};
    if (size >= 8 && std::memcmp(bytes, kPng, 8) == 0) return {};
    if (isJpeg(bytes, size)) return jpegHuffmanProblem(bytes, size);
    return "is neither a PNG nor a JPEG (glTF 2.0 textures are one or the other)";
}

// Refuses an image larger than Janus loads (kMaxImageSide / kMaxImagePixels), from the size in
// its header, before decoding it.
bool withinImageLimits(LoadContext& context, const std::string& label, int width, int height) {
    if (width <= kMaxImageSide && height <= kMaxImageSide && uint64_t(width) * uint64_t(height) <= kMaxImagePixels) return true;
    context.refuse(fmt::format("{} is {}x{} pixels, larger than Janus loads (at most {} on a side and {} Mi pixels in all); "
                               "scale it down",
                               label, width, height, kMaxImageSide, kMaxImagePixels >> 20));
    return false;
}

// JPEG textures are decoded by libjpeg-turbo, not stb_image: stb's JPEG decoder misbehaves on
// corrupt data in ways no check before it can catch (docs/TESTING.md, fuzzing findings 2, 3 and
// 7). A warning (data cut short, corrupt entropy-coded data) is an error too: libjpeg-turbo would
// otherwise fill what it could not decode with grey, a silently wrong texture.
using JpegDecoder = std::unique_ptr<void, int (*)(tjhandle)>;

JpegDecoder startJpegDecoder(const std::string& label, std::string& err) {
    JpegDecoder decoder(tjInitDecompress(), tjDestroy);
    if (!decoder) err += fmt::format("{} could not be decoded (libjpeg-turbo did not start: {})\n", label, tjGetErrorStr2(nullptr));
    return decoder;
}

// The size in the image's header; false (and why, in err) when there is none Janus can read.
bool imageSize(const std::string& label, const unsigned char* bytes, size_t size, bool jpeg, int& width, int& height,
               std::string& err) {
    if (jpeg) {
        const JpegDecoder decoder = startJpegDecoder(label, err);
        if (!decoder) return false;
        int subsampling = 0, colorspace = 0;
        if (tjDecompressHeader3(decoder.get(), bytes, static_cast<unsigned long>(size), &width, &height, &subsampling, &colorspace) != 0 ||
            width <= 0 || height <= 0) {
            err += fmt::format("{} is not a JPEG image Janus can decode ({})\n", label, tjGetErrorStr2(decoder.get()));
            return false;
        }
        return true;
    }
    int channels = 0;
    if (!stbi_info_from_memory(bytes, int(size), &width, &height, &channels)) {
        err += fmt::format("{} is not a PNG or JPEG image Janus can decode ({})\n", label, stbi_failure_reason());
        return false;
    }
    return true;
}

// One checked image to 8-bit RGBA (16-bit PNGs keep their high byte), JPEG with libjpeg-turbo,
// PNG with stb; `err` stays empty when it decodes. Safe to run for several images at once (stb's
// failure reason is per thread).
void decodeImage(tinygltf::Image& image, const PendingImage& pending, std::string& err) {
    const unsigned char* bytes = pending.bytes.data();
    const size_t size = pending.bytes.size();
    if (pending.jpeg) {
        const JpegDecoder decoder = startJpegDecoder(pending.label, err);
        if (!decoder) return;
        std::vector<unsigned char> rgba(size_t(image.width) * size_t(image.height) * 4);
        if (tjDecompress2(decoder.get(), bytes, static_cast<unsigned long>(size), rgba.data(), image.width, 0, image.height, TJPF_RGBA,
                          TJFLAG_STOPONWARNING) != 0) {
            err += fmt::format("{} could not be decoded ({})\n", pending.label, tjGetErrorStr2(decoder.get()));
            return;
        }
        image.image = std::move(rgba);
        return;
    }
    int width = 0, height = 0, channels = 0;
    stbi_uc* pixels = stbi_load_from_memory(bytes, int(size), &width, &height, &channels, 4);
    if (!pixels) {
        err += fmt::format("{} could not be decoded ({})\n", pending.label, stbi_failure_reason());
        return;
    }
    std::unique_ptr<stbi_uc, void (*)(void*)> owned(pixels, stbi_image_free);
    if (width != image.width || height != image.height) {   // the header said otherwise: not a file to trust
        err += fmt::format("{} decodes to {}x{} pixels but its header says {}x{}\n", pending.label, width, height, image.width,
                           image.height);
        return;
    }
    image.image.assign(pixels, pixels + size_t(width) * size_t(height) * 4);
}

// tinygltf's image loader: refuses what Janus does not decode (other formats, images beyond its
// limits) from the bytes and the header's size, before decoding anything, and leaves the decoding
// to decodeImages, after the parse, so that the images decode side by side.
bool loadImage(tinygltf::Image* image, const int index, std::string* err, std::string*, int, int, const unsigned char* bytes,
               int size, void* user) {
    LoadContext& context = *static_cast<LoadContext*>(user);
    const std::string label =
        fmt::format("image {} ('{}')", index, !image->uri.empty() ? shown(image->uri) : !image->name.empty() ? image->name : "embedded");
    const size_t byteCount = size_t(std::max(size, 0));
    if (std::string problem = textureBytesProblem(bytes, byteCount); !problem.empty()) {
        context.refuse(fmt::format("{} {}", label, problem));
        return false;
    }
    const bool jpeg = isJpeg(bytes, byteCount);
    int width = 0, height = 0;
    std::string why;
    if (!imageSize(label, bytes, byteCount, jpeg, width, height, why)) {
        if (err) *err += why;
        return false;
    }
    if (!withinImageLimits(context, label, width, height)) return false;
    image->width = width;
    image->height = height;
    image->component = 4;
    image->bits = 8;
    image->pixel_type = TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE;
    image->image.clear();
    context.pendingImages.push_back({size_t(index), label, std::vector<unsigned char>(bytes, bytes + byteCount), jpeg});
    return true;
}

// Decodes the images loadImage took, on every core. The first that fails, in image order, is the
// load's error, worded as when tinygltf reported it.
void decodeImages(LoadContext& context, tinygltf::Model& model, const std::filesystem::path& path) {
    std::vector<std::string> errors(context.pendingImages.size());
    parallelFor(errors.size(), parallelThreads(0, errors.size()), [&](size_t i) {
        const PendingImage& pending = context.pendingImages[i];
        decodeImage(model.images.at(pending.index), pending, errors[i]);
    });
    context.pendingImages.clear();
    for (std::string& reason : errors) {
        if (reason.empty()) continue;
        while (!reason.empty() && (reason.back() == '\n' || reason.back() == ' ')) reason.pop_back();
        throw SceneError(fmt::format("{}: malformed glTF: {}", path.string(), reason));
    }
}

// Everything the loader throws names the file, so errors from a scene file that references a
// glTF still point at the file that is wrong.
class GltfReader {
public:
    GltfReader(const std::filesystem::path& path, tinygltf::Model& model, const SceneLoadOptions& options)
        : m_path(path), m_model(model), m_options(options) {}

    [[noreturn]] void fail(const std::string& what) const {
        throw SceneError(fmt::format("{}: {}", m_path.string(), what));
    }

    Scene read(bool& hasCamera) {
        Scene scene;
        scene.name = m_path.stem().string();
        checkExtensions();
        checkImages();
        readMaterials(scene);
        readMeshes(scene);
        readSkins(scene);
        readNodes(scene);
        readHierarchy(scene);
        readAnimations(scene);
        scene.warnings = std::move(m_warnings);
        if (m_options.camera && !m_cameraFound) {
            if (*m_options.camera >= m_model.cameras.size())
                fail(fmt::format("camera {} does not exist: the file has {} camera(s)", *m_options.camera, m_model.cameras.size()));
            fail(fmt::format("camera {} ('{}') is used by no node of the loaded scene, so it has no place to look from", *m_options.camera,
                             m_model.cameras[*m_options.camera].name));
        }
        hasCamera = m_cameraFound;
        if (m_cameraFound) scene.camera = m_camera;
        // As glTF viewers show a file: at t = 0 of its first animation.
        try {
            poseScene(scene, 0.0f, scene.animations.empty() ? std::nullopt : std::optional<size_t>(0));
        } catch (const SceneError& e) {
            fail(e.what());
        }
        return scene;
    }

private:
    // A required extension we do not implement would render wrongly: refuse it by name. An
    // optional one we do not implement is ignored, with one warning each.
    void checkExtensions() {
        for (const std::string& name : m_model.extensionsRequired)
            if (!isSupportedExtension(name))
                fail(fmt::format("the file requires glTF extension '{}', which Janus does not implement (supported: {})", name,
                                 supportedExtensionList()));
        for (const std::string& name : m_model.extensionsUsed)
            if (!isSupportedExtension(name))
                warn(fmt::format("ignoring glTF extension '{}' (not implemented; the file does not require it)", name));
    }

    // One warning for the scene (Scene::warnings), naming the file; the same text is given once.
    void warn(const std::string& what) {
        const std::string line = fmt::format("{}: {}", m_path.string(), what);
        if (std::find(m_warnings.begin(), m_warnings.end(), line) == m_warnings.end()) m_warnings.push_back(line);
    }

    // tinygltf only warns about an image it could not read; a missing texture is an error here.
    void checkImages() const {
        for (size_t i = 0; i < m_model.images.size(); ++i) {
            const tinygltf::Image& image = m_model.images[i];
            if (image.image.empty() || image.width <= 0 || image.height <= 0) {
                fail(fmt::format("texture image {} ('{}') could not be read; check that the file exists next to the glTF "
                                 "and is a PNG or JPEG",
                                 i, image.uri.empty() ? image.name : image.uri));
            }
        }
    }

    int32_t textureFor(int gltfTexture, bool srgb, Scene& scene, const std::string& materialName) {
        if (gltfTexture < 0) return -1;
        if (size_t(gltfTexture) >= m_model.textures.size())
            fail(fmt::format("material '{}' references texture {} but the file has {}", materialName, gltfTexture,
                             m_model.textures.size()));
        const tinygltf::Texture& gltfTextureInfo = m_model.textures[size_t(gltfTexture)];
        const int source = gltfTextureInfo.source;
        if (source < 0 || size_t(source) >= m_model.images.size())
            fail(fmt::format("texture {} has no valid image source ({})", gltfTexture, source));
        const int sampler = gltfTextureInfo.sampler;
        if (sampler >= 0 && size_t(sampler) >= m_model.samplers.size())
            fail(fmt::format("texture {} references sampler {} but the file has {}", gltfTexture, sampler, m_model.samplers.size()));
        auto key = std::make_tuple(source, sampler, srgb);
        if (auto it = m_textureCache.find(key); it != m_textureCache.end()) return it->second;

        const tinygltf::Image& image = m_model.images[size_t(source)];
        TextureImage texture;
        texture.width = uint32_t(image.width);
        texture.height = uint32_t(image.height);
        texture.srgb = srgb;
        if (sampler >= 0) texture.sampling = samplingOf(m_model.samplers[size_t(sampler)]);
        texture.name = image.uri.empty() ? image.name : image.uri;
        const size_t pixels = size_t(image.width) * size_t(image.height);
        // The image loader (loadImage, decodeImage) gives every image as 8-bit RGBA; one without
        // that layout has no data (an external file tinygltf could not read).
        if (image.component != 4 || image.bits != 8 || image.image.size() != pixels * 4)
            fail(fmt::format("texture image '{}' has an unsupported layout ({} channels, {} bits)", texture.name,
                             image.component, image.bits));
        texture.rgba.assign(image.image.begin(), image.image.end());
        scene.textures.push_back(std::move(texture));
        const int32_t index = int32_t(scene.textures.size() - 1);
        m_textureCache[key] = index;
        return index;
    }

    static TextureSampling samplingOf(const tinygltf::Sampler& sampler) {
        auto wrap = [](int mode) {
            if (mode == TINYGLTF_TEXTURE_WRAP_CLAMP_TO_EDGE) return TextureWrap::ClampToEdge;
            if (mode == TINYGLTF_TEXTURE_WRAP_MIRRORED_REPEAT) return TextureWrap::MirroredRepeat;
            return TextureWrap::Repeat;
        };
        TextureSampling sampling;
        sampling.wrapU = wrap(sampler.wrapS);
        sampling.wrapV = wrap(sampler.wrapT);
        sampling.nearestMagnification = sampler.magFilter == TINYGLTF_TEXTURE_FILTER_NEAREST;
        switch (sampler.minFilter) {   // undefined (-1) keeps trilinear
            case TINYGLTF_TEXTURE_FILTER_NEAREST: sampling.nearestMinification = true; sampling.mipmapped = false; break;
            case TINYGLTF_TEXTURE_FILTER_LINEAR: sampling.mipmapped = false; break;
            case TINYGLTF_TEXTURE_FILTER_NEAREST_MIPMAP_NEAREST: sampling.nearestMinification = sampling.nearestMip = true; break;
            case TINYGLTF_TEXTURE_FILTER_LINEAR_MIPMAP_NEAREST: sampling.nearestMip = true; break;
            case TINYGLTF_TEXTURE_FILTER_NEAREST_MIPMAP_LINEAR: sampling.nearestMinification = true; break;
            default: break;
        }
        return sampling;
    }

    // A texture reference's UV set and KHR_texture_transform (whose texCoord, when given, replaces
    // the reference's). Janus reads TEXCOORD_0 and TEXCOORD_1: a higher set is refused by name
    // rather than sampled from the wrong coordinates.
    TextureTransform transformOf(int textureIndex, int texCoord, const tinygltf::ExtensionMap& extensions,
                                 const std::string& materialName, const char* texture) const {
        TextureTransform transform;
        if (textureIndex < 0) return transform;
        const std::string where = fmt::format("material '{}' {}", materialName, texture);
        int64_t set = texCoord;
        if (auto it = extensions.find("KHR_texture_transform"); it != extensions.end()) {
            const tinygltf::Value& extension = it->second;
            if (!extension.IsObject()) fail(fmt::format("{}: KHR_texture_transform is not an object", where));
            auto number = [&](const tinygltf::Value& value, const std::string& what) {
                if (!value.IsNumber() || !std::isfinite(value.GetNumberAsDouble()))
                    fail(fmt::format("{}: KHR_texture_transform {} is not a finite number", where, what));
                return float(value.GetNumberAsDouble());
            };
            auto pair = [&](const char* key) {
                const tinygltf::Value& value = extension.Get(key);
                if (!value.IsArray() || value.ArrayLen() != 2)
                    fail(fmt::format("{}: KHR_texture_transform {} must be an array of two numbers", where, key));
                return glm::vec2(number(value.Get(0), key), number(value.Get(1), key));
            };
            if (extension.Has("offset")) transform.offset = pair("offset");
            if (extension.Has("rotation")) transform.rotation = number(extension.Get("rotation"), "rotation");
            if (extension.Has("scale")) transform.scale = pair("scale");
            if (extension.Has("texCoord")) {
                const double value = number(extension.Get("texCoord"), "texCoord");
                if (value < 0.0 || value != std::floor(value))
                    fail(fmt::format("{}: KHR_texture_transform texCoord {} is not a non-negative integer", where, value));
                set = int64_t(std::min(value, 1e9));
            }
        }
        if (set < 0 || set > 1)
            fail(fmt::format("{} uses texCoord {} (TEXCOORD_{}); Janus reads TEXCOORD_0 and TEXCOORD_1 only", where, set, set));
        transform.texCoord = uint32_t(set);
        return transform;
    }

    void readMaterials(Scene& scene) {
        for (const tinygltf::Material& m : m_model.materials) {
            Material material;
            material.name = m.name;
            const auto& pbr = m.pbrMetallicRoughness;
            if (pbr.baseColorFactor.size() == 4)
                material.baseColorFactor = glm::vec4(pbr.baseColorFactor[0], pbr.baseColorFactor[1],
                                                     pbr.baseColorFactor[2], pbr.baseColorFactor[3]);
            material.metallicFactor = float(pbr.metallicFactor);
            material.roughnessFactor = float(pbr.roughnessFactor);
            if (m.emissiveFactor.size() == 3)
                material.emissiveFactor = glm::vec3(m.emissiveFactor[0], m.emissiveFactor[1], m.emissiveFactor[2]);
            material.doubleSided = m.doubleSided;
            if (m.alphaMode == "MASK") material.alphaMode = AlphaMode::Mask;
            else if (m.alphaMode == "BLEND") material.alphaMode = AlphaMode::Blend;
            material.alphaCutoff = float(m.alphaCutoff);
            material.baseColorTexture = textureFor(pbr.baseColorTexture.index, true, scene, m.name);
            material.metallicRoughnessTexture = textureFor(pbr.metallicRoughnessTexture.index, false, scene, m.name);
            material.normalTexture = textureFor(m.normalTexture.index, false, scene, m.name);
            material.occlusionTexture = textureFor(m.occlusionTexture.index, false, scene, m.name);
            material.normalScale = float(m.normalTexture.scale);
            material.occlusionStrength = float(m.occlusionTexture.strength);
            material.emissiveTexture = textureFor(m.emissiveTexture.index, true, scene, m.name);
            material.baseColorTransform = transformOf(pbr.baseColorTexture.index, pbr.baseColorTexture.texCoord,
                                                      pbr.baseColorTexture.extensions, m.name, "baseColorTexture");
            material.metallicRoughnessTransform =
                transformOf(pbr.metallicRoughnessTexture.index, pbr.metallicRoughnessTexture.texCoord,
                            pbr.metallicRoughnessTexture.extensions, m.name, "metallicRoughnessTexture");
            material.normalTransform =
                transformOf(m.normalTexture.index, m.normalTexture.texCoord, m.normalTexture.extensions, m.name, "normalTexture");
            material.occlusionTransform = transformOf(m.occlusionTexture.index, m.occlusionTexture.texCoord,
                                                      m.occlusionTexture.extensions, m.name, "occlusionTexture");
            material.emissiveTransform =
                transformOf(m.emissiveTexture.index, m.emissiveTexture.texCoord, m.emissiveTexture.extensions, m.name, "emissiveTexture");
            readMaterialExtensions(m, material);
            scene.materials.push_back(std::move(material));
        }
    }

    // The material extensions Janus implements (docs/SCENES.md); values are range-checked by
    // validateScene, types here.
    void readMaterialExtensions(const tinygltf::Material& m, Material& material) {
        const std::string where = fmt::format("material '{}'", m.name);
        auto extension = [&](const char* name) -> const tinygltf::Value* {
            auto it = m.extensions.find(name);
            if (it == m.extensions.end()) return nullptr;
            if (!it->second.IsObject()) fail(fmt::format("{}: {} is not an object", where, name));
            return &it->second;
        };
        auto number = [&](const tinygltf::Value& object, const char* name, const char* key, float fallback) {
            if (!object.Has(key)) return fallback;
            const tinygltf::Value& value = object.Get(key);
            if (!value.IsNumber() || !std::isfinite(value.GetNumberAsDouble()))
                fail(fmt::format("{}: {} {} is not a finite number", where, name, key));
            return float(value.GetNumberAsDouble());
        };
        if (const tinygltf::Value* e = extension("KHR_materials_emissive_strength"))
            material.emissiveStrength = number(*e, "KHR_materials_emissive_strength", "emissiveStrength", 1.0f);
        if (extension("KHR_materials_unlit")) material.unlit = true;
        if (const tinygltf::Value* e = extension("KHR_materials_ior")) material.ior = number(*e, "KHR_materials_ior", "ior", 1.5f);
        if (const tinygltf::Value* e = extension("KHR_materials_specular")) {
            material.specularFactor = number(*e, "KHR_materials_specular", "specularFactor", 1.0f);
            if (e->Has("specularColorFactor")) {
                const tinygltf::Value& value = e->Get("specularColorFactor");
                if (!value.IsArray() || value.ArrayLen() != 3)
                    fail(fmt::format("{}: KHR_materials_specular specularColorFactor must be an array of three numbers", where));
                for (int c = 0; c < 3; ++c) {
                    const tinygltf::Value& component = value.Get(c);
                    if (!component.IsNumber() || !std::isfinite(component.GetNumberAsDouble()))
                        fail(fmt::format("{}: KHR_materials_specular specularColorFactor is not three finite numbers", where));
                    material.specularColorFactor[c] = float(component.GetNumberAsDouble());
                }
            }
            // The factors are applied; the textures would need two more material bindings.
            for (const char* texture : {"specularTexture", "specularColorTexture"})
                if (e->Has(texture))
                    warn(fmt::format("{}: ignoring KHR_materials_specular {} (Janus applies the specular factors only)", where, texture));
        }
    }

    // The first texture of `material` that reads TEXCOORD_1, or nullptr.
    static const char* textureReadingUv1(const Material& material) {
        for (const Material::TextureSlot& slot : material.textureSlots())
            if (slot.texture >= 0 && slot.transform->texCoord == 1) return slot.name;
        return nullptr;
    }

    // The vertex attributes (and other accessors) Janus reads, for the component types each may have.
    enum class Attribute {
        Position, Normal, Tangent, TexCoord, Color,
        Joints,            // JOINTS_n: UNSIGNED_BYTE or UNSIGNED_SHORT, not normalized
        Weights,           // WEIGHTS_n: FLOAT, or normalized UNSIGNED_BYTE or UNSIGNED_SHORT
        Float,             // FLOAT only: inverse bind matrices, keyframe times, translation and scale keyframes
        AnimationOutput,   // FLOAT or any normalized 8/16-bit integer: rotation and weights keyframes
    };

    static const char* componentTypeName(int type) {
        switch (type) {
            case TINYGLTF_COMPONENT_TYPE_BYTE: return "BYTE";
            case TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE: return "UNSIGNED_BYTE";
            case TINYGLTF_COMPONENT_TYPE_SHORT: return "SHORT";
            case TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT: return "UNSIGNED_SHORT";
            case TINYGLTF_COMPONENT_TYPE_INT: return "INT";
            case TINYGLTF_COMPONENT_TYPE_UNSIGNED_INT: return "UNSIGNED_INT";
            case TINYGLTF_COMPONENT_TYPE_FLOAT: return "FLOAT";
            default: return "an unknown component type";
        }
    }

    // glTF 2.0 with KHR_mesh_quantization: positions and texture coordinates may be FLOAT or 8/16-bit
    // integers, normalised or not; normals and tangents FLOAT or normalised BYTE / SHORT.
    // `normalized` is meaningless (and not allowed) on FLOAT.
    static bool allowedComponentType(Attribute attribute, int type, bool normalized) {
        if (type == TINYGLTF_COMPONENT_TYPE_FLOAT) return !normalized && attribute != Attribute::Joints;
        if (attribute == Attribute::Float) return false;
        const bool signedType = type == TINYGLTF_COMPONENT_TYPE_BYTE || type == TINYGLTF_COMPONENT_TYPE_SHORT;
        const bool unsignedType = type == TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE || type == TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT;
        if (attribute == Attribute::Normal || attribute == Attribute::Tangent) return signedType && normalized;
        if (attribute == Attribute::Color || attribute == Attribute::Weights)
            return normalized && (type == TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE || type == TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT);
        if (attribute == Attribute::Joints) return !normalized && unsignedType;
        if (attribute == Attribute::AnimationOutput) return normalized && (signedType || unsignedType);
        return signedType || unsignedType;
    }

    static const char* allowedComponentTypes(Attribute attribute) {
        switch (attribute) {
            case Attribute::Normal:
            case Attribute::Tangent: return "FLOAT, or normalized BYTE or SHORT (KHR_mesh_quantization)";
            case Attribute::Color:
            case Attribute::Weights: return "FLOAT, or normalized UNSIGNED_BYTE or UNSIGNED_SHORT";
            case Attribute::Joints: return "UNSIGNED_BYTE or UNSIGNED_SHORT, not normalized";
            case Attribute::Float: return "FLOAT";
            case Attribute::AnimationOutput: return "FLOAT, or normalized BYTE, UNSIGNED_BYTE, SHORT or UNSIGNED_SHORT";
            default: return "FLOAT, or BYTE, UNSIGNED_BYTE, SHORT or UNSIGNED_SHORT, normalized or not (KHR_mesh_quantization)";
        }
    }

    // Reads accessor `index` of vertex attribute `attribute` as `width` floats per element. Integer
    // components are normalised as glTF specifies when the accessor is `normalized` (unsigned: c / max;
    // signed: max(c / max, -1)) and converted as they are otherwise (KHR_mesh_quantization).
    // Every offset is bounds-checked: a bad file must not crash us.
    std::vector<float> readFloats(int index, int width, Attribute attribute, const std::string& what) const {
        const tinygltf::Accessor& accessor = accessorAt(index, what);
        if (tinygltf::GetNumComponentsInType(uint32_t(accessor.type)) != width)
            fail(fmt::format("{} accessor {} has {} components per element, expected {}", what, index,
                             tinygltf::GetNumComponentsInType(uint32_t(accessor.type)), width));
        const bool normalized = accessor.normalized;
        if (!allowedComponentType(attribute, accessor.componentType, normalized))
            fail(fmt::format("{} accessor {} is {}{}, which glTF does not allow here; allowed: {}", what, index,
                             normalized ? "normalized " : "", componentTypeName(accessor.componentType), allowedComponentTypes(attribute)));
        const int componentSize = tinygltf::GetComponentSizeInBytes(uint32_t(accessor.componentType));
        const size_t count = checkedElementCount(accessor, index, what, sizeof(float) * size_t(width));
        std::vector<float> out(count * size_t(width));
        forEachElement(accessor, index, what, size_t(componentSize) * size_t(width), sizeof(float) * size_t(width), [&](const uint8_t* src, size_t e) {
            for (int c = 0; c < width; ++c) {
                const uint8_t* p = src + size_t(c) * size_t(componentSize);
                float value = 0.0f;
                switch (accessor.componentType) {
                    case TINYGLTF_COMPONENT_TYPE_FLOAT: std::memcpy(&value, p, 4); break;
                    case TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE: value = normalized ? float(*p) / 255.0f : float(*p); break;
                    case TINYGLTF_COMPONENT_TYPE_BYTE: {
                        const float v = float(int8_t(*p));
                        value = normalized ? std::max(v / 127.0f, -1.0f) : v;
                        break;
                    }
                    case TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT: {
                        uint16_t v;
                        std::memcpy(&v, p, 2);
                        value = normalized ? float(v) / 65535.0f : float(v);
                        break;
                    }
                    default: {   // SHORT (allowedComponentType admits nothing else)
                        int16_t v;
                        std::memcpy(&v, p, 2);
                        value = normalized ? std::max(float(v) / 32767.0f, -1.0f) : float(v);
                        break;
                    }
                }
                out[e * size_t(width) + size_t(c)] = value;
            }
        });
        return out;
    }

    std::vector<uint32_t> readIndices(int index) const {
        const tinygltf::Accessor& accessor = accessorAt(index, "index");
        if (accessor.type != TINYGLTF_TYPE_SCALAR) fail(fmt::format("index accessor {} is not scalar", index));
        const int componentSize = tinygltf::GetComponentSizeInBytes(uint32_t(accessor.componentType));
        if (componentSize != 1 && componentSize != 2 && componentSize != 4)
            fail(fmt::format("index accessor {} has component type {}; indices must be unsigned byte, short or int", index,
                             accessor.componentType));
        std::vector<uint32_t> out(checkedElementCount(accessor, index, "index", sizeof(uint32_t)));
        forEachElement(accessor, index, "index", size_t(componentSize), sizeof(uint32_t), [&](const uint8_t* src, size_t e) {
            uint32_t value = 0;
            if (componentSize == 1) value = *src;
            else if (componentSize == 2) { uint16_t v; std::memcpy(&v, src, 2); value = v; }
            else std::memcpy(&value, src, 4);
            out[e] = value;
        });
        return out;
    }

    const tinygltf::Accessor& accessorAt(int index, const std::string& what) const {
        if (index < 0 || size_t(index) >= m_model.accessors.size())
            fail(fmt::format("{} accessor {} does not exist (the file has {})", what, index, m_model.accessors.size()));
        return m_model.accessors[size_t(index)];
    }

    // The element count of `accessor` (elements of `decodedSize` bytes once read), refused when
    // the decoded size passes kMaxAccessorBytes. Called before anything is allocated for the
    // accessor: a count crafted to wrap a size computation (e.g. 6148914691236517206 VEC3 floats)
    // must not reach an allocation or a copy.
    size_t checkedElementCount(const tinygltf::Accessor& accessor, int index, const std::string& what, size_t decodedSize) const {
        const uint64_t count = accessor.count;
        uint64_t decodedBytes = 0;
        const bool wraps = __builtin_mul_overflow(count, uint64_t(std::max<size_t>(decodedSize, 1)), &decodedBytes);
        if (wraps || decodedBytes > kMaxAccessorBytes)
            fail(fmt::format("{} accessor {} declares {} elements ({} bytes once read), more than Janus reads from one accessor "
                             "({} MiB); the count is wrong or the asset is too large",
                             what, index, count, wraps ? std::string("over 2^64") : std::to_string(decodedBytes), kMaxAccessorBytes >> 20));
        return size_t(count);
    }

    // The first byte of `count` elements of `elementSize` bytes, `stride` bytes apart (0: tightly
    // packed; else the view's byteStride when `strided`), starting `offset` bytes into buffer view
    // `viewIndex`: checked with overflow-safe arithmetic to lie inside the view and its buffer.
    // `stride` returns the distance used. `what` names the data for messages ("... accessor 3").
    const uint8_t* checkedViewRange(int viewIndex, uint64_t offset, uint64_t count, size_t elementSize, bool strided, size_t& stride,
                                    const std::string& what) const {
        if (viewIndex < 0 || size_t(viewIndex) >= m_model.bufferViews.size())
            fail(fmt::format("{} has no valid buffer view ({})", what, viewIndex));
        const tinygltf::BufferView& view = m_model.bufferViews[size_t(viewIndex)];
        if (view.buffer < 0 || size_t(view.buffer) >= m_model.buffers.size())
            fail(fmt::format("buffer view {} references missing buffer {}", viewIndex, view.buffer));
        const uint64_t bufferSize = m_model.buffers[size_t(view.buffer)].data.size();
        stride = strided && view.byteStride ? view.byteStride : elementSize;
        if (stride < elementSize)
            fail(fmt::format("{}: buffer view {} has byteStride {}, smaller than one element ({} bytes)", what, viewIndex, stride,
                             elementSize));
        uint64_t viewEnd = 0, span = 0, lastEnd = 0;
        const bool overflow = __builtin_add_overflow(uint64_t(view.byteOffset), uint64_t(view.byteLength), &viewEnd) ||
                              __builtin_mul_overflow(uint64_t(stride), count - 1, &span) || __builtin_add_overflow(span, offset, &lastEnd) ||
                              __builtin_add_overflow(lastEnd, uint64_t(elementSize), &lastEnd);
        if (overflow || lastEnd > view.byteLength || viewEnd > bufferSize)
            fail(fmt::format("{} reads past the end of its buffer (the .bin file is too short or the accessor's count/offset is wrong)",
                             what));
        return m_model.buffers[size_t(view.buffer)].data.data() + view.byteOffset + offset;   // no overflow: checked above
    }

    // Visits the accessor's `count` elements (`elementSize` bytes each in the file, `decodedSize`
    // once read) in order: from its buffer view, or zeros without one (glTF: "When undefined, the
    // accessor MUST be initialized with zeros"), with a sparse accessor's substitutions applied.
    template <typename Visit>
    void forEachElement(const tinygltf::Accessor& accessor, int index, const std::string& what, size_t elementSize, size_t decodedSize,
                        Visit&& visit) const {
        const size_t count = checkedElementCount(accessor, index, what, decodedSize);
        if (count == 0) return;
        const std::string label = fmt::format("{} accessor {}", what, index);
        const uint8_t* base = nullptr;
        size_t stride = elementSize;
        if (accessor.bufferView >= 0 || !accessor.sparse.isSparse) {
            if (accessor.bufferView < 0) {   // all zeros
                const std::vector<uint8_t> zero(elementSize, 0);
                for (size_t e = 0; e < count; ++e) visit(zero.data(), e);
                return;
            }
            base = checkedViewRange(accessor.bufferView, uint64_t(accessor.byteOffset), count, elementSize, true, stride, label);
        }
        if (!accessor.sparse.isSparse) {
            for (size_t e = 0; e < count; ++e) visit(base + e * stride, e);
            return;
        }
        std::vector<uint8_t> dense(count * elementSize, 0);   // count * elementSize <= count * decodedSize (or the limit's floor)
        if (base)
            for (size_t e = 0; e < count; ++e) std::memcpy(dense.data() + e * elementSize, base + e * stride, elementSize);
        applySparse(accessor, label, elementSize, count, dense);
        for (size_t e = 0; e < count; ++e) visit(dense.data() + e * elementSize, e);
    }

    // glTF sparse accessors: `sparse.count` (index, value) pairs replace elements of the dense data.
    // The indices are strictly increasing and inside `count`; both arrays lie inside their buffer
    // views (which are tightly packed: glTF forbids byteStride on them).
    void applySparse(const tinygltf::Accessor& accessor, const std::string& label, size_t elementSize, size_t count,
                     std::vector<uint8_t>& dense) const {
        const auto& sparse = accessor.sparse;
        if (sparse.count < 1 || uint64_t(sparse.count) > count)
            fail(fmt::format("{} is sparse with count {}; it must be in [1, {}] (the accessor's count)", label, sparse.count, count));
        const int indexType = sparse.indices.componentType;
        if (indexType != TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE && indexType != TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT &&
            indexType != TINYGLTF_COMPONENT_TYPE_UNSIGNED_INT)
            fail(fmt::format("{} has sparse indices of component type {}; glTF allows UNSIGNED_BYTE, UNSIGNED_SHORT or UNSIGNED_INT", label,
                             componentTypeName(indexType)));
        const size_t indexSize = size_t(tinygltf::GetComponentSizeInBytes(uint32_t(indexType)));
        const size_t pairs = size_t(sparse.count);
        if (sparse.indices.byteOffset < 0 || sparse.values.byteOffset < 0) fail(fmt::format("{} has a negative sparse byteOffset", label));
        size_t stride = 0;
        const uint8_t* indices = checkedViewRange(sparse.indices.bufferView, uint64_t(sparse.indices.byteOffset), pairs,
                                                  indexSize, false, stride, label + " sparse indices");
        const uint8_t* values = checkedViewRange(sparse.values.bufferView, uint64_t(sparse.values.byteOffset), pairs,
                                                 elementSize, false, stride, label + " sparse values");
        uint64_t previous = 0;
        for (size_t i = 0; i < pairs; ++i) {
            uint64_t target = 0;
            if (indexSize == 1) target = indices[i];
            else if (indexSize == 2) { uint16_t v; std::memcpy(&v, indices + i * 2, 2); target = v; }
            else { uint32_t v; std::memcpy(&v, indices + i * 4, 4); target = v; }
            if (target >= count)
                fail(fmt::format("{} has sparse index {} (entry {}), outside the accessor's {} elements", label, target, i, count));
            if (i > 0 && target <= previous)
                fail(fmt::format("{} has sparse indices that are not strictly increasing ({} after {}, entry {})", label, target, previous, i));
            previous = target;
            std::memcpy(dense.data() + target * elementSize, values + i * elementSize, elementSize);
        }
    }

    // The indices of a primitive of glTF mode `mode` as a list of its topology (`topology`
    // returns which): strips and fans become triangle lists with glTF's vertex order (so the
    // winding is kept), line strips and loops become line lists. A list whose index count is
    // not a whole number of its primitives is an error; strips and fans too short for one
    // triangle (or line) give an empty list.
    std::vector<uint32_t> primitiveList(int mode, std::vector<uint32_t> indices, const std::string& where, MeshTopology& topology) const {
        const size_t n = indices.size();
        std::vector<uint32_t> list;
        switch (mode) {
            case TINYGLTF_MODE_POINTS: topology = MeshTopology::Points; return indices;
            case TINYGLTF_MODE_LINE: topology = MeshTopology::Lines;
                if (n % 2 != 0) fail(fmt::format("{} has {} indices, which is not a whole number of lines (mode LINES)", where, n));
                return indices;
            case TINYGLTF_MODE_LINE_STRIP:
            case TINYGLTF_MODE_LINE_LOOP:
                topology = MeshTopology::Lines;
                for (size_t i = 0; i + 1 < n; ++i) list.insert(list.end(), {indices[i], indices[i + 1]});
                if (mode == TINYGLTF_MODE_LINE_LOOP && n >= 2) list.insert(list.end(), {indices[n - 1], indices[0]});
                return list;
            case TINYGLTF_MODE_TRIANGLE_STRIP:
                topology = MeshTopology::Triangles;
                // glTF: triangle i is (v_i, v_{i + 1 + i % 2}, v_{i + 2 - i % 2}).
                for (size_t i = 0; i + 2 < n; ++i)
                    list.insert(list.end(), {indices[i], indices[i + 1 + i % 2], indices[i + 2 - i % 2]});
                return list;
            case TINYGLTF_MODE_TRIANGLE_FAN:
                topology = MeshTopology::Triangles;
                // glTF: triangle i is (v_{i + 1}, v_{i + 2}, v_0).
                for (size_t i = 0; i + 2 < n; ++i) list.insert(list.end(), {indices[i + 1], indices[i + 2], indices[0]});
                return list;
            default:
                topology = MeshTopology::Triangles;
                if (n % 3 != 0) fail(fmt::format("{} has {} indices, which is not a whole number of triangles", where, n));
                return indices;
        }
    }

    // JOINTS_0/WEIGHTS_0 and JOINTS_1/WEIGHTS_1: per vertex the four strongest of the (up to
    // eight) influences, weights renormalised to sum 1; a vertex whose weights are all zero gets
    // weight 1 on its first joint (JOINTS_0's x). Influences left with weight 0 get joint 0, so
    // that no joint index reaches past the skin unless it carries weight (readNode checks those
    // against the skin: m_maxJoint).
    void readSkinAttributes(const tinygltf::Primitive& primitive, const std::string& where, Mesh& mesh, size_t sceneMesh) {
        auto attribute = [&](const std::string& name) {
            auto it = primitive.attributes.find(name);
            return it == primitive.attributes.end() ? -1 : it->second;
        };
        const size_t vertexCount = mesh.vertices.size();
        std::vector<std::vector<float>> joints, weights;
        for (int set = 0;; ++set) {
            const std::string jointsName = fmt::format("JOINTS_{}", set), weightsName = fmt::format("WEIGHTS_{}", set);
            const int j = attribute(jointsName), w = attribute(weightsName);
            if (j < 0 && w < 0) break;
            if (j < 0 || w < 0)
                fail(fmt::format("{} has {} without {}; skinned primitives need both", where, j < 0 ? weightsName : jointsName,
                                 j < 0 ? jointsName : weightsName));
            if (set >= 2) {
                warn(fmt::format("{}: ignoring {} and {} (Janus reads two sets of joints and weights)", where, jointsName, weightsName));
                continue;
            }
            joints.push_back(readFloats(j, 4, Attribute::Joints, where + " " + jointsName));
            weights.push_back(readFloats(w, 4, Attribute::Weights, where + " " + weightsName));
            for (const auto& [name, values] : {std::pair{jointsName, &joints.back()}, std::pair{weightsName, &weights.back()}})
                if (values->size() / 4 != vertexCount)
                    fail(fmt::format("{} {} has {} elements but POSITION has {}", where, name, values->size() / 4, vertexCount));
        }
        if (joints.empty()) {
            if (attribute("JOINTS_1") >= 0 || attribute("WEIGHTS_1") >= 0)
                fail(fmt::format("{} has JOINTS_1/WEIGHTS_1 but no JOINTS_0/WEIGHTS_0", where));
            return;
        }
        mesh.joints.resize(vertexCount);
        mesh.weights.resize(vertexCount);
        MaxJoint& maxJoint = m_maxJoint[sceneMesh];
        for (size_t v = 0; v < vertexCount; ++v) {
            struct Influence {
                uint32_t joint;
                float weight;
            };
            std::array<Influence, 8> influences{};
            size_t count = 0;
            for (size_t set = 0; set < joints.size(); ++set)
                for (size_t i = 0; i < 4; ++i) {
                    const float weight = weights[set][v * 4 + i];
                    if (!std::isfinite(weight) || weight < 0.0f)
                        fail(fmt::format("{} WEIGHTS_{} has weight {} at vertex {}; weights must be finite and >= 0", where, set, weight, v));
                    influences[count++] = Influence{uint32_t(joints[set][v * 4 + i]), weight};
                }
            // The four strongest; equal weights keep their order (set 0 first, then x, y, z, w).
            std::stable_sort(influences.begin(), influences.begin() + long(count),
                             [](const Influence& a, const Influence& b) { return a.weight > b.weight; });
            float sum = 0.0f;
            for (size_t i = 0; i < 4; ++i) sum += influences[i].weight;
            glm::u16vec4& jointSet = mesh.joints[v];
            glm::vec4& weightSet = mesh.weights[v];
            if (sum > 0.0f) {
                for (size_t i = 0; i < 4; ++i) {
                    weightSet[int(i)] = influences[i].weight / sum;
                    jointSet[int(i)] = influences[i].weight > 0.0f ? uint16_t(influences[i].joint) : uint16_t(0);
                }
            } else {
                weightSet = glm::vec4(1.0f, 0.0f, 0.0f, 0.0f);
                jointSet = glm::u16vec4(uint16_t(joints[0][v * 4]), 0, 0, 0);
            }
            for (size_t i = 0; i < 4; ++i)
                if (weightSet[int(i)] > 0.0f && (maxJoint.vertex == SIZE_MAX || jointSet[int(i)] > maxJoint.joint)) {
                    maxJoint.joint = jointSet[int(i)];
                    maxJoint.vertex = v;
                }
        }
    }

    // The primitive's morph targets (POSITION, NORMAL and TANGENT displacements; other target
    // attributes are ignored with a warning) and the mesh's default weights.
    void readMorphTargets(const tinygltf::Mesh& gltfMesh, const tinygltf::Primitive& primitive, const std::string& where, Mesh& mesh) {
        const size_t vertexCount = mesh.vertices.size();
        if (primitive.targets.size() > kMaxMorphTargets)
            fail(fmt::format("{} has {} morph targets; Janus morphs with at most {}", where, primitive.targets.size(), kMaxMorphTargets));
        if (!gltfMesh.primitives.empty() && primitive.targets.size() != gltfMesh.primitives[0].targets.size())
            fail(fmt::format("{} has {} morph targets but primitive 0 has {}; glTF requires the same number in every primitive", where,
                             primitive.targets.size(), gltfMesh.primitives[0].targets.size()));
        if (!gltfMesh.weights.empty() && gltfMesh.weights.size() != primitive.targets.size())
            fail(fmt::format("mesh '{}' has {} default weights but {} morph targets", gltfMesh.name, gltfMesh.weights.size(),
                             primitive.targets.size()));
        for (size_t t = 0; t < primitive.targets.size(); ++t) {
            MorphTarget target;
            for (const auto& [name, accessor] : primitive.targets[t]) {
                const std::string what = fmt::format("{} morph target {} {}", where, t, name);
                std::vector<glm::vec3>* into = name == "POSITION" ? &target.positions
                                               : name == "NORMAL" ? &target.normals
                                               : name == "TANGENT" ? &target.tangents
                                                                   : nullptr;
                if (!into) {
                    warn(fmt::format("{}: ignoring morph target attribute {} (Janus morphs POSITION, NORMAL and TANGENT)", where, name));
                    continue;
                }
                const Attribute kind = name == "POSITION" ? Attribute::Position : name == "NORMAL" ? Attribute::Normal : Attribute::Tangent;
                const std::vector<float> values = readFloats(accessor, 3, kind, what);
                if (values.size() / 3 != vertexCount)
                    fail(fmt::format("{} has {} elements but the primitive's POSITION has {}", what, values.size() / 3, vertexCount));
                into->resize(vertexCount);
                for (size_t v = 0; v < vertexCount; ++v) (*into)[v] = glm::vec3(values[v * 3], values[v * 3 + 1], values[v * 3 + 2]);
                for (const glm::vec3& d : *into)
                    if (!std::isfinite(d.x) || !std::isfinite(d.y) || !std::isfinite(d.z)) fail(fmt::format("{} holds NaN or Inf", what));
            }
            mesh.morphTargets.push_back(std::move(target));
        }
        mesh.morphWeights.assign(primitive.targets.size(), 0.0f);
        for (size_t t = 0; t < gltfMesh.weights.size(); ++t) {
            mesh.morphWeights[t] = float(gltfMesh.weights[t]);
            if (!std::isfinite(mesh.morphWeights[t])) fail(fmt::format("mesh '{}' default weight {} is NaN or infinite", gltfMesh.name, t));
        }
    }

    void readMeshes(Scene& scene) {
        for (size_t meshIndex = 0; meshIndex < m_model.meshes.size(); ++meshIndex) {
            const tinygltf::Mesh& gltfMesh = m_model.meshes[meshIndex];
            std::vector<uint32_t>& sceneMeshes = m_meshPrimitives[int(meshIndex)];
            for (size_t p = 0; p < gltfMesh.primitives.size(); ++p) {
                const tinygltf::Primitive& primitive = gltfMesh.primitives[p];
                const std::string where = fmt::format("mesh '{}' primitive {}", gltfMesh.name, p);
                const int mode = primitive.mode == -1 ? TINYGLTF_MODE_TRIANGLES : primitive.mode;
                if (mode < TINYGLTF_MODE_POINTS || mode > TINYGLTF_MODE_TRIANGLE_FAN)
                    fail(fmt::format("{} has mode {}; glTF primitive modes are 0 (POINTS) to 6 (TRIANGLE_FAN)", where, primitive.mode));
                auto attribute = [&](const char* name) {
                    auto it = primitive.attributes.find(name);
                    return it == primitive.attributes.end() ? -1 : it->second;
                };
                if (attribute("POSITION") < 0) fail(fmt::format("{} has no POSITION attribute", where));
                Mesh mesh;
                const std::vector<float> positions = readFloats(attribute("POSITION"), 3, Attribute::Position, where + " POSITION");
                const size_t vertexCount = positions.size() / 3;
                mesh.vertices.resize(vertexCount);
                for (size_t v = 0; v < vertexCount; ++v) {
                    Vertex& vertex = mesh.vertices[v];
                    vertex.position = glm::vec3(positions[v * 3], positions[v * 3 + 1], positions[v * 3 + 2]);
                    vertex.normal = glm::vec3(0.0f);
                    vertex.uv = vertex.uv1 = glm::vec2(0.0f);
                    vertex.tangent = glm::vec4(0.0f);
                }
                auto readInto = [&](const char* name, int width, Attribute kind, auto&& store) {
                    if (attribute(name) < 0) return false;
                    const std::vector<float> values = readFloats(attribute(name), width, kind, where + " " + name);
                    if (values.size() / size_t(width) != vertexCount)
                        fail(fmt::format("{} {} has {} elements but POSITION has {}", where, name,
                                         values.size() / size_t(width), vertexCount));
                    for (size_t v = 0; v < vertexCount; ++v) store(mesh.vertices[v], &values[v * size_t(width)]);
                    return true;
                };
                const bool hasNormals =
                    readInto("NORMAL", 3, Attribute::Normal, [](Vertex& v, const float* f) { v.normal = glm::vec3(f[0], f[1], f[2]); });
                const bool hasUvs =
                    readInto("TEXCOORD_0", 2, Attribute::TexCoord, [](Vertex& v, const float* f) { v.uv = glm::vec2(f[0], f[1]); });
                const bool hasUvs1 =
                    readInto("TEXCOORD_1", 2, Attribute::TexCoord, [](Vertex& v, const float* f) { v.uv1 = glm::vec2(f[0], f[1]); });
                const bool hasTangents = readInto("TANGENT", 4, Attribute::Tangent,
                                                  [](Vertex& v, const float* f) { v.tangent = glm::vec4(f[0], f[1], f[2], f[3]); });
                if (const int colors = attribute("COLOR_0"); colors >= 0) {
                    const int width = tinygltf::GetNumComponentsInType(uint32_t(accessorAt(colors, where + " COLOR_0").type));
                    if (width != 3 && width != 4)
                        fail(fmt::format("{} COLOR_0 accessor {} has {} components per element; glTF vertex colours are VEC3 or VEC4", where,
                                         colors, width));
                    readInto("COLOR_0", width, Attribute::Color, [width](Vertex& v, const float* f) {
                        v.color = glm::vec4(f[0], f[1], f[2], width == 4 ? f[3] : 1.0f);
                    });
                }
                readSkinAttributes(primitive, where, mesh, scene.meshes.size());
                readMorphTargets(gltfMesh, primitive, where, mesh);

                if (primitive.indices >= 0) {
                    mesh.indices = readIndices(primitive.indices);
                    for (size_t i = 0; i < mesh.indices.size(); ++i)
                        if (mesh.indices[i] >= vertexCount)
                            fail(fmt::format("{} has bad indices: index {} at position {} is out of range (the mesh has "
                                             "{} vertices)",
                                             where, mesh.indices[i], i, vertexCount));
                } else {
                    mesh.indices.resize(vertexCount);
                    for (size_t i = 0; i < vertexCount; ++i) mesh.indices[i] = uint32_t(i);
                }
                mesh.indices = primitiveList(mode, std::move(mesh.indices), where, mesh.topology);
                if (primitive.material >= 0 && size_t(primitive.material) >= m_model.materials.size())
                    fail(fmt::format("{} references material {} but the file has {}", where, primitive.material,
                                     m_model.materials.size()));
                mesh.material = primitive.material;
                const Material* material = primitive.material >= 0 ? &scene.materials[size_t(primitive.material)] : nullptr;
                if (const char* texture = material ? textureReadingUv1(*material) : nullptr; texture && !hasUvs1)
                    fail(fmt::format("{} uses material '{}', whose {} reads texCoord 1, but the primitive has no TEXCOORD_1", where,
                                     material->name, texture));
                // Points and lines without normals are drawn unlit (there is no surface to derive them from).
                if (!hasNormals) {
                    if (mesh.topology == MeshTopology::Triangles) generateNormals(mesh);
                    else mesh.unlit = true;
                }
                // glTF asks clients to compute tangents when a normal-mapped mesh has none, from
                // the UV set the normal texture reads.
                if (material && material->normalTexture >= 0 && !hasTangents && mesh.topology == MeshTopology::Triangles) {
                    const uint32_t normalSet = material->normalTransform.texCoord;
                    if (normalSet == 0 ? hasUvs : hasUvs1) generateTangents(mesh, normalSet);
                }
                scene.meshes.push_back(std::move(mesh));
                m_meshLabels.push_back(where);
                sceneMeshes.push_back(uint32_t(scene.meshes.size() - 1));
            }
        }
    }

    static glm::mat4 localMatrix(const tinygltf::Node& node) {
        if (node.matrix.size() == 16) {
            glm::mat4 m;
            for (int i = 0; i < 16; ++i) glm::value_ptr(m)[i] = float(node.matrix[size_t(i)]);   // column-major in both
            return m;
        }
        glm::mat4 m(1.0f);
        if (node.translation.size() == 3)
            m = glm::translate(m, glm::vec3(node.translation[0], node.translation[1], node.translation[2]));
        if (node.rotation.size() == 4)
            m *= glm::mat4_cast(glm::quat(float(node.rotation[3]), float(node.rotation[0]), float(node.rotation[1]),
                                          float(node.rotation[2])));
        if (node.scale.size() == 3) m = glm::scale(m, glm::vec3(node.scale[0], node.scale[1], node.scale[2]));
        return m;
    }

    static bool finite(const glm::mat4& m) {
        for (int i = 0; i < 16; ++i)
            if (!std::isfinite(glm::value_ptr(m)[i])) return false;
        return true;
    }

    // What one node brings (instances, camera, light, marker), given its world matrix.
    void readNode(int index, const glm::mat4& world, Scene& scene) {
        const tinygltf::Node& node = m_model.nodes[size_t(index)];
        const std::string name = nodeLabel(index);
        if (!finite(world)) fail(fmt::format("node '{}' has a NaN or infinite transform", name));

        if (node.mesh >= 0) {
            auto it = m_meshPrimitives.find(node.mesh);
            if (it == m_meshPrimitives.end()) fail(fmt::format("node '{}' references missing mesh {}", name, node.mesh));
            // Optional node extras {"renderingLayers": mask}, the glTF twin of a scene file's meshLayers.
            uint32_t layers = 1u;
            if (node.extras.IsObject() && node.extras.Has("renderingLayers")) {
                const tinygltf::Value& value = node.extras.Get("renderingLayers");
                if (!value.IsNumber() || value.GetNumberAsDouble() < 0 || value.GetNumberAsDouble() > double(UINT32_MAX) ||
                    value.GetNumberAsDouble() != std::floor(value.GetNumberAsDouble()))
                    fail(fmt::format("node '{}' extras.renderingLayers must be an integer mask in [0, 4294967295]", name));
                layers = uint32_t(value.GetNumberAsDouble());
            }
            if (node.skin >= 0 && size_t(node.skin) >= scene.skins.size())
                fail(fmt::format("node '{}' references skin {} but the file has {}", name, node.skin, scene.skins.size()));
            for (uint32_t mesh : it->second) {
                Instance instance{mesh, world, layers, node.name};
                instance.node = index;
                const bool skinnedMesh = !scene.meshes[mesh].joints.empty();
                if (node.skin >= 0 && skinnedMesh) {
                    const Skin& skin = scene.skins[size_t(node.skin)];
                    if (auto used = m_maxJoint.find(mesh); used != m_maxJoint.end() && used->second.joint >= skin.joints.size())
                        fail(fmt::format("node '{}': {} gives vertex {} weight on joint {}, but the node's skin {} has {} joints (JOINTS "
                                         "values index the skin's joints)",
                                         name, m_meshLabels[mesh], used->second.vertex, used->second.joint, skinLabel(node.skin),
                                         skin.joints.size()));
                    m_jointMatrices += skin.joints.size();
                    if (m_jointMatrices > kMaxJointMatrices)
                        fail(fmt::format("the skinned instances need more than {} joint matrices (node '{}' adds {} for skin {}); the "
                                         "file is wrong or too large for Janus",
                                         kMaxJointMatrices, name, skin.joints.size(), skinLabel(node.skin)));
                    // glTF ignores the skinned mesh node's own transform: the joints place the mesh.
                    instance.skin = node.skin;
                    instance.world = glm::mat4(1.0f);
                } else if (node.skin >= 0) {
                    warn(fmt::format("node '{}' has a skin but {} has no JOINTS_0/WEIGHTS_0; it is drawn unskinned, with the node's "
                                     "transform",
                                     name, m_meshLabels[mesh]));
                } else if (skinnedMesh) {
                    warn(fmt::format("{} has JOINTS_0/WEIGHTS_0 but node '{}' has no skin; it is drawn unskinned there", m_meshLabels[mesh],
                                     name));
                    instance.mesh = unskinnedCopy(mesh, scene);
                }
                if (!node.weights.empty() && node.weights.size() != scene.meshes[mesh].morphTargets.size())
                    fail(fmt::format("node '{}' has {} morph weights but {} has {} morph targets", name, node.weights.size(),
                                     m_meshLabels[mesh], scene.meshes[mesh].morphTargets.size()));
                scene.instances.push_back(std::move(instance));
            }
        }
        if (node.camera >= 0 && !m_cameraFound && (!m_options.camera || uint32_t(node.camera) == *m_options.camera))
            readCamera(index, world, name);
        bool hasLight = false;
        if (auto ext = node.extensions.find("KHR_lights_punctual"); ext != node.extensions.end() && ext->second.Has("light")) {
            hasLight = true;
            readLight(ext->second.Get("light").GetNumberAsInt(), world, name, scene);
            scene.lights.back().node = index;
        }
        // Empty leaf nodes are placement markers (probe volumes, cubemap centres...).
        if (node.mesh < 0 && node.camera < 0 && !hasLight && node.children.empty())
            scene.markers.push_back(Marker{node.name, world, index});
    }

    std::string skinLabel(int index) const {
        const std::string& name = m_model.skins[size_t(index)].name;
        return name.empty() ? fmt::format("{}", index) : fmt::format("{} ('{}')", index, name);
    }

    // The mesh `mesh` without its joints and weights, for a node that uses a skinned glTF mesh
    // without a skin (made once per mesh).
    uint32_t unskinnedCopy(uint32_t mesh, Scene& scene) {
        if (auto it = m_unskinned.find(mesh); it != m_unskinned.end()) return it->second;
        Mesh copy = scene.meshes[mesh];
        copy.joints.clear();
        copy.weights.clear();
        scene.meshes.push_back(std::move(copy));
        m_meshLabels.push_back(m_meshLabels[mesh]);
        const uint32_t index = uint32_t(scene.meshes.size() - 1);
        m_unskinned[mesh] = index;
        return index;
    }

    // glTF skins: joints (nodes) and inverse bind matrices (a MAT4 FLOAT accessor with at least
    // one matrix per joint; identity matrices without one).
    void readSkins(Scene& scene) {
        for (size_t s = 0; s < m_model.skins.size(); ++s) {
            const tinygltf::Skin& gltfSkin = m_model.skins[s];
            const std::string label = "skin " + skinLabel(int(s));
            Skin skin;
            skin.name = gltfSkin.name;
            if (gltfSkin.joints.empty()) fail(fmt::format("{} has no joints", label));
            if (gltfSkin.joints.size() > kMaxSkinJoints)
                fail(fmt::format("{} has {} joints; Janus skins with at most {}", label, gltfSkin.joints.size(), kMaxSkinJoints));
            for (int joint : gltfSkin.joints) {
                if (joint < 0 || size_t(joint) >= m_model.nodes.size())
                    fail(fmt::format("{} has joint node {}, which does not exist (the file has {} nodes)", label, joint, m_model.nodes.size()));
                skin.joints.push_back(uint32_t(joint));
            }
            if (gltfSkin.inverseBindMatrices >= 0) {
                const std::string what = label + " inverseBindMatrices";
                if (accessorAt(gltfSkin.inverseBindMatrices, what).type != TINYGLTF_TYPE_MAT4)
                    fail(fmt::format("{} accessor {} is not MAT4", what, gltfSkin.inverseBindMatrices));
                const std::vector<float> values = readFloats(gltfSkin.inverseBindMatrices, 16, Attribute::Float, what);
                if (values.size() / 16 < skin.joints.size())
                    fail(fmt::format("{} accessor {} has {} matrices for {} joints", what, gltfSkin.inverseBindMatrices, values.size() / 16,
                                     skin.joints.size()));
                for (size_t j = 0; j < skin.joints.size(); ++j) {
                    glm::mat4 m;
                    std::memcpy(glm::value_ptr(m), &values[j * 16], sizeof(m));   // column-major in both
                    if (!finite(m)) fail(fmt::format("{} matrix {} holds NaN or Inf", what, j));
                    skin.inverseBindMatrices.push_back(m);
                }
            } else {
                skin.inverseBindMatrices.assign(skin.joints.size(), glm::mat4(1.0f));
            }
            scene.skins.push_back(std::move(skin));
        }
    }

    // Scene::nodes: every glTF node (also those outside the default scene, which skins and
    // animations may use), with its rest transform and morph weights, and the parent links.
    void readHierarchy(Scene& scene) {
        scene.nodes.resize(m_model.nodes.size());
        for (size_t n = 0; n < m_model.nodes.size(); ++n) {
            const tinygltf::Node& gltfNode = m_model.nodes[n];
            Node& node = scene.nodes[n];
            node.name = gltfNode.name;
            if (gltfNode.matrix.size() == 16) {
                const glm::mat4 m = localMatrix(gltfNode);
                node.matrix = m;
                glm::vec3 skew;
                glm::vec4 perspective;
                if (!glm::decompose(m, node.scale, node.rotation, node.translation, skew, perspective)) {
                    node.translation = glm::vec3(m[3]);
                    node.rotation = glm::quat(1.0f, 0.0f, 0.0f, 0.0f);
                    node.scale = glm::vec3(glm::length(glm::vec3(m[0])), glm::length(glm::vec3(m[1])), glm::length(glm::vec3(m[2])));
                }
            } else {
                if (gltfNode.translation.size() == 3)
                    node.translation = glm::vec3(gltfNode.translation[0], gltfNode.translation[1], gltfNode.translation[2]);
                if (gltfNode.rotation.size() == 4)
                    node.rotation = glm::quat(float(gltfNode.rotation[3]), float(gltfNode.rotation[0]), float(gltfNode.rotation[1]),
                                              float(gltfNode.rotation[2]));
                if (gltfNode.scale.size() == 3) node.scale = glm::vec3(gltfNode.scale[0], gltfNode.scale[1], gltfNode.scale[2]);
            }
            for (double w : gltfNode.weights) node.weights.push_back(float(w));
            for (int child : gltfNode.children) {
                if (child < 0 || size_t(child) >= m_model.nodes.size())
                    fail(fmt::format("node '{}' has child {}, which does not exist (the file has {} nodes)", nodeLabel(int(n)), child,
                                     m_model.nodes.size()));
                Node& childNode = scene.nodes[size_t(child)];
                if (childNode.parent >= 0)
                    fail(fmt::format("node {} ('{}') has two parents ('{}' and '{}'); glTF nodes have at most one parent", child,
                                     nodeLabel(child), nodeLabel(childNode.parent), nodeLabel(int(n))));
                childNode.parent = int32_t(n);
                node.children.push_back(uint32_t(child));
            }
        }
    }

    // glTF animations: samplers (keyframe times: a FLOAT SCALAR accessor, finite, >= 0, strictly
    // increasing; values: one per keyframe, three for CUBICSPLINE) and channels (translation,
    // rotation, scale, weights; other paths, such as KHR_animation_pointer's "pointer", are
    // ignored with a warning).
    void readAnimations(Scene& scene) {
        for (size_t a = 0; a < m_model.animations.size(); ++a) {
            const tinygltf::Animation& gltfAnimation = m_model.animations[a];
            const std::string label =
                gltfAnimation.name.empty() ? fmt::format("animation {}", a) : fmt::format("animation {} ('{}')", a, gltfAnimation.name);
            Animation animation;
            animation.name = gltfAnimation.name;
            struct Output {
                int componentType;
                int width;
            };
            std::vector<Output> outputs;
            for (size_t s = 0; s < gltfAnimation.samplers.size(); ++s) {
                const tinygltf::AnimationSampler& gltfSampler = gltfAnimation.samplers[s];
                const std::string where = fmt::format("{} sampler {}", label, s);
                AnimationSampler sampler;
                if (gltfSampler.interpolation == "LINEAR") sampler.interpolation = Interpolation::Linear;
                else if (gltfSampler.interpolation == "STEP") sampler.interpolation = Interpolation::Step;
                else if (gltfSampler.interpolation == "CUBICSPLINE") sampler.interpolation = Interpolation::CubicSpline;
                else
                    fail(fmt::format("{} has interpolation '{}'; glTF allows LINEAR, STEP and CUBICSPLINE", where, gltfSampler.interpolation));
                if (accessorAt(gltfSampler.input, where + " input").type != TINYGLTF_TYPE_SCALAR)
                    fail(fmt::format("{} input accessor {} is not SCALAR (keyframe times are FLOAT SCALAR)", where, gltfSampler.input));
                sampler.times = readFloats(gltfSampler.input, 1, Attribute::Float, where + " input");
                if (sampler.times.empty()) fail(fmt::format("{} input accessor {} has no keyframes", where, gltfSampler.input));
                for (size_t k = 0; k < sampler.times.size(); ++k) {
                    const float t = sampler.times[k];
                    if (!std::isfinite(t) || t < 0.0f)
                        fail(fmt::format("{} input has keyframe time {} (keyframe {}); times must be finite and >= 0", where, t, k));
                    if (k > 0 && !(t > sampler.times[k - 1]))
                        fail(fmt::format("{} input is not strictly increasing: keyframe {} at {} s follows {} s", where, k, t,
                                         sampler.times[k - 1]));
                }
                const tinygltf::Accessor& output = accessorAt(gltfSampler.output, where + " output");
                const int width = tinygltf::GetNumComponentsInType(uint32_t(output.type));
                if (width != 1 && width != 3 && width != 4)
                    fail(fmt::format("{} output accessor {} has {} components per element; keyframe values are SCALAR (weights), VEC3 "
                                     "(translation, scale) or VEC4 (rotation)",
                                     where, gltfSampler.output, width));
                sampler.values = readFloats(gltfSampler.output, width, Attribute::AnimationOutput, where + " output");
                const bool cubic = sampler.interpolation == Interpolation::CubicSpline;
                const size_t keys = sampler.times.size(), perKey = cubic ? 3 : 1, elements = sampler.values.size() / size_t(width);
                if (width > 1 ? elements != keys * perKey : (elements == 0 || elements % (keys * perKey) != 0))
                    fail(fmt::format("{} output accessor {} has {} elements for {} keyframes; it needs {}{}", where, gltfSampler.output,
                                     elements, keys,
                                     width > 1 ? fmt::format("{}", keys * perKey) : fmt::format("a multiple of {}", keys * perKey),
                                     width > 1 ? (cubic ? " (in-tangent, value and out-tangent per keyframe for CUBICSPLINE)"
                                                        : " (one value per keyframe)")
                                               : (cubic ? " (keyframes x morph targets x 3 for CUBICSPLINE)" : " (keyframes x morph targets)")));
                for (float v : sampler.values)
                    if (!std::isfinite(v)) fail(fmt::format("{} output holds NaN or Inf", where));
                sampler.components = uint32_t(width > 1 ? size_t(width) : elements / (keys * perKey));
                animation.duration = std::max(animation.duration, sampler.times.back());
                animation.samplers.push_back(std::move(sampler));
                outputs.push_back(Output{output.componentType, width});
            }
            for (size_t c = 0; c < gltfAnimation.channels.size(); ++c) {
                const tinygltf::AnimationChannel& gltfChannel = gltfAnimation.channels[c];
                const std::string where = fmt::format("{} channel {}", label, c);
                const std::string& path = gltfChannel.target_path;
                AnimationChannel channel;
                if (path == "translation") channel.path = AnimationPath::Translation;
                else if (path == "rotation") channel.path = AnimationPath::Rotation;
                else if (path == "scale") channel.path = AnimationPath::Scale;
                else if (path == "weights") channel.path = AnimationPath::Weights;
                else {
                    warn(fmt::format("{}: ignoring target path '{}' (Janus animates translation, rotation, scale and weights)", where, path));
                    continue;
                }
                if (gltfChannel.target_node < 0) {
                    warn(fmt::format("{}: ignoring a channel without a target node", where));
                    continue;
                }
                if (gltfChannel.sampler < 0 || size_t(gltfChannel.sampler) >= animation.samplers.size())
                    fail(fmt::format("{} uses sampler {} but the animation has {}", where, gltfChannel.sampler, animation.samplers.size()));
                if (size_t(gltfChannel.target_node) >= m_model.nodes.size())
                    fail(fmt::format("{} targets node {}, which does not exist (the file has {} nodes)", where, gltfChannel.target_node,
                                     m_model.nodes.size()));
                const int nodeIndex = gltfChannel.target_node;
                const tinygltf::Node& node = m_model.nodes[size_t(nodeIndex)];
                if (node.matrix.size() == 16)
                    fail(fmt::format("{} animates the {} of node '{}', which has a 'matrix'; glTF animates only nodes given by "
                                     "translation, rotation and scale",
                                     where, path, nodeLabel(nodeIndex)));
                channel.sampler = uint32_t(gltfChannel.sampler);
                channel.node = uint32_t(nodeIndex);
                const Output& output = outputs[channel.sampler];
                const AnimationSampler& sampler = animation.samplers[channel.sampler];
                switch (channel.path) {
                    case AnimationPath::Translation:
                    case AnimationPath::Scale:
                        if (output.width != 3 || output.componentType != TINYGLTF_COMPONENT_TYPE_FLOAT)
                            fail(fmt::format("{} animates {} with sampler {}, whose output is not VEC3 FLOAT", where, path, channel.sampler));
                        break;
                    case AnimationPath::Rotation:
                        if (output.width != 4)
                            fail(fmt::format("{} animates rotation with sampler {}, whose output is not VEC4 (xyzw quaternions)", where,
                                             channel.sampler));
                        break;
                    case AnimationPath::Weights: {
                        const size_t targets =
                            node.mesh >= 0 && size_t(node.mesh) < m_model.meshes.size() && !m_model.meshes[size_t(node.mesh)].primitives.empty()
                                ? m_model.meshes[size_t(node.mesh)].primitives[0].targets.size()
                                : 0;
                        if (targets == 0)
                            fail(fmt::format("{} animates the morph weights of node '{}', which has no mesh with morph targets", where,
                                             nodeLabel(nodeIndex)));
                        if (output.width != 1 || sampler.components != targets)
                            fail(fmt::format("{} animates the weights of node '{}' ({} morph targets) with sampler {}, whose output gives {} "
                                             "values per keyframe; it needs one SCALAR per morph target",
                                             where, nodeLabel(nodeIndex), targets, channel.sampler,
                                             output.width == 1 ? sampler.components : uint32_t(output.width)));
                        break;
                    }
                }
                animation.channels.push_back(channel);
            }
            scene.animations.push_back(std::move(animation));
        }
    }

    std::string nodeLabel(int index) const {
        const std::string& name = m_model.nodes[size_t(index)].name;
        return name.empty() ? fmt::format("#{}", index) : name;
    }

    void readCamera(int index, const glm::mat4& world, const std::string& name) {
        const tinygltf::Node& node = m_model.nodes[size_t(index)];
        if (size_t(node.camera) >= m_model.cameras.size()) fail(fmt::format("node '{}' references missing camera {}", name, node.camera));
        const tinygltf::Camera& camera = m_model.cameras[size_t(node.camera)];
        const std::string label = fmt::format("camera {} ('{}')", node.camera, camera.name);
        if (camera.type == "perspective") {
            m_camera.projection = CameraProjection::Perspective;
            m_camera.fovYRadians = float(camera.perspective.yfov);
            m_camera.nearPlane = float(camera.perspective.znear);
            // zfar 0 means an infinite projection in glTF; a large finite far plane keeps ours simple.
            m_camera.farPlane = camera.perspective.zfar > 0.0 ? float(camera.perspective.zfar) : m_camera.nearPlane * 1.0e5f;
        } else if (camera.type == "orthographic") {
            const tinygltf::OrthographicCamera& ortho = camera.orthographic;
            // glTF: xmag and ymag non-zero (negative ones would mirror the image: refused), zfar > znear >= 0.
            if (!(ortho.ymag > 0.0) || !(ortho.xmag > 0.0) || !std::isfinite(ortho.xmag) || !std::isfinite(ortho.ymag))
                fail(fmt::format("{} is orthographic with xmag {} and ymag {}; both must be finite and > 0", label, ortho.xmag, ortho.ymag));
            if (!(ortho.znear >= 0.0) || !(ortho.zfar > ortho.znear) || !std::isfinite(ortho.zfar))
                fail(fmt::format("{} is orthographic with znear {} and zfar {}; it needs 0 <= znear < zfar (zfar is required)", label,
                                 ortho.znear, ortho.zfar));
            m_camera.projection = CameraProjection::Orthographic;
            m_camera.orthographicHalfHeight = float(ortho.ymag);
            m_camera.nearPlane = float(ortho.znear);
            m_camera.farPlane = float(ortho.zfar);
        } else {
            fail(fmt::format("{} has type '{}'; glTF cameras are \"perspective\" or \"orthographic\"", label, camera.type));
        }
        placeCamera(m_camera, world);
        m_camera.node = index;
        m_cameraFound = true;
    }

    bool hasExplicitRange(int index) const {
        auto it = m_model.extensions.find("KHR_lights_punctual");
        if (it == m_model.extensions.end() || !it->second.IsObject() || !it->second.Has("lights")) return false;
        const tinygltf::Value& lights = it->second.Get("lights");
        if (!lights.IsArray() || size_t(index) >= lights.ArrayLen()) return false;
        const tinygltf::Value& light = lights.Get(index);
        return light.IsObject() && light.Has("range");
    }

    void readLight(int index, const glm::mat4& world, const std::string& nodeName, Scene& scene) {
        if (index < 0 || size_t(index) >= m_model.lights.size())
            fail(fmt::format("node '{}' references KHR_lights_punctual light {} but the file has {}", nodeName, index,
                             m_model.lights.size()));
        const tinygltf::Light& gltfLight = m_model.lights[size_t(index)];
        Light light;
        if (gltfLight.type == "directional") light.type = LightType::Directional;
        else if (gltfLight.type == "point") light.type = LightType::Point;
        else if (gltfLight.type == "spot") light.type = LightType::Spot;
        else fail(fmt::format("light '{}' has unknown type '{}'", gltfLight.name, gltfLight.type));
        if (gltfLight.color.size() == 3) light.color = glm::vec3(gltfLight.color[0], gltfLight.color[1], gltfLight.color[2]);
        light.intensity = float(gltfLight.intensity);
        placeLight(light, world);
        // KHR_lights_punctual: no range means infinite. tinygltf reads a missing range as 0, so
        // whether the file gave one comes from the extension's JSON. A range it gives is kept as
        // it is, also <= 0 (which the extension forbids): such a light lights nothing, as
        // docs/SCENES.md says for every light, rather than becoming infinite.
        if (hasExplicitRange(index)) light.range = float(gltfLight.range);
        light.innerConeAngle = float(gltfLight.spot.innerConeAngle);
        light.outerConeAngle = float(gltfLight.spot.outerConeAngle);
        if (const char* why = darkLightReason(light))
            warn(fmt::format("KHR_lights_punctual light {}{} on node '{}' lights nothing ({}); the renderer skips it", index,
                             gltfLight.name.empty() ? std::string() : fmt::format(" ('{}')", gltfLight.name), nodeName, why));
        scene.lights.push_back(light);
    }

    // Walks the default scene's node trees depth first, parents before children in file order,
    // with an explicit stack: a hierarchy 100000 nodes deep must not overflow the call stack.
    // glTF node hierarchies are disjoint trees, so every node is reached at most once: a node
    // that is its own ancestor (a cycle) or has two parents is an error, which also keeps a
    // crafted file from multiplying instances exponentially through shared children.
    void readNodes(Scene& scene) {
        std::vector<int> roots;
        if (m_options.scene && *m_options.scene >= m_model.scenes.size())
            fail(fmt::format("scene {} does not exist: the file has {} scene(s){}", *m_options.scene, m_model.scenes.size(),
                             m_model.scenes.empty() ? "" : fmt::format(" (0 to {})", m_model.scenes.size() - 1)));
        if (!m_model.scenes.empty()) {
            const int sceneIndex = m_options.scene ? int(*m_options.scene) : m_model.defaultScene >= 0 ? m_model.defaultScene : 0;
            if (size_t(sceneIndex) >= m_model.scenes.size()) fail(fmt::format("default scene {} does not exist", sceneIndex));
            roots = m_model.scenes[size_t(sceneIndex)].nodes;
        } else {
            // No scene list: every node that is nobody's child is a root.
            std::vector<bool> isChild(m_model.nodes.size(), false);
            for (const tinygltf::Node& node : m_model.nodes)
                for (int c : node.children)
                    if (c >= 0 && size_t(c) < isChild.size()) isChild[size_t(c)] = true;
            for (size_t n = 0; n < m_model.nodes.size(); ++n)
                if (!isChild[n]) roots.push_back(int(n));
        }
        enum : uint8_t { Unvisited, OnPath, Done };
        std::vector<uint8_t> state(m_model.nodes.size(), Unvisited);
        struct Frame {
            int node;
            glm::mat4 world;
            size_t nextChild;
        };
        std::vector<Frame> stack;
        // Reaches `index` from `parent` (-1 for a root): checks it, reads it and makes it the top of the stack.
        auto enter = [&](int index, int parent, const glm::mat4& parentWorld) {
            if (index < 0 || size_t(index) >= m_model.nodes.size())
                fail(parent < 0 ? fmt::format("scene root node {} does not exist (the file has {})", index, m_model.nodes.size())
                                : fmt::format("node '{}' has child {}, which does not exist (the file has {} nodes)", nodeLabel(parent),
                                              index, m_model.nodes.size()));
            if (state[size_t(index)] == OnPath)
                fail(fmt::format("node {} ('{}') is its own ancestor (cycle in 'children', through node '{}'); glTF node hierarchies must "
                                 "be trees",
                                 index, nodeLabel(index), nodeLabel(parent)));
            if (state[size_t(index)] == Done)
                fail(fmt::format("node {} ('{}') is reached twice ({}); glTF nodes have at most one parent and are not also scene roots",
                                 index, nodeLabel(index),
                                 parent < 0 ? std::string("listed as a root after being reached")
                                            : fmt::format("again as a child of '{}'", nodeLabel(parent))));
            state[size_t(index)] = OnPath;
            const glm::mat4 world = parentWorld * localMatrix(m_model.nodes[size_t(index)]);
            readNode(index, world, scene);
            stack.push_back(Frame{index, world, 0});
        };
        for (int root : roots) {
            enter(root, -1, glm::mat4(1.0f));
            while (!stack.empty()) {
                Frame& top = stack.back();
                const std::vector<int>& children = m_model.nodes[size_t(top.node)].children;
                if (top.nextChild < children.size()) {
                    const int child = children[top.nextChild++];
                    const int parent = top.node;
                    const glm::mat4 parentWorld = top.world;   // `top` dies when enter() grows the stack
                    enter(child, parent, parentWorld);
                } else {
                    state[size_t(top.node)] = Done;
                    stack.pop_back();
                }
            }
        }
        // Without a scene list every node is reached from a root unless it lies on (or under) a
        // cycle, which then has no root.
        if (m_model.scenes.empty())
            for (size_t n = 0; n < m_model.nodes.size(); ++n)
                if (state[n] == Unvisited)
                    fail(fmt::format("node {} ('{}') is on or below a cycle in 'children' (no node of the cycle is a root); glTF node "
                                     "hierarchies must be trees",
                                     n, nodeLabel(int(n))));
    }

    std::filesystem::path m_path;
    tinygltf::Model& m_model;
    SceneLoadOptions m_options;
    std::map<std::tuple<int, int, bool>, int32_t> m_textureCache;   // (image, sampler, sRGB)
    std::map<int, std::vector<uint32_t>> m_meshPrimitives;
    std::vector<std::string> m_meshLabels;        // per Scene::meshes entry: "mesh 'name' primitive p"
    // Per skinned Scene::meshes entry: the highest joint index that carries weight, and a vertex using it.
    struct MaxJoint {
        uint32_t joint = 0;
        size_t vertex = SIZE_MAX;
    };
    std::map<size_t, MaxJoint> m_maxJoint;
    std::map<uint32_t, uint32_t> m_unskinned;     // skinned mesh -> its copy without joints (unskinnedCopy)
    uint64_t m_jointMatrices = 0;                 // joint matrices of the skinned instances so far (kMaxJointMatrices)
    Camera m_camera;
    bool m_cameraFound = false;
    std::vector<std::string> m_warnings;
};

}  // namespace

Scene loadGltf(const std::filesystem::path& path, bool& hasCamera, const SceneLoadOptions& options) {
    std::error_code ec;
    if (!std::filesystem::exists(path, ec))
        throw SceneError(fmt::format("{}: no such file (check the path; scene files resolve 'gltf' relative to themselves)",
                                     path.string()));
    if (!std::filesystem::is_regular_file(path, ec))
        throw SceneError(fmt::format("{}: not a regular file (a directory, FIFO or device); give a .gltf or .glb file", path.string()));
    std::vector<char> bytes;
    {
        std::ifstream in(path, std::ios::binary);
        const uint64_t size = std::filesystem::file_size(path, ec);
        if (!in || ec) throw SceneError(fmt::format("{}: cannot be read", path.string()));
        if (size > UINT32_MAX) throw SceneError(fmt::format("{}: is larger than 4 GiB, which glTF files cannot be", path.string()));
        bytes.resize(size_t(size));
        if (!in.read(bytes.data(), std::streamsize(size))) throw SceneError(fmt::format("{}: cannot be read", path.string()));
    }
    return loadGltfFromMemory(std::string_view(bytes.data(), bytes.size()), path, hasCamera, options);
}

Scene loadGltfFromMemory(std::string_view bytes, const std::filesystem::path& path, bool& hasCamera, const SceneLoadOptions& options) {
    std::error_code ec;
    if (bytes.size() > UINT32_MAX) throw SceneError(fmt::format("{}: is larger than 4 GiB, which glTF files cannot be", path.string()));
    const bool binary = lowerCaseExtension(path) == ".glb";

    LoadContext context;
    context.folder = std::filesystem::absolute(path, ec).parent_path().lexically_normal();
    // lexically_normal keeps a trailing separator on some folders; tinygltf adds its own '/'.
    std::string folder = context.folder.string();
    while (folder.size() > 1 && folder.back() == '/') folder.pop_back();
    context.folder = folder;
    context.uriPrefix = folder == "/" ? folder : folder + "/";
    context.allowOutside = options.allowPathsOutsideSceneFolder;
    std::vector<std::string> skipped;   // animation channels without a target node (tinygltf drops them)
    if (std::optional<std::string_view> text = binary ? glbJson(bytes) : std::string_view(bytes.data(), bytes.size())) {
        // JSON that does not parse is left to tinygltf, which says where.
        const nlohmann::json root = nlohmann::json::parse(text->begin(), text->end(), nullptr, /*allow_exceptions=*/false);
        if (!root.is_discarded()) {
            if (const std::string problem = gltfSchemaProblem(root); !problem.empty())
                throw SceneError(fmt::format("{}: malformed glTF: {}", path.string(), problem));
            checkReferences(root, context);
            skipped = nodelessChannels(root);
        }
    }
    if (!context.refusal.empty()) throw SceneError(fmt::format("{}: {}", path.string(), context.refusal));

    tinygltf::Model model;
    tinygltf::TinyGLTF loader;
    loader.SetFsCallbacks(
        tinygltf::FsCallbacks{&fileExists, &expandFilePath, &tinygltf::ReadWholeFile, &tinygltf::WriteWholeFile, &context});
    loader.SetImageLoader(&loadImage, &context);
    std::string error, warning;
    const bool ok = binary ? loader.LoadBinaryFromMemory(&model, &error, &warning, reinterpret_cast<const unsigned char*>(bytes.data()),
                                                         unsigned(bytes.size()), folder)
                           : loader.LoadASCIIFromString(&model, &error, &warning, bytes.data(), unsigned(bytes.size()), folder);
    // A refused URI or image makes tinygltf fail (or, for images, only warn): say why.
    if (!context.refusal.empty()) throw SceneError(fmt::format("{}: {}", path.string(), context.refusal));
    if (!ok) {
        std::string reason = error.empty() ? warning : error;
        while (!reason.empty() && (reason.back() == '\n' || reason.back() == ' ')) reason.pop_back();
        throw SceneError(fmt::format("{}: malformed glTF: {}", path.string(), reason.empty() ? "tinygltf gave no reason" : reason));
    }
    decodeImages(context, model, path);
    Scene scene = GltfReader(path, model, options).read(hasCamera);
    for (const std::string& what : skipped) scene.warnings.push_back(fmt::format("{}: {}", path.string(), what));
    return scene;
}

}  // namespace janus::renderer::detail
