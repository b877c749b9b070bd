// Builds the seed corpus from the shared scenes at fuzz time (scripts/fuzz.sh), so that no scene
// is committed: janus_fuzz_seeds SCENES_DIR SCENE_FILES_DIR OUT_DIR writes
//   OUT/gltf        every small .gltf, its buffers embedded as data: URIs (the fuzzer mutates one
//                   input, not a folder) and its images replaced by fuzz/assets/tex.png (decoding
//                   large textures would only slow every execution; fuzz_image covers decoders);
//                   a .glb twin with the buffer as BIN chunk when it has a single buffer
//   OUT/image       small .png / .jpg files, and the first .hdr sky shrunk to 32x16 and 4x2 and
//                   written as Radiance HDR (RLE and flat), EXR (each compression, half and float)
//                   and PFM
//   OUT/scene_file  every .json scene file in SCENE_FILES_DIR, its "gltf" pointed at triangle.gltf
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <iterator>
#include <string>
#include <utility>
#include <vector>

#include <nlohmann/json.hpp>
#include <stb_image_write.h>
#include <tinyexr.h>

#include "glb_with_image.h"
#include "gi/gi_bake_file.h"
#include "janus/renderer/image.h"

namespace fs = std::filesystem;
using nlohmann::json;

namespace {

// Larger seeds would slow every execution they are picked for; the structure of a small glTF
// exercises the same code.
constexpr uintmax_t kMaxSeedBytes = 16 * 1024;

std::string readFile(const fs::path& path) {
    std::ifstream in(path, std::ios::binary);
    return std::string((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
}

void writeFile(const fs::path& path, const std::string& bytes) {
    std::ofstream(path, std::ios::binary).write(bytes.data(), std::streamsize(bytes.size()));
}

std::string base64(const std::string& bytes) {
    static const char* digits = "ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789+/";
    std::string out;
    for (size_t i = 0; i < bytes.size(); i += 3) {
        uint32_t v = uint32_t(uint8_t(bytes[i])) << 16;
        if (i + 1 < bytes.size()) v |= uint32_t(uint8_t(bytes[i + 1])) << 8;
        if (i + 2 < bytes.size()) v |= uint32_t(uint8_t(bytes[i + 2]));
        out += digits[(v >> 18) & 63];
        out += digits[(v >> 12) & 63];
        out += i + 1 < bytes.size() ? digits[(v >> 6) & 63] : '=';
        out += i + 2 < bytes.size() ? digits[v & 63] : '=';
    }
    return out;
}

std::string glb(std::string jsonText, std::string bin) { return janus::fuzz::makeGlb(std::move(jsonText), std::move(bin)); }

bool isUri(const json& object) { return object.is_object() && object.contains("uri") && object["uri"].is_string(); }

// Returns how many seeds it wrote (0 or more) for one glTF.
int gltfSeeds(const fs::path& path, const fs::path& out) {
    json gltf = json::parse(readFile(path), nullptr, false);
    if (!gltf.is_object()) return 0;
    std::vector<std::string> buffers;
    for (json& buffer : gltf.value("buffers", json::array())) {
        if (!isUri(buffer)) return 0;
        const std::string uri = buffer["uri"];
        if (uri.rfind("data:", 0) == 0) return 0;
        const fs::path file = path.parent_path() / uri;
        std::error_code ec;
        if (!fs::is_regular_file(file, ec) || fs::file_size(file, ec) > kMaxSeedBytes) return 0;
        buffers.push_back(readFile(file));
    }
    if (gltf.contains("images"))
        for (json& image : gltf["images"])
            if (isUri(image)) image["uri"] = "tex.png";
    const std::string name = path.stem().string();
    json embedded = gltf;
    for (size_t i = 0; i < buffers.size(); ++i)
        embedded["buffers"][i]["uri"] = "data:application/octet-stream;base64," + base64(buffers[i]);
    const std::string text = embedded.dump();
    if (text.size() > kMaxSeedBytes) return 0;
    writeFile(out / "gltf" / (name + ".gltf"), text);
    if (buffers.size() != 1) return 1;
    gltf["buffers"][0].erase("uri");
    writeFile(out / "gltf" / (name + ".glb"), glb(gltf.dump(), buffers[0]));
    return 2;
}

janus::renderer::ImageRGBAF shrink(const janus::renderer::ImageRGBAF& image, uint32_t width, uint32_t height) {
    janus::renderer::ImageRGBAF out;
    out.width = width;
    out.height = height;
    out.pixels.resize(size_t(width) * height * 4);
    for (uint32_t y = 0; y < height; ++y)
        for (uint32_t x = 0; x < width; ++x)
            for (int c = 0; c < 4; ++c)
                out.pixels[(size_t(y) * width + x) * 4 + size_t(c)] =
                    image.pixels[(size_t(y * image.height / height) * image.width + x * image.width / width) * 4 + size_t(c)];
    return out;
}

void appendToString(void* context, void* data, int size) { static_cast<std::string*>(context)->append(static_cast<char*>(data), size_t(size)); }

std::string exr(const janus::renderer::ImageRGBAF& image, int compression, int pixelType) {
    const size_t count = size_t(image.width) * image.height;
    std::vector<float> planes[3];
    const char* names[3] = {"B", "G", "R"};
    unsigned char* pointers[3];
    for (int i = 0; i < 3; ++i) {
        planes[i].resize(count);
        for (size_t p = 0; p < count; ++p) planes[i][p] = image.pixels[p * 4 + size_t(2 - i)];
        pointers[i] = reinterpret_cast<unsigned char*>(planes[i].data());
    }
    EXRImage exrImage;
    InitEXRImage(&exrImage);
    exrImage.num_channels = 3;
    exrImage.images = pointers;
    exrImage.width = int(image.width);
    exrImage.height = int(image.height);
    EXRHeader header;
    InitEXRHeader(&header);
    EXRChannelInfo channels[3] = {};
    int inputTypes[3], storedTypes[3];
    for (int i = 0; i < 3; ++i) {
        channels[i].name[0] = names[i][0];
        inputTypes[i] = TINYEXR_PIXELTYPE_FLOAT;
        storedTypes[i] = pixelType;
    }
    header.num_channels = 3;
    header.channels = channels;
    header.pixel_types = inputTypes;
    header.requested_pixel_types = storedTypes;
    header.compression_type = compression;
    unsigned char* memory = nullptr;
    const char* error = nullptr;
    const size_t size = SaveEXRImageToMemory(&exrImage, &header, &memory, &error);
    if (error) FreeEXRErrorMessage(error);
    std::string bytes(reinterpret_cast<char*>(memory), size);
    std::free(memory);
    return bytes;
}

void imageSeeds(const fs::path& scenes, const fs::path& out, int& written) {
    bool skyDone = false;
    for (const fs::directory_entry& entry : fs::recursive_directory_iterator(scenes)) {
        if (!entry.is_regular_file()) continue;
        const fs::path& path = entry.path();
        const std::string extension = path.extension().string();
        if ((extension == ".png" || extension == ".jpg") && entry.file_size() <= 16 * 1024) {
            fs::copy_file(path, out / "image" / (path.parent_path().parent_path().filename().string() + "-" + path.filename().string()),
                          fs::copy_options::overwrite_existing);
            ++written;
        }
        if (extension != ".hdr" || skyDone) continue;
        skyDone = true;
        const janus::renderer::ImageRGBAF sky = janus::renderer::readRadianceHDR(path);
        for (auto [width, height] : {std::pair{32u, 16u}, std::pair{4u, 2u}}) {
            const janus::renderer::ImageRGBAF small = shrink(sky, width, height);
            const std::string stem = "sky-" + std::to_string(width) + "x" + std::to_string(height);
            std::string hdr;
            stbi_write_hdr_to_func(appendToString, &hdr, int(width), int(height), 4, small.pixels.data());
            writeFile(out / "image" / (stem + ".hdr"), hdr);   // RLE scanlines at width 32, flat at 4
            janus::renderer::writePFM(out / "image" / (stem + ".pfm"), small);
            written += 2;
            for (int compression : {TINYEXR_COMPRESSIONTYPE_NONE, TINYEXR_COMPRESSIONTYPE_RLE, TINYEXR_COMPRESSIONTYPE_ZIPS,
                                    TINYEXR_COMPRESSIONTYPE_ZIP, TINYEXR_COMPRESSIONTYPE_PIZ})
                for (int type : {TINYEXR_PIXELTYPE_HALF, TINYEXR_PIXELTYPE_FLOAT}) {
                    writeFile(out / "image" / (stem + "-c" + std::to_string(compression) + "-t" + std::to_string(type) + ".exr"),
                              exr(small, compression, type));
                    ++written;
                }
        }
    }
}

}  // namespace

// GI bake files in this build's format (so a format change never leaves the seeds stale): a
// small bake made by hand, one per kind of brick mix, written by the renderer's own writer.
int giBakeSeeds(const fs::path& out) {
    using namespace janus::renderer;
    int count = 0;
    for (const bool withSky : {false, true}) {
        IrradianceVolume volume;
        volume.probeCounts = glm::uvec3(2, 1, 1);
        volume.surfelsPerProbe = 16;
        GiBake bake;
        bake.probeCounts = volume.probeCounts;
        bake.samplesPerProbe = volume.surfelsPerProbe;
        for (uint32_t p = 0; p < 2; ++p) {
            bake.probePositions.push_back(glm::vec3(float(p) - 0.5f, 0.0f, 0.0f));
            bake.backFaceFraction.push_back(0.0f);
            bake.valid.push_back(true);
            bake.probeFirstTransfer.push_back(p * 2);
            bake.probeTransferCount.push_back(2);
        }
        for (uint32_t b = 0; b < 3; ++b) {
            GiSurfel surfel;
            surfel.position = glm::vec3(float(b), -1.0f, 0.0f);
            surfel.normal = surfel.faceNormal = glm::vec3(0.0f, 1.0f, 0.0f);
            surfel.albedo = glm::vec3(0.5f);
            surfel.emission = glm::vec3(float(b));
            surfel.renderingLayers = 1u << b;
            bake.surfels.push_back(surfel);
            bake.bricks.push_back(GiBrick{b, 1, false, glm::vec3(0.0f)});
        }
        if (withSky) bake.bricks.push_back(GiBrick{0, 0, true, glm::vec3(0.0f, 1.0f, 0.0f)});
        for (uint32_t t = 0; t < 4; ++t) {
            GiTransfer transfer;
            transfer.brick = t % uint32_t(bake.bricks.size());
            for (size_t k = 0; k < 9; ++k) transfer.sh[k] = 0.1f * float(k + t);
            bake.transfers.push_back(transfer);
        }
        if (withSky)   // and visibility maps
            for (size_t i = 0; i < 2 * size_t(kGiVisibilityResolution) * kGiVisibilityResolution; ++i) {
                const float mean = 1.0f + float(i % 5) * 0.5f;
                bake.distanceMoments.push_back(glm::vec2(mean, mean * mean + 0.01f));
            }
        writeGiBakeFile(out / "gi_bake" / (withSky ? "with-sky.bake" : "surfels.bake"), bake, volume, 0x5eedu);
        ++count;
    }
    return count;
}

int main(int argc, char** argv) {
    if (argc != 4) {
        std::cerr << "usage: janus_fuzz_seeds SCENES_DIR SCENE_FILES_DIR OUT_DIR\n";
        return 2;
    }
    const fs::path scenes = argv[1], sceneFiles = argv[2], out = argv[3];
    for (const char* dir : {"gltf", "image", "scene_file", "gi_bake"}) fs::create_directories(out / dir);
    int gltfCount = 0, imageCount = 0, sceneCount = 0;
    for (const fs::directory_entry& entry : fs::recursive_directory_iterator(scenes))
        if (entry.is_regular_file() && entry.path().extension() == ".gltf" && entry.file_size() <= kMaxSeedBytes)
            gltfCount += gltfSeeds(entry.path(), out);
    imageSeeds(scenes, out, imageCount);
    for (const fs::path& dir : {scenes, sceneFiles})
        for (const fs::directory_entry& entry : fs::recursive_directory_iterator(dir)) {
            if (!entry.is_regular_file() || entry.path().extension() != ".json") continue;
            json scene = json::parse(readFile(entry.path()), nullptr, false);
            if (!scene.is_object() || !scene.contains("gltf")) continue;
            scene["gltf"] = "triangle.gltf";
            writeFile(out / "scene_file" / entry.path().filename(), scene.dump(2));
            ++sceneCount;
        }
    const int bakeCount = giBakeSeeds(out);
    std::cout << "seeds: " << gltfCount << " glTF/GLB, " << imageCount << " images, " << sceneCount << " scene files, " << bakeCount
              << " GI bake files in " << out.string() << "\n";
    return 0;
}
