// CPU images: what renders read back into, what files are written from, what parity compares.
#pragma once

#include <cstdint>
#include <filesystem>
#include <stdexcept>
#include <string>
#include <string_view>
#include <vector>

namespace janus::renderer {

// 8-bit RGBA, row 0 on top, sRGB-encoded when it is a display image.
struct ImageRGBA8 {
    uint32_t width = 0;
    uint32_t height = 0;
    std::vector<uint8_t> pixels;   // width * height * 4
};

// 32-bit float RGBA, row 0 on top, linear.
struct ImageRGBAF {
    uint32_t width = 0;
    uint32_t height = 0;
    std::vector<float> pixels;     // width * height * 4
};

class ImageIOError : public std::runtime_error {
public:
    using std::runtime_error::runtime_error;
};

// Writers are atomic: they write a temporary file beside `path` and rename it into place, so a
// reader never sees a half-written file. They throw ImageIOError naming the path on failure.
void writePNG(const std::filesystem::path& path, const ImageRGBA8& image);
void writePFM(const std::filesystem::path& path, const ImageRGBAF& image);   // RGB, little-endian
void writeEXR(const std::filesystem::path& path, const ImageRGBAF& image);   // RGBA, 32-bit float
ImageRGBA8 readPNG(const std::filesystem::path& path);
// Readers for the HDR outputs, so tools and tests can check what was written. Throw ImageIOError.
ImageRGBAF readPFM(const std::filesystem::path& path);   // alpha reads as 1
// OpenEXR, single-part scanline or tiled: R, G, B and optional A channels (alpha 1 without one), or
// one channel read as grey; half, float and uint samples. Refused before decoding: a side above
// 32768 or more than 32 Mi pixels (8192x4096) in all.
ImageRGBAF readEXR(const std::filesystem::path& path);
// Radiance RGBE (.hdr) through stb_image, alpha 1, row 0 on top. Throws ImageIOError naming the
// path for a missing file, a file that is not Radiance HDR (stb would convert an LDR file; that is
// refused), a side above 32768 or more than 32 Mi pixels in all (checked before decoding), or a
// NaN, infinite or negative sample
// (refused, naming the pixel: radiance must be finite and >= 0; RGBE cannot encode them, so such a
// file is corrupt).
ImageRGBAF readRadianceHDR(const std::filesystem::path& path);

// The readers above for a file's bytes already in memory; `name` stands for the path in messages
// ("cannot read EXR '<name>': ..."). Same checks, same errors.
ImageRGBA8 decodePNG(std::string_view bytes, const std::string& name);
ImageRGBAF decodePFM(std::string_view bytes, const std::string& name);
ImageRGBAF decodeEXR(std::string_view bytes, const std::string& name);
ImageRGBAF decodeRadianceHDR(std::string_view bytes, const std::string& name);

// `path`'s extension in lower case (".GLB" -> ".glb"): Janus tells scene, image and sky files by
// their extension, in any case.
std::string lowerCaseExtension(const std::filesystem::path& path);

// Writes `bytes` to `path` atomically (temporary file + rename). Throws ImageIOError.
void writeFileAtomically(const std::filesystem::path& path, const std::string& bytes);
// Unlinks the temporary files of writes in progress (their targets stay as they were). Async-
// signal-safe, for a SIGINT / SIGTERM handler, after which the process must not go on writing:
// a program that is interrupted leaves no ".<name>.tmp-XXXXXX" behind (janus's main does this).
void removeTemporaryFilesNow() noexcept;

struct ImageDifference {
    uint32_t maxChannelDifference = 0;   // in 1/255 steps
    double psnr = 0.0;                   // dB; +infinity when identical
    uint64_t differingPixels = 0;        // pixels with any channel difference > threshold
    uint64_t totalPixels = 0;
};

// Compares two images of equal size (throws std::invalid_argument otherwise). A pixel counts
// as differing when any channel differs by more than `threshold` steps.
ImageDifference compareImages(const ImageRGBA8& a, const ImageRGBA8& b, uint32_t threshold = 0);

// Heat map of |a - b| (max over channels): black where equal, then blue -> green -> yellow -> red
// up to `fullScaleSteps` (differences at or above it are red).
ImageRGBA8 differenceHeatmap(const ImageRGBA8& a, const ImageRGBA8& b, uint32_t fullScaleSteps = 8);

}  // namespace janus::renderer
