// Regression tests for what fuzzing found (fuzz/, docs/TESTING.md "Fuzzing and sanitizers"):
// each input that crashed, leaked or exhausted memory is in fuzz/corpus/ and must now give a
// clear ImageIOError / SceneError. CPU only. Leaks show only under LeakSanitizer, so those tests
// fail before their fix in scripts/sanitize.sh, not in a plain build.
#include <gtest/gtest.h>

#include <cstring>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <string>

#include <unistd.h>

#include "../../fuzz/glb_with_image.h"
#include "janus/renderer/image.h"
#include "janus/renderer/scene.h"

#include <nlohmann/json.hpp>

namespace fs = std::filesystem;
using namespace janus::renderer;

namespace {

using janus::fuzz::appendU32;

const fs::path kCorpus = JANUS_FUZZ_CORPUS_DIR;

std::string readFile(const fs::path& path) {
    std::ifstream in(path, std::ios::binary);
    EXPECT_TRUE(in) << "missing " << path;
    return {std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
}

template <typename Error, typename Load>
std::string errorOf(Load&& load) {
    try {
        load();
    } catch (const Error& e) {
        return e.what();
    }
    ADD_FAILURE() << "nothing was thrown";
    return {};
}


Scene loadTexture(std::string_view image) { return loadSceneFromMemory(janus::fuzz::glbWithImage(image), fs::temp_directory_path() / "texture.glb"); }

// A valid 2x2 RGBA float EXR (scanline, ZIP) from our writer, in memory.
std::string smallExr() {
    const fs::path file = fs::temp_directory_path() / ("janus-fuzz-findings-" + std::to_string(::getpid()) + ".exr");
    ImageRGBAF image{2, 2, std::vector<float>(16, 0.5f)};
    writeEXR(file, image);
    std::string bytes = readFile(file);
    fs::remove(file);
    return bytes;
}

}  // namespace

// tinyexr's LoadEXRFromMemory returned without freeing the parsed header when the pixels then
// failed to load, and its decoder freed a failed image without its channels: both leaked on every
// such file (LeakSanitizer in fuzz_image).
TEST(FuzzFindings, ExrWhosePixelsFailToDecodeIsRefusedWithoutLeaking) {
    for (const char* name : {"exr-leak-header-after-failed-load.exr", "exr-leak-channels-after-bad-chunk.exr"}) {
        SCOPED_TRACE(name);
        const std::string message = errorOf<ImageIOError>([&] { decodeEXR(readFile(kCorpus / "image" / name), name); });
        EXPECT_NE(message.find(std::string("cannot read EXR '") + name + "'"), std::string::npos) << message;
    }
}

TEST(FuzzFindings, ExrCutShortIsRefusedWithoutLeaking) {
    const std::string exr = smallExr();
    for (size_t size : {size_t(8), exr.size() / 2, exr.size() - 1}) {
        SCOPED_TRACE(size);
        EXPECT_THROW(decodeEXR(std::string_view(exr).substr(0, size), "cut.exr"), ImageIOError);
    }
    EXPECT_EQ(decodeEXR(exr, "whole.exr").pixels, std::vector<float>(16, 0.5f));
}

// A header is a few bytes; the pixels it claims must not be allocated before they are checked.
TEST(FuzzFindings, ExrClaimingMoreThan32MiPixelsIsRefusedFromItsHeader) {
    std::string exr = smallExr();
    const size_t at = exr.find("dataWindow");
    ASSERT_NE(at, std::string::npos);
    // name\0 "box2i"\0 size(4) then min_x, min_y, max_x, max_y.
    const size_t box = at + std::strlen("dataWindow") + 1 + std::strlen("box2i") + 1 + 4;
    const int32_t window[4] = {0, 0, 8191, 8191};
    std::memcpy(&exr[box], window, sizeof(window));
    const std::string message = errorOf<ImageIOError>([&] { decodeEXR(exr, "huge.exr"); });
    EXPECT_NE(message.find("8192x8192 is outside"), std::string::npos) << message;
}

// tinyexr's PIZ decoder copies a chunk's bitmap (its range from the chunk's first 4 bytes) and
// reads the Huffman length before checking either against the chunk: this 2 KiB file made it read
// 1851 bytes past its end (AddressSanitizer in fuzz_image). decodeEXR gives tinyexr a zero-padded
// copy, so the reads stay in owned memory and the chunk is refused. The read past the end shows
// only under AddressSanitizer (scripts/sanitize.sh), where this test failed before the fix.
TEST(FuzzFindings, ExrWithAPizBitmapPastTheEndOfTheFileIsRefused) {
    const std::string message = errorOf<ImageIOError>([] {
        decodeEXR(readFile(kCorpus / "image" / "exr-piz-bitmap-past-the-end.exr"), "sky.exr");
    });
    EXPECT_NE(message.find("sky.exr"), std::string::npos) << message;
}

// stb_image (Debian's, 2022) writes past its 257-entry Huffman arrays when a JPEG's DHT table
// declares more than 256 codes (UBSan in fuzz_image: index 257 out of bounds in
// stbi__build_huffman, then up to 4 KiB written over the decoder's state). The loader now checks
// the tables before stb sees the file. In a plain build stb failed on this file with a generic
// "could not be read", so the test failed before the fix too.
TEST(FuzzFindings, JpegWithAHuffmanTableOfMoreThan256CodesIsRefusedBeforeDecoding) {
    const std::string message = errorOf<SceneError>([] { loadTexture(readFile(kCorpus / "image" / "jpeg-dht-more-than-256-codes.jpg")); });
    EXPECT_NE(message.find("Huffman table"), std::string::npos) << message;
    EXPECT_NE(message.find("at most 256"), std::string::npos) << message;
}

// The same overflow through a DHT table whose 16 code counts run past the end of the file: stb
// reads the missing bytes as 0 and still builds the table, which the first check skipped
// (UBSan in fuzz_image, session 5). Before the fix the check passed the file on to stb.
TEST(FuzzFindings, JpegWithAHuffmanTableCutByTheEndOfTheFileIsRefusedBeforeDecoding) {
    const std::string message = errorOf<SceneError>([] { loadTexture(readFile(kCorpus / "image" / "jpeg-dht-cut-by-end-of-file.jpg")); });
    EXPECT_NE(message.find("Huffman table"), std::string::npos) << message;
    EXPECT_NE(message.find("at most 256"), std::string::npos) << message;
}

// stb_image's RLE scanline reader for Radiance HDR takes a count of 0 as "copy nothing" and
// loops forever without advancing, and it reads bytes past the end of the data as 0: the fuzzed
// 321-byte sky, cut short inside an RLE scanline, hung the loader (fuzz_image, timeout). The
// loader now walks the scanlines first. Before the fix these tests never returned.
TEST(FuzzFindings, RadianceHdrCutInsideAnRleScanlineIsRefusedInsteadOfHanging) {
    const std::string message = errorOf<ImageIOError>([] {
        decodeRadianceHDR(readFile(kCorpus / "image" / "hdr-rle-cut-inside-a-scanline.hdr"), "sky.hdr");
    });
    EXPECT_NE(message.find("ends inside its pixel data"), std::string::npos) << message;
    EXPECT_NE(message.find("sky.hdr"), std::string::npos) << message;
}

// A valid 8x2 RLE sky: each scanline's components one run of 8 (mantissas 128, 64, 32, exponent 129).
std::string rleSky() {
    std::string hdr = "#?RADIANCE\nFORMAT=32-bit_rle_rgbe\n\n-Y 2 +X 8\n";
    for (int row = 0; row < 2; ++row) {
        hdr += std::string{2, 2, 0, 8};
        for (unsigned char value : {128, 64, 32, 129}) hdr += std::string{char(128 + 8), char(value)};
    }
    return hdr;
}
constexpr size_t kRleSkyHeader = 45;   // bytes before the first scanline

TEST(FuzzFindings, RadianceHdrCutAnywhereInItsPixelDataIsRefused) {
    const std::string hdr = rleSky();
    ASSERT_EQ(hdr.substr(kRleSkyHeader - 10, 10), "-Y 2 +X 8\n");
    const ImageRGBAF whole = decodeRadianceHDR(hdr, "whole.hdr");
    ASSERT_EQ(whole.width, 8u);
    ASSERT_EQ(whole.height, 2u);
    EXPECT_FLOAT_EQ(whole.pixels[0], 1.0f);   // 128 * 2^(129 - 136)
    for (size_t cut = kRleSkyHeader; cut < hdr.size(); ++cut) {
        const std::string message = errorOf<ImageIOError>([&] { decodeRadianceHDR(hdr.substr(0, cut), "cut.hdr"); });
        EXPECT_NE(message.find("ends inside its pixel data"), std::string::npos) << "cut at byte " << cut << ": " << message;
    }
}

// A count of 0 inside the data copies nothing, in stb as in Radiance's own reader: the walk that
// refuses cut files must not refuse it.
TEST(FuzzFindings, RadianceHdrWithACountOf0InsideItsDataStillLoads) {
    std::string hdr = rleSky();
    const ImageRGBAF plain = decodeRadianceHDR(hdr, "plain.hdr");
    hdr.insert(kRleSkyHeader + 4 + 2, 1, '\0');   // before the second component's run
    const ImageRGBAF withZero = decodeRadianceHDR(hdr, "zero.hdr");
    EXPECT_EQ(withZero.pixels, plain.pixels);
}

// stb_image's JPEG AC decoder let its bit count go negative on corrupt entropy-coded data and then
// shifted by more than 31 bits (UBSan in fuzz_image), decoding garbage. JPEG textures are now
// decoded by libjpeg-turbo, which stops on corrupt data; before, this texture loaded as noise.
TEST(FuzzFindings, JpegWithCorruptEntropyCodedDataIsRefused) {
    const std::string message = errorOf<SceneError>([] { loadTexture(readFile(kCorpus / "image" / "jpeg-ac-code-bits-below-zero.jpg")); });
    EXPECT_NE(message.find("Corrupt JPEG data"), std::string::npos) << message;   // libjpeg-turbo's reason, passed on
}

TEST(FuzzFindings, ValidJpegAndPngTexturesStillLoad) {
    const fs::path jpeg = fs::path(JANUS_SHARED_SCENES_DIR) / "khronos/Fox/screenshot/screenshot.jpg";
    const fs::path png = fs::path(JANUS_SHARED_SCENES_DIR) / "BoxTextured/glTF/CesiumLogoFlat.png";
    for (const fs::path& file : {jpeg, png}) {
        SCOPED_TRACE(file.string());
        const Scene scene = loadTexture(readFile(file));
        ASSERT_EQ(scene.textures.size(), 1u);
        EXPECT_GT(scene.textures[0].width, 0u);
    }
}

// glTF textures are PNG or JPEG; stb's other decoders (BMP here, GIF, PSD, TGA, PIC, PNM, HDR)
// are no longer reachable from a glTF. Before, this 2x1 BMP loaded.
TEST(FuzzFindings, TexturesOtherThanPngOrJpegAreRefused) {
    std::string bmp = "BM";
    appendU32(bmp, 62);   // file size
    appendU32(bmp, 0);
    appendU32(bmp, 54);   // pixel data offset
    appendU32(bmp, 40);   // BITMAPINFOHEADER
    appendU32(bmp, 2);
    appendU32(bmp, 1);
    bmp += std::string("\x01\x00\x18\x00", 4);   // 1 plane, 24 bits
    for (int i = 0; i < 6; ++i) appendU32(bmp, 0);
    bmp += std::string("\x00\x00\xff\xff\x00\x00\x00\x00", 8);   // two pixels, row padded to 4 bytes
    const std::string message = errorOf<SceneError>([&] { loadTexture(bmp); });
    EXPECT_NE(message.find("neither a PNG nor a JPEG"), std::string::npos) << message;
}

// nlohmann::json reports a number beyond double's range as out_of_range, not parse_error, so it
// escaped the scene-file loader as a foreign exception (fuzz_scene_file: std::terminate).
TEST(FuzzFindings, SceneFileWithANumberBeyondDoubleIsMalformedJson) {
    const std::string json = R"({"gltf": "triangle.gltf", "camera": {"near": 1e400}})";
    const std::string message =
        errorOf<SceneError>([&] { loadSceneFromMemory(json, fs::temp_directory_path() / "overflow.json"); });
    EXPECT_NE(message.find("overflow.json: malformed JSON"), std::string::npos) << message;
    EXPECT_NE(message.find("1e400"), std::string::npos) << message;
    // The file the fuzzer found, through the file API.
    const fs::path file = kCorpus / "scene_file" / "number-overflow-1e390.json";
    EXPECT_NE(errorOf<SceneError>([&] { loadScene(file); }).find("malformed JSON"), std::string::npos);
}
