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

#include "janus/renderer/image.h"
#include "janus/renderer/scene.h"


namespace fs = std::filesystem;
using namespace janus::renderer;

namespace {

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

