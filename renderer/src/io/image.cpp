// Image files (PNG, PFM, EXR), atomic writes, and image comparison for parity checks.
#include "janus/renderer/image.h"

#include <algorithm>
#include <array>
#include <atomic>
#include <bit>
#include <cctype>
#include <cerrno>
#include <cmath>
#include <cstdlib>
#include <cstring>
#include <fstream>
#include <iterator>
#include <limits>
#include <memory>
#include <sstream>

#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>

#include <fmt/format.h>
#include <stb/stb_image.h>
#include <stb/stb_image_write.h>
#include <tinyexr.h>

// The stb implementations come from Debian's libstb (linked by renderer/CMakeLists.txt), and
// tinyexr's from libtinyexr, so neither *_IMPLEMENTATION macro is defined here.

namespace janus::renderer {
namespace {

// Largest side we accept for any image file: far beyond any render target, small enough that
// width * height * 4 channels * sizeof(float) cannot overflow and that stb's int sizes hold.
constexpr uint32_t kMaxImageSide = 1u << 15;
// Largest float image a reader decodes: 32 Mi pixels (8192x4096, a 512 MiB RGBA32F sky). Checked
// from the header: a few bytes claiming 32768x32768 must not make the decoder allocate 16 GiB.
constexpr uint64_t kMaxFloatImagePixels = uint64_t(1) << 25;

std::string describeErrno(int error) { return std::strerror(error); }

template <typename Image>
void checkImageShape(const std::filesystem::path& path, const Image& image, const char* what) {
    if (image.width == 0 || image.height == 0)
        throw ImageIOError(fmt::format("cannot write {} '{}': the image is empty ({}x{}); render something first",
                                       what, path.string(), image.width, image.height));
    if (image.width > kMaxImageSide || image.height > kMaxImageSide)
        throw ImageIOError(fmt::format("cannot write {} '{}': {}x{} exceeds the largest supported side of {}",
                                       what, path.string(), image.width, image.height, kMaxImageSide));
    const size_t expected = size_t(image.width) * image.height * 4;
    if (image.pixels.size() != expected)
        throw ImageIOError(fmt::format("cannot write {} '{}': the pixel buffer holds {} values but {}x{} RGBA needs {}",
                                       what, path.string(), image.pixels.size(), image.width, image.height, expected));
}

// The temporary files being written, for removeTemporaryFilesNow(), which a signal handler calls:
// fixed slots of fixed size, read there without a lock or an allocation. A slot is claimed (1),
// filled, and then published (2); the handler unlinks published ones only.
struct TemporaryFileSlot {
    std::atomic<int> state{0};   // 0 free, 1 being filled, 2 holds a path
    char path[4096];
};
std::array<TemporaryFileSlot, 32> g_temporaryFiles;

// The slot now holding `path`, or -1 when none is free or the path does not fit (the file is then
// only removed by its owner, as before).
int publishTemporaryFile(const std::string& path) {
    if (path.size() >= sizeof(TemporaryFileSlot::path)) return -1;
    for (size_t i = 0; i < g_temporaryFiles.size(); ++i) {
        int expected = 0;
        if (!g_temporaryFiles[i].state.compare_exchange_strong(expected, 1, std::memory_order_acquire)) continue;
        std::memcpy(g_temporaryFiles[i].path, path.c_str(), path.size() + 1);
        g_temporaryFiles[i].state.store(2, std::memory_order_release);
        return int(i);
    }
    return -1;
}

void withdrawTemporaryFile(int slot) {
    if (slot >= 0) g_temporaryFiles[size_t(slot)].state.store(0, std::memory_order_release);
}

// Closes the descriptor and unlinks the temporary file unless release() was called, so every
// early exit (exception included) leaves nothing behind; removeTemporaryFilesNow() covers the exits
// that run no destructor (a signal).
class TemporaryFile {
public:
    explicit TemporaryFile(const std::filesystem::path& target) {
        const std::filesystem::path directory = target.has_parent_path() ? target.parent_path() : ".";
        // A dot-prefixed name beside the target: same filesystem (so rename is atomic) and
        // hidden from casual listings while it exists.
        std::string pattern = (directory / ("." + target.filename().string() + ".tmp-XXXXXX")).string();
        m_fd = ::mkstemp(pattern.data());
        if (m_fd < 0) {
            const int error = errno;
            throw ImageIOError(fmt::format("cannot write '{}': cannot create a file in '{}' ({}); "
                                           "check that the directory exists and is writable",
                                           target.string(), directory.string(), describeErrno(error)));
        }
        m_path = pattern;
        m_slot = publishTemporaryFile(m_path);
        // mkstemp creates the file 0600; outputs are ordinary files others may read.
        ::fchmod(m_fd, 0644);
    }
    ~TemporaryFile() {
        if (m_fd >= 0) ::close(m_fd);
        if (!m_path.empty()) ::unlink(m_path.c_str());
        withdrawTemporaryFile(m_slot);
    }
    TemporaryFile(const TemporaryFile&) = delete;
    TemporaryFile& operator=(const TemporaryFile&) = delete;

    int fd() const { return m_fd; }
    const std::string& path() const { return m_path; }

    // Closes the descriptor, reporting errors (a deferred write error can surface here).
    int close() {
        const int result = ::close(m_fd);
        m_fd = -1;
        return result;
    }
    // After the rename: the path is the target's now.
    void release() {
        withdrawTemporaryFile(m_slot);
        m_slot = -1;
        m_path.clear();
    }

private:
    int m_fd = -1;
    std::string m_path;
    int m_slot = -1;   // in g_temporaryFiles
};

void writeAll(const std::filesystem::path& target, TemporaryFile& file, const std::string& bytes) {
    const char* data = bytes.data();
    size_t left = bytes.size();
    while (left > 0) {
        const ssize_t written = ::write(file.fd(), data, left);
        if (written < 0) {
            if (errno == EINTR) continue;
            const int error = errno;
            throw ImageIOError(fmt::format("cannot write '{}': {} after {} of {} bytes; {}", target.string(), describeErrno(error),
                                           bytes.size() - left, bytes.size(),
                                           error == EFBIG ? "the file size limit (ulimit -f) is below what the file needs"
                                                          : "free some space or choose another location"));
        }
        data += written;
        left -= size_t(written);
    }
}

std::string readWholeFile(const std::filesystem::path& path, const char* what) {
    std::error_code ec;
    if (!std::filesystem::exists(path, ec))
        throw ImageIOError(fmt::format("cannot read {} '{}': no such file", what, path.string()));
    if (std::filesystem::is_directory(path, ec))
        throw ImageIOError(fmt::format("cannot read {} '{}': it is a directory", what, path.string()));
    if (!std::filesystem::is_regular_file(path, ec))
        throw ImageIOError(fmt::format("cannot read {} '{}': it is not a regular file (a FIFO or device)", what, path.string()));
    std::ifstream in(path, std::ios::binary);
    if (!in) throw ImageIOError(fmt::format("cannot read {} '{}': {}", what, path.string(), describeErrno(errno)));
    std::string bytes((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
    if (in.bad()) throw ImageIOError(fmt::format("cannot read {} '{}': read error", what, path.string()));
    return bytes;
}

void appendLittleEndian(std::string& out, float value) {
    const uint32_t bits = std::bit_cast<uint32_t>(value);
    for (int shift = 0; shift < 32; shift += 8) out.push_back(char((bits >> shift) & 0xFF));
}

float readLittleEndianFloat(const unsigned char* bytes) {
    const uint32_t bits = uint32_t(bytes[0]) | uint32_t(bytes[1]) << 8 | uint32_t(bytes[2]) << 16 | uint32_t(bytes[3]) << 24;
    return std::bit_cast<float>(bits);
}

float readBigEndianFloat(const unsigned char* bytes) {
    const uint32_t bits = uint32_t(bytes[3]) | uint32_t(bytes[2]) << 8 | uint32_t(bytes[1]) << 16 | uint32_t(bytes[0]) << 24;
    return std::bit_cast<float>(bits);
}

void appendToString(void* context, void* data, int size) {
    static_cast<std::string*>(context)->append(static_cast<const char*>(data), size_t(size));
}

void checkSameSize(const ImageRGBA8& a, const ImageRGBA8& b, const char* what) {
    if (a.width != b.width || a.height != b.height)
        throw std::invalid_argument(fmt::format("{}: images differ in size ({}x{} vs {}x{}); render both at the same --size",
                                                what, a.width, a.height, b.width, b.height));
    const size_t expected = size_t(a.width) * a.height * 4;
    if (a.pixels.size() != expected || b.pixels.size() != expected)
        throw std::invalid_argument(fmt::format("{}: pixel buffers hold {} and {} values but {}x{} RGBA needs {}",
                                                what, a.pixels.size(), b.pixels.size(), a.width, a.height, expected));
}

uint32_t maxChannelDifferenceAt(const ImageRGBA8& a, const ImageRGBA8& b, size_t pixel) {
    uint32_t largest = 0;
    for (size_t c = 0; c < 4; ++c) {
        const int diff = std::abs(int(a.pixels[pixel * 4 + c]) - int(b.pixels[pixel * 4 + c]));
        largest = std::max(largest, uint32_t(diff));
    }
    return largest;
}

}  // namespace

void writeFileAtomically(const std::filesystem::path& path, const std::string& bytes) {
    if (path.empty() || !path.has_filename())
        throw ImageIOError(fmt::format("cannot write '{}': the path names no file", path.string()));
    std::error_code ec;
    if (std::filesystem::is_directory(path, ec))
        throw ImageIOError(fmt::format("cannot write '{}': it is a directory; give a file name", path.string()));

    TemporaryFile file(path);
    writeAll(path, file, bytes);
    // fsync before rename: otherwise a crash could leave the new name pointing at empty data.
    if (::fsync(file.fd()) != 0) {
        const int error = errno;
        throw ImageIOError(fmt::format("cannot write '{}': flushing to disk failed ({})", path.string(), describeErrno(error)));
    }
    if (file.close() != 0) {
        const int error = errno;
        throw ImageIOError(fmt::format("cannot write '{}': closing failed ({})", path.string(), describeErrno(error)));
    }
    if (::rename(file.path().c_str(), path.c_str()) != 0) {
        const int error = errno;
        throw ImageIOError(fmt::format("cannot write '{}': cannot move the finished file into place ({}); "
                                       "check that the path is not a directory and is writable",
                                       path.string(), describeErrno(error)));
    }
    file.release();
}

std::string lowerCaseExtension(const std::filesystem::path& path) {
    std::string extension = path.extension().string();
    for (char& c : extension) c = char(std::tolower(static_cast<unsigned char>(c)));
    return extension;
}

void removeTemporaryFilesNow() noexcept {
    for (TemporaryFileSlot& slot : g_temporaryFiles)
        if (slot.state.load(std::memory_order_acquire) == 2) ::unlink(slot.path);
}

void writePNG(const std::filesystem::path& path, const ImageRGBA8& image) {
    checkImageShape(path, image, "PNG");
    std::string encoded;
    const int ok = stbi_write_png_to_func(appendToString, &encoded, int(image.width), int(image.height), 4,
                                          image.pixels.data(), int(image.width * 4));
    if (!ok || encoded.empty())
        throw ImageIOError(fmt::format("cannot write PNG '{}': the PNG encoder failed (out of memory?)", path.string()));
    writeFileAtomically(path, encoded);
}

ImageRGBA8 readPNG(const std::filesystem::path& path) { return decodePNG(readWholeFile(path, "PNG"), path.string()); }

ImageRGBA8 decodePNG(std::string_view bytes, const std::string& name) {
    if (bytes.size() > size_t(std::numeric_limits<int>::max()))
        throw ImageIOError(fmt::format("cannot read PNG '{}': the file is too large", name));
    int width = 0, height = 0, channelsInFile = 0;
    std::unique_ptr<stbi_uc, void (*)(void*)> decoded(
        stbi_load_from_memory(reinterpret_cast<const stbi_uc*>(bytes.data()), int(bytes.size()), &width, &height,
                              &channelsInFile, 4),
        stbi_image_free);
    if (!decoded)
        throw ImageIOError(fmt::format("cannot read PNG '{}': {}", name, stbi_failure_reason()));
    ImageRGBA8 image;
    image.width = uint32_t(width);
    image.height = uint32_t(height);
    image.pixels.assign(decoded.get(), decoded.get() + size_t(width) * size_t(height) * 4);
    return image;
}

void writePFM(const std::filesystem::path& path, const ImageRGBAF& image) {
    checkImageShape(path, image, "PFM");
    // "PF" = 3 channels; a negative scale declares little-endian samples.
    std::string out = fmt::format("PF\n{} {}\n-1.0\n", image.width, image.height);
    out.reserve(out.size() + size_t(image.width) * image.height * 3 * sizeof(float));
    // PFM stores the bottom row first, so walk our rows (row 0 on top) in reverse.
    for (uint32_t row = image.height; row-- > 0;) {
        const float* source = image.pixels.data() + size_t(row) * image.width * 4;
        for (uint32_t x = 0; x < image.width; ++x)
            for (int c = 0; c < 3; ++c) appendLittleEndian(out, source[x * 4 + c]);
    }
    writeFileAtomically(path, out);
}

ImageRGBAF readPFM(const std::filesystem::path& path) { return decodePFM(readWholeFile(path, "PFM"), path.string()); }

ImageRGBAF decodePFM(std::string_view bytes, const std::string& name) {
    std::istringstream header{std::string(bytes)};
    std::string magic;
    long long width = 0, height = 0;
    double scale = 0.0;
    header >> magic >> width >> height >> scale;
    if (!header || (magic != "PF" && magic != "Pf"))
        throw ImageIOError(fmt::format("cannot read PFM '{}': not a PFM file (bad header)", name));
    if (width <= 0 || height <= 0 || width > kMaxImageSide || height > kMaxImageSide || scale == 0.0)
        throw ImageIOError(fmt::format("cannot read PFM '{}': bad size {}x{} or scale {}", name, width, height, scale));
    header.get();   // exactly one whitespace character separates the header from the samples
    const size_t offset = size_t(header.tellg());
    const int channels = magic == "PF" ? 3 : 1;
    const size_t needed = size_t(width) * size_t(height) * size_t(channels) * sizeof(float);
    if (bytes.size() < offset + needed)
        throw ImageIOError(fmt::format("cannot read PFM '{}': truncated ({} bytes of samples, {} needed)",
                                       name, bytes.size() - offset, needed));

    ImageRGBAF image;
    image.width = uint32_t(width);
    image.height = uint32_t(height);
    image.pixels.assign(size_t(width) * size_t(height) * 4, 1.0f);
    const auto* samples = reinterpret_cast<const unsigned char*>(bytes.data() + offset);
    const bool littleEndian = scale < 0.0;
    for (uint32_t fileRow = 0; fileRow < image.height; ++fileRow) {
        const uint32_t row = image.height - 1 - fileRow;
        for (uint32_t x = 0; x < image.width; ++x) {
            for (int c = 0; c < 3; ++c) {
                const int sourceChannel = channels == 3 ? c : 0;
                const unsigned char* at = samples + ((size_t(fileRow) * image.width + x) * channels + sourceChannel) * 4;
                image.pixels[(size_t(row) * image.width + x) * 4 + c] =
                    littleEndian ? readLittleEndianFloat(at) : readBigEndianFloat(at);
            }
        }
    }
    return image;
}

void writeEXR(const std::filesystem::path& path, const ImageRGBAF& image) {
    checkImageShape(path, image, "EXR");
    const size_t pixelCount = size_t(image.width) * image.height;
    // EXR readers expect channels sorted by name; A, B, G, R is that order.
    constexpr std::array<const char*, 4> kChannelNames = {"A", "B", "G", "R"};
    constexpr std::array<int, 4> kSourceChannel = {3, 2, 1, 0};
    std::array<std::vector<float>, 4> planes;
    for (size_t i = 0; i < 4; ++i) {
        planes[i].resize(pixelCount);
        for (size_t p = 0; p < pixelCount; ++p) planes[i][p] = image.pixels[p * 4 + size_t(kSourceChannel[i])];
    }
    std::array<unsigned char*, 4> planePointers{};
    for (size_t i = 0; i < 4; ++i) planePointers[i] = reinterpret_cast<unsigned char*>(planes[i].data());

    EXRImage exrImage;
    InitEXRImage(&exrImage);
    exrImage.num_channels = 4;
    exrImage.images = planePointers.data();
    exrImage.width = int(image.width);
    exrImage.height = int(image.height);

    EXRHeader header;
    InitEXRHeader(&header);
    std::array<EXRChannelInfo, 4> channels{};
    std::array<int, 4> pixelTypes{};
    for (size_t i = 0; i < 4; ++i) {
        std::strncpy(channels[i].name, kChannelNames[i], sizeof(channels[i].name) - 1);
        pixelTypes[i] = TINYEXR_PIXELTYPE_FLOAT;
    }
    header.num_channels = 4;
    header.channels = channels.data();
    header.pixel_types = pixelTypes.data();
    header.requested_pixel_types = pixelTypes.data();
    header.compression_type = TINYEXR_COMPRESSIONTYPE_ZIP;

    unsigned char* memory = nullptr;
    const char* error = nullptr;
    const size_t size = SaveEXRImageToMemory(&exrImage, &header, &memory, &error);
    std::unique_ptr<unsigned char, void (*)(void*)> owned(memory, std::free);
    if (size == 0 || !memory) {
        const std::string reason = error ? error : "unknown encoder error";
        if (error) FreeEXRErrorMessage(error);
        throw ImageIOError(fmt::format("cannot write EXR '{}': {}", path.string(), reason));
    }
    writeFileAtomically(path, std::string(reinterpret_cast<const char*>(memory), size));
}

ImageRGBAF readEXR(const std::filesystem::path& path) { return decodeEXR(readWholeFile(path, "EXR"), path.string()); }

ImageRGBAF decodeEXR(std::string_view bytes, const std::string& name) {
    // Not tinyexr's LoadEXRFromMemory: it leaks its header and image on most error paths (found
    // by fuzz/fuzz_image.cpp) and allocates whatever size a header claims. Its lower-level calls
    // let every exit free what was allocated, and the size be refused before anything is decoded.
    auto fail = [&](const std::string& why) { return ImageIOError(fmt::format("cannot read EXR '{}': {}", name, why)); };
    auto tinyexrError = [&](const char* error, int code) {
        const std::string reason = error ? error : fmt::format("tinyexr error {}", code);
        if (error) FreeEXRErrorMessage(error);
        return fail(reason);
    };
    // tinyexr's PIZ decoder (Debian's 1.0.1) reads a chunk's bitmap range and Huffman length
    // before checking them against the chunk: a corrupt chunk near the end of the file made it
    // read up to 8 KiB past the end (found by fuzz_image, AddressSanitizer). Zero bytes after the
    // end keep every such read inside memory we own; the checks that follow then refuse the chunk.
    constexpr size_t kPizOverreadPadding = 8192 + 4 + 4 + 64;   // bitmap, its range, the length, slack
    std::vector<unsigned char> padded(bytes.size() + kPizOverreadPadding, 0);
    std::memcpy(padded.data(), bytes.data(), bytes.size());
    const unsigned char* data = padded.data();
    EXRVersion version;
    if (ParseEXRVersionFromMemory(&version, data, bytes.size()) != TINYEXR_SUCCESS) throw fail("not an OpenEXR file");
    if (version.multipart || version.non_image)
        throw fail("multi-part and deep EXR files are not supported; save a single-part scanline or tiled image");
    EXRHeader header;
    InitEXRHeader(&header);
    std::unique_ptr<EXRHeader, int (*)(EXRHeader*)> headerOwner(&header, FreeEXRHeader);
    const char* error = nullptr;
    if (const int code = ParseEXRHeaderFromMemory(&header, &version, data, bytes.size(), &error); code != TINYEXR_SUCCESS)
        throw tinyexrError(error, code);
    const int64_t width = int64_t(header.data_window.max_x) - header.data_window.min_x + 1;
    const int64_t height = int64_t(header.data_window.max_y) - header.data_window.min_y + 1;
    if (width < 1 || height < 1 || width > kMaxImageSide || height > kMaxImageSide || width * height > int64_t(kMaxFloatImagePixels))
        throw fail(fmt::format("size {}x{} is outside 1..{} per side and {} Mi pixels in all", width, height, kMaxImageSide,
                               kMaxFloatImagePixels >> 20));
    constexpr std::array<const char*, 4> kNames = {"R", "G", "B", "A"};
    std::array<int, 4> source = {-1, -1, -1, -1};
    for (int c = 0; c < header.num_channels; ++c) {
        if (header.pixel_types[c] == TINYEXR_PIXELTYPE_HALF) header.requested_pixel_types[c] = TINYEXR_PIXELTYPE_FLOAT;
        for (size_t k = 0; k < 4; ++k)
            if (std::strcmp(header.channels[c].name, kNames[k]) == 0) source[k] = c;
    }
    if (header.num_channels == 1) {
        source = {0, 0, 0, -1};   // grey: the one channel in R, G and B; alpha 1
    } else if (source[0] < 0 || source[1] < 0 || source[2] < 0) {
        throw fail(fmt::format("it has no R, G and B channels ({} channels); Janus reads RGB(A) and single-channel images",
                               header.num_channels));
    }

    EXRImage exr;
    InitEXRImage(&exr);
    // When a chunk fails to decode, tinyexr frees the image itself (FreeEXRImage) but with
    // num_channels still 0, so the channels it allocated leaked (found by fuzzing). Set here, it
    // frees them too. Its pointers then dangle: the image is ours to free only after success.
    exr.num_channels = header.num_channels;
    if (const int code = LoadEXRImageFromMemory(&exr, &header, data, bytes.size(), &error); code != TINYEXR_SUCCESS)
        throw tinyexrError(error, code);
    std::unique_ptr<EXRImage, int (*)(EXRImage*)> imageOwner(&exr, FreeEXRImage);
    if (int64_t(exr.width) != width || int64_t(exr.height) != height)
        throw fail(fmt::format("the decoder returned {}x{} pixels for a {}x{} data window", exr.width, exr.height, width, height));

    ImageRGBAF image;
    image.width = uint32_t(width);
    image.height = uint32_t(height);
    image.pixels.assign(size_t(width) * size_t(height) * 4, 1.0f);
    // One sample of channel `c` of a decoded block; UINT channels are converted, not reinterpreted.
    auto sample = [&](unsigned char* const* planes, int c, size_t at) {
        if (header.requested_pixel_types[c] == TINYEXR_PIXELTYPE_UINT) return float(reinterpret_cast<const uint32_t*>(planes[c])[at]);
        return reinterpret_cast<const float*>(planes[c])[at];
    };
    // Copies a block of `blockWidth` x `blockHeight` samples (rows `stride` apart) to (x0, y0),
    // clipped to the image: tiles on the right and bottom edges overhang it.
    auto copyBlock = [&](unsigned char* const* planes, int64_t x0, int64_t y0, int64_t blockWidth, int64_t blockHeight, size_t stride) {
        if (!planes) throw fail("the decoder returned a tile without data");
        for (int64_t y = 0; y < blockHeight && y0 + y < height; ++y)
            for (int64_t x = 0; x < blockWidth && x0 + x < width; ++x) {
                if (x0 + x < 0 || y0 + y < 0) continue;
                float* out = &image.pixels[(size_t(y0 + y) * size_t(width) + size_t(x0 + x)) * 4];
                for (size_t k = 0; k < 4; ++k)
                    if (source[k] >= 0) out[k] = sample(planes, source[k], size_t(y) * stride + size_t(x));
            }
    };
    if (header.tiled) {
        if (!exr.tiles) throw fail("the decoder returned no tiles for a tiled image");
        for (int t = 0; t < exr.num_tiles; ++t) {
            const EXRTile& tile = exr.tiles[t];
            copyBlock(tile.images, int64_t(tile.offset_x) * header.tile_size_x, int64_t(tile.offset_y) * header.tile_size_y,
                      std::min(tile.width, header.tile_size_x), std::min(tile.height, header.tile_size_y), size_t(header.tile_size_x));
        }
    } else {
        copyBlock(exr.images, 0, 0, width, height, size_t(width));
    }
    return image;
}

ImageRGBAF readRadianceHDR(const std::filesystem::path& path) {
    return decodeRadianceHDR(readWholeFile(path, "Radiance HDR"), path.string());
}

namespace {

// Why stb_image would hang on or misread this Radiance HDR, or "" when it would not. stb reads
// bytes past the end of the data as 0 (a flat file cut short decodes missing pixels from
// uninitialised bytes), and its RLE scanline reader (Debian's 2022 stb) takes a count of 0 as
// "copy nothing" without advancing: past the end it reads 0 for ever, so a file cut short inside
// an RLE scanline hung it (found by fuzz_image). This walks the data exactly as stb does, header
// tokens included, before stb sees it, and refuses a file that ends inside its pixel data.
std::string radianceDataProblem(std::string_view bytes, int width, int height) {
    size_t at = 0;
    bool readPastEnd = false;
    auto atEnd = [&] { return at >= bytes.size(); };
    auto next = [&]() -> int {
        if (atEnd()) {
            readPastEnd = true;
            return 0;
        }
        return int(static_cast<unsigned char>(bytes[at++]));
    };
    constexpr size_t kTokenMax = 1023;   // STBI__HDR_BUFLEN - 1
    auto token = [&] {
        std::string text;
        char c = char(next());
        while (!atEnd() && c != '\n') {
            text += c;
            if (text.size() == kTokenMax) {
                while (!atEnd() && next() != '\n') {}
                break;
            }
            c = char(next());
        }
        return text;
    };
    const std::string endsEarly = "the file ends inside its pixel data";
    // Flat pixels, 4 bytes each, from `firstPixel` on.
    auto flatFrom = [&](uint64_t firstPixel) {
        const uint64_t needed = (uint64_t(width) * uint64_t(height) - firstPixel) * 4;
        return bytes.size() - std::min(at, bytes.size()) < needed ? endsEarly : std::string();
    };
    token();                                   // #?RADIANCE (checked by stb)
    while (!token().empty()) {}                // header lines up to the empty one
    token();                                   // -Y height +X width (as stbi_info read them)
    if (width < 8 || width >= 32768) return flatFrom(0);
    for (int row = 0; row < height; ++row) {
        const int c1 = next(), c2 = next(), high = next();
        const int low = next();
        if (readPastEnd) return endsEarly;
        // Not RLE: stb takes these 4 bytes as pixel 0 and reads the rest of the image flat.
        if (c1 != 2 || c2 != 2 || (high & 0x80)) return flatFrom(1);
        if (((high << 8) | low) != width) return "";   // stb refuses the scanline length
        for (int component = 0; component < 4; ++component) {
            for (int x = 0; x < width;) {
                int count = next();
                if (count > 128) {
                    count -= 128;
                    next();
                } else {
                    at += size_t(count);   // 0 copies nothing (as Radiance's reader does)
                    if (at > bytes.size()) return endsEarly;
                }
                if (readPastEnd) return endsEarly;   // past the end stb reads 0s, and loops on them for ever
                if (count > width - x) return "";   // stb refuses the run
                x += count;
            }
        }
    }
    return "";
}

}  // namespace

ImageRGBAF decodeRadianceHDR(std::string_view bytes, const std::string& name) {
    if (bytes.size() > size_t(std::numeric_limits<int>::max()))
        throw ImageIOError(fmt::format("cannot read Radiance HDR '{}': the file is too large", name));
    const auto* data = reinterpret_cast<const stbi_uc*>(bytes.data());
    const int length = int(bytes.size());
    if (!stbi_is_hdr_from_memory(data, length))
        throw ImageIOError(fmt::format("cannot read Radiance HDR '{}': not a Radiance HDR (.hdr, RGBE) file", name));
    int width = 0, height = 0, channelsInFile = 0;
    if (!stbi_info_from_memory(data, length, &width, &height, &channelsInFile))
        throw ImageIOError(fmt::format("cannot read Radiance HDR '{}': {}", name, stbi_failure_reason()));
    if (width <= 0 || height <= 0 || uint32_t(width) > kMaxImageSide || uint32_t(height) > kMaxImageSide ||
        uint64_t(width) * uint64_t(height) > kMaxFloatImagePixels)
        throw ImageIOError(fmt::format("cannot read Radiance HDR '{}': size {}x{} is outside 1..{} per side and {} Mi pixels in all",
                                       name, width, height, kMaxImageSide, kMaxFloatImagePixels >> 20));
    if (const std::string problem = radianceDataProblem(bytes, width, height); !problem.empty())
        throw ImageIOError(fmt::format("cannot read Radiance HDR '{}': {}; the file is corrupt", name, problem));
    std::unique_ptr<float, void (*)(void*)> decoded(stbi_loadf_from_memory(data, length, &width, &height, &channelsInFile, 4),
                                                    stbi_image_free);
    if (!decoded) throw ImageIOError(fmt::format("cannot read Radiance HDR '{}': {}", name, stbi_failure_reason()));
    ImageRGBAF image;
    image.width = uint32_t(width);
    image.height = uint32_t(height);
    image.pixels.assign(decoded.get(), decoded.get() + size_t(width) * size_t(height) * 4);
    for (size_t i = 0; i < image.pixels.size(); ++i) {
        const float value = image.pixels[i];
        if (!std::isfinite(value) || value < 0.0f) {
            const size_t pixel = i / 4;
            throw ImageIOError(fmt::format("cannot read Radiance HDR '{}': pixel ({}, {}) channel {} is {}; radiance must be finite "
                                           "and non-negative (the file is corrupt)",
                                           name, pixel % image.width, pixel / image.width, i % 4, value));
        }
    }
    return image;
}

ImageDifference compareImages(const ImageRGBA8& a, const ImageRGBA8& b, uint32_t threshold) {
    checkSameSize(a, b, "compareImages");
    ImageDifference result;
    result.totalPixels = uint64_t(a.width) * a.height;
    uint64_t sumOfSquares = 0;
    for (size_t pixel = 0; pixel < result.totalPixels; ++pixel) {
        uint32_t largest = 0;
        for (size_t c = 0; c < 4; ++c) {
            const int diff = std::abs(int(a.pixels[pixel * 4 + c]) - int(b.pixels[pixel * 4 + c]));
            sumOfSquares += uint64_t(diff * diff);
            largest = std::max(largest, uint32_t(diff));
        }
        result.maxChannelDifference = std::max(result.maxChannelDifference, largest);
        if (largest > threshold) ++result.differingPixels;
    }
    if (sumOfSquares == 0) {
        result.psnr = std::numeric_limits<double>::infinity();
    } else {
        const double meanSquaredError = double(sumOfSquares) / double(result.totalPixels * 4);
        result.psnr = 10.0 * std::log10(255.0 * 255.0 / meanSquaredError);
    }
    return result;
}

ImageRGBA8 differenceHeatmap(const ImageRGBA8& a, const ImageRGBA8& b, uint32_t fullScaleSteps) {
    checkSameSize(a, b, "differenceHeatmap");
    // A zero scale would divide by zero; treat it as "any difference is full scale".
    const double fullScale = double(std::max(fullScaleSteps, 1u));
    // Ramp stops at t = 0, 1/3, 2/3, 1.
    constexpr std::array<std::array<double, 3>, 4> kRamp = {{{0, 0, 255}, {0, 255, 0}, {255, 255, 0}, {255, 0, 0}}};

    ImageRGBA8 heatmap;
    heatmap.width = a.width;
    heatmap.height = a.height;
    heatmap.pixels.assign(a.pixels.size(), 0);
    const size_t pixelCount = size_t(a.width) * a.height;
    for (size_t pixel = 0; pixel < pixelCount; ++pixel) {
        uint8_t* out = &heatmap.pixels[pixel * 4];
        out[3] = 255;
        const uint32_t diff = maxChannelDifferenceAt(a, b, pixel);
        if (diff == 0) continue;   // black
        const double t = std::min(double(diff) / fullScale, 1.0);
        const double position = t * 3.0;
        const size_t segment = std::min(size_t(position), size_t(2));
        const double blend = position - double(segment);
        for (size_t c = 0; c < 3; ++c) {
            const double value = kRamp[segment][c] + (kRamp[segment + 1][c] - kRamp[segment][c]) * blend;
            out[c] = uint8_t(std::lround(value));
        }
    }
    return heatmap;
}

}  // namespace janus::renderer
