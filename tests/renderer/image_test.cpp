// image.h: comparison, heat maps, file formats and the atomicity of every writer.
#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cerrno>
#include <cmath>
#include <csignal>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <limits>
#include <string>
#include <vector>

#include <sys/resource.h>
#include <sys/wait.h>
#include <unistd.h>

#include "janus/renderer/image.h"

namespace fs = std::filesystem;
using namespace janus::renderer;

namespace {

ImageRGBA8 solidImage(uint32_t width, uint32_t height, std::array<uint8_t, 4> rgba) {
    ImageRGBA8 image{width, height, {}};
    for (uint32_t i = 0; i < width * height; ++i) image.pixels.insert(image.pixels.end(), rgba.begin(), rgba.end());
    return image;
}

// Every channel of every pixel distinct-ish, alpha included, so a row flip, channel swap or
// premultiplication would show.
ImageRGBA8 patternImage(uint32_t width, uint32_t height) {
    ImageRGBA8 image{width, height, std::vector<uint8_t>(size_t(width) * height * 4)};
    for (uint32_t y = 0; y < height; ++y)
        for (uint32_t x = 0; x < width; ++x) {
            uint8_t* p = &image.pixels[(size_t(y) * width + x) * 4];
            p[0] = uint8_t(x * 7 + y);
            p[1] = uint8_t(y * 13 + 5);
            p[2] = uint8_t((x ^ y) * 3);
            p[3] = uint8_t(255 - x - y);
        }
    return image;
}

ImageRGBAF patternImageF(uint32_t width, uint32_t height) {
    ImageRGBAF image{width, height, std::vector<float>(size_t(width) * height * 4)};
    for (uint32_t y = 0; y < height; ++y)
        for (uint32_t x = 0; x < width; ++x) {
            float* p = &image.pixels[(size_t(y) * width + x) * 4];
            p[0] = float(x) * 0.25f + float(y) * 100.0f;   // HDR values well above 1
            p[1] = -float(x + 1) / 3.0f;                    // negatives survive float formats
            p[2] = 1e-6f * float(y + 1);
            p[3] = 0.5f + float(x) / 64.0f;
        }
    return image;
}

std::string readFile(const fs::path& path) {
    std::ifstream in(path, std::ios::binary);
    return {std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
}

std::vector<std::string> directoryEntries(const fs::path& dir) {
    std::vector<std::string> names;
    for (const auto& entry : fs::directory_iterator(dir)) names.push_back(entry.path().filename().string());
    std::sort(names.begin(), names.end());
    return names;
}

class ImageFiles : public ::testing::Test {
protected:
    void SetUp() override {
        std::string pattern = (fs::temp_directory_path() / "janus-image-test-XXXXXX").string();
        ASSERT_NE(::mkdtemp(pattern.data()), nullptr) << std::strerror(errno);
        dir = pattern;
    }
    void TearDown() override {
        std::error_code ec;
        fs::remove_all(dir, ec);
    }
    fs::path dir;
};

}  // namespace

// ---- comparison ---------------------------------------------------------------------------

TEST(CompareImages, IdenticalImagesHaveInfinitePsnrAndNoDifferences) {
    const ImageRGBA8 a = patternImage(5, 3);
    const ImageDifference diff = compareImages(a, a);
    EXPECT_EQ(diff.maxChannelDifference, 0u);
    EXPECT_TRUE(std::isinf(diff.psnr) && diff.psnr > 0);
    EXPECT_EQ(diff.differingPixels, 0u);
    EXPECT_EQ(diff.totalPixels, 15u);
}

TEST(CompareImages, CountsMaxDifferencePsnrAndPixelsAboveThreshold) {
    const ImageRGBA8 a = solidImage(4, 2, {100, 100, 100, 200});
    ImageRGBA8 b = a;
    b.pixels[0 * 4 + 0] += 1;   // pixel 0: red +1
    b.pixels[1 * 4 + 1] += 3;   // pixel 1: green +3
    b.pixels[2 * 4 + 3] -= 5;   // pixel 2: alpha -5 (alpha counts like any channel)
    b.pixels[2 * 4 + 2] -= 2;   //          and blue -2; the pixel's largest difference is 5

    const ImageDifference exact = compareImages(a, b);
    EXPECT_EQ(exact.maxChannelDifference, 5u);
    EXPECT_EQ(exact.differingPixels, 3u);
    EXPECT_EQ(exact.totalPixels, 8u);
    // MSE over all 32 channel values: (1 + 9 + 25 + 4) / 32.
    const double expectedPsnr = 10.0 * std::log10(255.0 * 255.0 / (39.0 / 32.0));
    EXPECT_DOUBLE_EQ(exact.psnr, expectedPsnr);

    EXPECT_EQ(compareImages(a, b, 1).differingPixels, 2u);   // the +1 pixel is within threshold
    EXPECT_EQ(compareImages(a, b, 3).differingPixels, 1u);
    EXPECT_EQ(compareImages(a, b, 5).differingPixels, 0u);
    EXPECT_EQ(compareImages(a, b, 5).maxChannelDifference, 5u);   // the threshold only affects the count
}

TEST(CompareImages, IsSymmetric) {
    const ImageRGBA8 a = patternImage(6, 4);
    ImageRGBA8 b = a;
    b.pixels[7] = uint8_t(b.pixels[7] + 40);
    const ImageDifference ab = compareImages(a, b, 2);
    const ImageDifference ba = compareImages(b, a, 2);
    EXPECT_EQ(ab.maxChannelDifference, ba.maxChannelDifference);
    EXPECT_EQ(ab.differingPixels, ba.differingPixels);
    EXPECT_DOUBLE_EQ(ab.psnr, ba.psnr);
}

TEST(CompareImages, RejectsImagesOfDifferentSizes) {
    EXPECT_THROW(compareImages(solidImage(4, 2, {}), solidImage(2, 4, {})), std::invalid_argument);
    ImageRGBA8 truncated = solidImage(4, 2, {});
    truncated.pixels.pop_back();
    EXPECT_THROW(compareImages(solidImage(4, 2, {}), truncated), std::invalid_argument);
    EXPECT_THROW(differenceHeatmap(solidImage(4, 2, {}), solidImage(4, 3, {})), std::invalid_argument);
}

// ---- heat map -----------------------------------------------------------------------------

TEST(DifferenceHeatmap, MapsDifferencesToBlackBlueGreenYellowRed) {
    const ImageRGBA8 a = solidImage(6, 1, {50, 50, 50, 255});
    ImageRGBA8 b = a;
    const int differences[6] = {0, 1, 3, 6, 9, 40};   // with full scale 9: 0, 1/9, 1/3, 2/3, 1, >1
    for (int i = 0; i < 6; ++i) b.pixels[size_t(i) * 4 + 1] = uint8_t(50 + differences[i]);

    const ImageRGBA8 heat = differenceHeatmap(a, b, 9);
    ASSERT_EQ(heat.width, 6u);
    ASSERT_EQ(heat.height, 1u);
    auto pixel = [&](int i) {
        return std::array<int, 4>{heat.pixels[size_t(i) * 4], heat.pixels[size_t(i) * 4 + 1], heat.pixels[size_t(i) * 4 + 2],
                                  heat.pixels[size_t(i) * 4 + 3]};
    };
    EXPECT_EQ(pixel(0), (std::array<int, 4>{0, 0, 0, 255}));       // equal: black
    EXPECT_EQ(pixel(1), (std::array<int, 4>{0, 85, 170, 255}));    // a third of the way blue -> green
    EXPECT_EQ(pixel(2), (std::array<int, 4>{0, 255, 0, 255}));     // green
    EXPECT_EQ(pixel(3), (std::array<int, 4>{255, 255, 0, 255}));   // yellow
    EXPECT_EQ(pixel(4), (std::array<int, 4>{255, 0, 0, 255}));     // red at full scale
    EXPECT_EQ(pixel(5), (std::array<int, 4>{255, 0, 0, 255}));     // and beyond
}

TEST(DifferenceHeatmap, ZeroFullScaleMakesAnyDifferenceRed) {
    const ImageRGBA8 a = solidImage(2, 1, {0, 0, 0, 0});
    ImageRGBA8 b = a;
    b.pixels[4] = 1;
    const ImageRGBA8 heat = differenceHeatmap(a, b, 0);
    EXPECT_EQ(std::vector<uint8_t>(heat.pixels.begin(), heat.pixels.end()), (std::vector<uint8_t>{0, 0, 0, 255, 255, 0, 0, 255}));
}

// ---- PNG ----------------------------------------------------------------------------------

TEST_F(ImageFiles, PngRoundTripIsExact) {
    const ImageRGBA8 image = patternImage(37, 23);   // odd sizes catch stride mistakes
    const fs::path file = dir / "round trip.png";
    writePNG(file, image);

    const std::string bytes = readFile(file);
    ASSERT_GE(bytes.size(), 8u);
    EXPECT_EQ(bytes.substr(0, 8), std::string("\x89PNG\r\n\x1a\n", 8));

    const ImageRGBA8 back = readPNG(file);
    EXPECT_EQ(back.width, 37u);
    EXPECT_EQ(back.height, 23u);
    EXPECT_EQ(back.pixels, image.pixels);
    EXPECT_EQ(directoryEntries(dir), std::vector<std::string>{"round trip.png"});   // no temporary left behind
}

TEST_F(ImageFiles, ReadPngReportsMissingAndMalformedFiles) {
    const fs::path missing = dir / "missing.png";
    try {
        readPNG(missing);
        FAIL() << "readPNG of a missing file did not throw";
    } catch (const ImageIOError& e) {
        EXPECT_NE(std::string(e.what()).find(missing.string()), std::string::npos) << e.what();
    }
    const fs::path garbage = dir / "garbage.png";
    std::ofstream(garbage) << "this is not a PNG";
    EXPECT_THROW(readPNG(garbage), ImageIOError);
}

// ---- PFM and EXR --------------------------------------------------------------------------

TEST_F(ImageFiles, PfmIsLittleEndianRgbBottomRowFirstAndRoundTrips) {
    const ImageRGBAF image = patternImageF(3, 2);
    const fs::path file = dir / "hdr.pfm";
    writePFM(file, image);

    const std::string bytes = readFile(file);
    const std::string header = "PF\n3 2\n-1.0\n";
    ASSERT_EQ(bytes.size(), header.size() + 3 * 2 * 3 * sizeof(float));
    EXPECT_EQ(bytes.substr(0, header.size()), header);
    // The first sample is the red of the bottom row's first pixel (row 1 here).
    float first = 0;
    std::memcpy(&first, bytes.data() + header.size(), sizeof(float));   // this machine is little-endian
    EXPECT_EQ(first, image.pixels[(1 * 3 + 0) * 4 + 0]);

    const ImageRGBAF back = readPFM(file);
    ASSERT_EQ(back.width, 3u);
    ASSERT_EQ(back.height, 2u);
    for (size_t p = 0; p < 6; ++p) {
        for (size_t c = 0; c < 3; ++c) EXPECT_EQ(back.pixels[p * 4 + c], image.pixels[p * 4 + c]) << "pixel " << p << " channel " << c;
        EXPECT_EQ(back.pixels[p * 4 + 3], 1.0f);   // PFM has no alpha
    }
}

TEST_F(ImageFiles, ExrRoundTripIsExactIncludingAlpha) {
    const ImageRGBAF image = patternImageF(19, 7);
    const fs::path file = dir / "hdr.exr";
    writeEXR(file, image);
    const std::string bytes = readFile(file);
    ASSERT_GE(bytes.size(), 4u);
    EXPECT_EQ(bytes.substr(0, 4), std::string("\x76\x2f\x31\x01", 4));   // OpenEXR magic

    const ImageRGBAF back = readEXR(file);
    EXPECT_EQ(back.width, 19u);
    EXPECT_EQ(back.height, 7u);
    EXPECT_EQ(back.pixels, image.pixels);   // 32-bit float channels, lossless compression
}

// ---- atomic writes ------------------------------------------------------------------------

TEST_F(ImageFiles, WritersRejectInconsistentImagesWithoutCreatingFiles) {
    ImageRGBA8 empty;
    EXPECT_THROW(writePNG(dir / "empty.png", empty), ImageIOError);
    ImageRGBA8 truncated = patternImage(4, 4);
    truncated.pixels.resize(10);
    EXPECT_THROW(writePNG(dir / "truncated.png", truncated), ImageIOError);
    ImageRGBAF hdr = patternImageF(4, 4);
    hdr.pixels.resize(3);
    EXPECT_THROW(writeEXR(dir / "truncated.exr", hdr), ImageIOError);
    EXPECT_THROW(writePFM(dir / "truncated.pfm", hdr), ImageIOError);
    EXPECT_TRUE(directoryEntries(dir).empty());
}

TEST_F(ImageFiles, WriteIntoMissingDirectoryNamesThePath) {
    const fs::path file = dir / "no-such-dir" / "out.png";
    try {
        writePNG(file, patternImage(2, 2));
        FAIL() << "writing into a missing directory did not throw";
    } catch (const ImageIOError& e) {
        EXPECT_NE(std::string(e.what()).find(file.string()), std::string::npos) << e.what();
    }
    EXPECT_TRUE(directoryEntries(dir).empty());
}

TEST_F(ImageFiles, WriteOntoADirectoryFailsAndLeavesItAlone) {
    fs::create_directory(dir / "taken.png");
    EXPECT_THROW(writePNG(dir / "taken.png", patternImage(2, 2)), ImageIOError);
    EXPECT_TRUE(fs::is_directory(dir / "taken.png"));
    EXPECT_EQ(directoryEntries(dir), std::vector<std::string>{"taken.png"});
}

TEST_F(ImageFiles, ReplacingAFileSwapsTheWholeContent) {
    const fs::path file = dir / "report.json";
    writeFileAtomically(file, std::string(10000, 'a'));
    writeFileAtomically(file, "short");
    EXPECT_EQ(readFile(file), "short");
    EXPECT_EQ(directoryEntries(dir), std::vector<std::string>{"report.json"});
}

// A write that fails half way (here: the file size limit is hit) must leave the previous file
// untouched and no temporary behind. RLIMIT_FSIZE makes write() fail with EFBIG part way through,
// the same path as a full disk, without needing one.
TEST_F(ImageFiles, FailedWriteLeavesPreviousFileAndNoPartialFile) {
    const fs::path file = dir / "image.png";
    writePNG(file, patternImage(8, 8));
    const std::string before = readFile(file);

    rlimit original{};
    ASSERT_EQ(::getrlimit(RLIMIT_FSIZE, &original), 0);
    const auto previousHandler = std::signal(SIGXFSZ, SIG_IGN);   // otherwise exceeding the limit kills the process
    rlimit limited = original;
    limited.rlim_cur = 4096;
    ASSERT_EQ(::setrlimit(RLIMIT_FSIZE, &limited), 0);

    bool threw = false;
    std::string message;
    try {
        writeFileAtomically(file, std::string(64 * 1024, 'x'));
    } catch (const ImageIOError& e) {
        threw = true;
        message = e.what();
    }
    ::setrlimit(RLIMIT_FSIZE, &original);
    std::signal(SIGXFSZ, previousHandler);

    EXPECT_TRUE(threw) << "a write beyond RLIMIT_FSIZE did not throw";
    EXPECT_NE(message.find(file.string()), std::string::npos) << message;
    EXPECT_EQ(readFile(file), before);
    EXPECT_EQ(directoryEntries(dir), std::vector<std::string>{"image.png"});
}

// A write cut short by a signal runs no destructor: the handler's removeTemporaryFilesNow() is
// what removes the temporary file (janus's main calls it on SIGINT, SIGTERM and SIGHUP). A child
// process gets SIGXFSZ in the middle of its write, deterministically, from its file size limit;
// its handler does what janus's does and exits. Before, ".image.png.tmp-XXXXXX" stayed behind.
extern "C" void removeTemporaryFilesAndExit(int) {
    removeTemporaryFilesNow();
    _exit(42);
}

TEST_F(ImageFiles, AWriteInterruptedByASignalLeavesNoTemporaryFileWhenTheHandlerAsks) {
    const fs::path file = dir / "image.png";
    writePNG(file, patternImage(8, 8));
    const std::string before = readFile(file);
    const pid_t child = ::fork();
    ASSERT_GE(child, 0);
    if (child == 0) {
        std::signal(SIGXFSZ, removeTemporaryFilesAndExit);
        rlimit limited{};
        ::getrlimit(RLIMIT_FSIZE, &limited);
        limited.rlim_cur = 4096;
        ::setrlimit(RLIMIT_FSIZE, &limited);
        try {
            writeFileAtomically(file, std::string(64 * 1024, 'x'));
        } catch (...) {
        }
        _exit(1);   // the signal did not come
    }
    int status = 0;
    ASSERT_EQ(::waitpid(child, &status, 0), child);
    ASSERT_TRUE(WIFEXITED(status));
    EXPECT_EQ(WEXITSTATUS(status), 42) << "the write was not interrupted by SIGXFSZ";
    EXPECT_EQ(readFile(file), before);
    EXPECT_EQ(directoryEntries(dir), std::vector<std::string>{"image.png"});
}
