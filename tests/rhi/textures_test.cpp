// Textures: exact round trips of every format x dimension x mip level / face / slice, copies
// between buffers and textures (faces, mips, slices), and mip generation.
#include <glm/gtc/packing.hpp>

#include "backend_test.h"

namespace janus::rhi::test {
namespace {

class TextureTest : public BackendTest {};
JANUS_INSTANTIATE_BACKEND_TESTS(TextureTest);

const Format kColorFormats[] = {Format::RGBA8_UNORM, Format::RGBA8_SRGB,     Format::RGBA16_FLOAT,
                                Format::RGBA32_FLOAT, Format::R11G11B10_FLOAT, Format::R32_UINT,
                                Format::RGBA32_UINT, Format::R32_FLOAT};

// Contents for one subresource: every texel different, values exactly representable in
// `format` (so a round trip must be bit exact), and different for every `seed`.
std::vector<std::byte> texelData(Format format, size_t texels, uint32_t seed) {
    const FormatInfo& info = formatInfo(format);
    std::vector<std::byte> bytes(texels * info.bytesPerPixel);
    auto put = [&](size_t index, auto value) { std::memcpy(bytes.data() + index * sizeof(value), &value, sizeof(value)); };
    size_t scalars = texels * (format == Format::R11G11B10_FLOAT ? 1 : info.channels);
    for (size_t i = 0; i < scalars; ++i) {
        uint32_t k = uint32_t(i) + 37 * seed + 1;
        switch (format) {
            case Format::RGBA8_UNORM:
            case Format::RGBA8_SRGB: put(i, uint8_t(k * 13 + (k >> 8))); break;
            case Format::RGBA16_FLOAT: put(i, toHalf(float(k % 211) * 0.25f - 20.0f)); break;
            case Format::RGBA32_FLOAT:
            case Format::R32_FLOAT: put(i, float(k) * 1.375f - 300.0f); break;
            case Format::R32_UINT:
            case Format::RGBA32_UINT: put(i, k * 2654435761u); break;
            case Format::R11G11B10_FLOAT:
                // Small multiples of powers of two: exact in 11- and 10-bit floats (no sign bit).
                put(i, glm::packF2x11_1x10(glm::vec3(float(k % 29) * 0.5f, float(k % 23) * 0.25f, float(k % 19) * 2.0f)));
                break;
            case Format::D32_FLOAT: put(i, float(k % 1024) / 1024.0f); break;
            case Format::Unknown: break;
        }
    }
    return bytes;
}

struct Subresource {
    TextureSubresource sub;
    uint32_t width, height;
};

std::vector<Subresource> allSubresources(const TextureDesc& desc) {
    std::vector<Subresource> subs;
    for (uint32_t mip = 0; mip < desc.mipLevels; ++mip) {
        uint32_t layers = desc.dimension == TextureDimension::TextureCube ? 6
                          : desc.dimension == TextureDimension::Texture3D ? mipExtent(desc.depth, mip)
                                                                          : 1;
        for (uint32_t layer = 0; layer < layers; ++layer)
            subs.push_back({{mip, layer}, mipExtent(desc.width, mip), mipExtent(desc.height, mip)});
    }
    return subs;
}

std::string describe(const TextureDesc& desc, const Subresource& s) {
    return fmt::format("{} {} {}x{}x{} mip {} layer {}", toString(desc.format), toString(desc.dimension), desc.width,
                       desc.height, desc.depth, s.sub.mipLevel, s.sub.layer);
}

// Writes every subresource with distinct data, then reads them all back: each must be exact
// and no write may have landed in another subresource.
void expectRoundTrip(IDevice& device, const TextureDesc& requested) {
    TextureHandle texture = device.createTexture(requested);
    const TextureDesc& desc = texture->desc();
    ASSERT_EQ(desc.mipLevels, requested.mipLevels ? requested.mipLevels : fullMipCount(desc.width, desc.height,
              desc.dimension == TextureDimension::Texture3D ? desc.depth : 1));
    std::vector<Subresource> subs = allSubresources(desc);
    std::vector<std::vector<std::byte>> written;
    for (size_t i = 0; i < subs.size(); ++i) {
        written.push_back(texelData(desc.format, size_t(subs[i].width) * subs[i].height, uint32_t(i)));
        device.writeTexture(texture, subs[i].sub, written.back().data(), written.back().size());
    }
    for (size_t i = 0; i < subs.size(); ++i) {
        std::vector<std::byte> read = device.readTexture(texture, subs[i].sub);
        EXPECT_TRUE(read == written[i]) << describe(desc, subs[i]) << ": read back " << read.size()
                                        << " bytes that differ from the " << written[i].size() << " written";
    }
}

TEST_P(TextureTest, RoundTrips2DWithMipChain) {
    for (Format format : kColorFormats) {
        SCOPED_TRACE(toString(format));
        // 0 = full chain: 16x8, 8x4, 4x2, 2x1, 1x1.
        expectRoundTrip(device(), TextureDesc().setFormat(format).setSize(16, 8).setMipLevels(0));
    }
}

TEST_P(TextureTest, RoundTrips3DWithMipChainEverySlice) {
    for (Format format : kColorFormats) {
        SCOPED_TRACE(toString(format));
        expectRoundTrip(device(), TextureDesc().setDimension(TextureDimension::Texture3D).setFormat(format)
                                      .setSize(8, 4, 4).setMipLevels(0));
    }
}

TEST_P(TextureTest, RoundTripsCubeWithMipChainEveryFace) {
    for (Format format : kColorFormats) {
        SCOPED_TRACE(toString(format));
        expectRoundTrip(device(), TextureDesc().setDimension(TextureDimension::TextureCube).setFormat(format)
                                      .setSize(8, 8).setMipLevels(0));
    }
}

// Odd, non-power-of-two extents: mip extents round down (5x3 -> 2x1 -> 1x1) and rows are not
// multiples of 16 bytes.
TEST_P(TextureTest, RoundTripsOddSizes) {
    for (Format format : kColorFormats) {
        SCOPED_TRACE(toString(format));
        expectRoundTrip(device(), TextureDesc().setFormat(format).setSize(5, 3).setMipLevels(0));
        expectRoundTrip(device(), TextureDesc().setDimension(TextureDimension::Texture3D).setFormat(format).setSize(3, 5, 3).setMipLevels(0));
        expectRoundTrip(device(), TextureDesc().setDimension(TextureDimension::TextureCube).setFormat(format).setSize(3, 3).setMipLevels(0));
    }
}

TEST_P(TextureTest, RoundTripsDepth) {
    expectRoundTrip(device(), TextureDesc().setFormat(Format::D32_FLOAT).setSize(8, 4)
                                  .setUsage(TextureUsage::Sampled | TextureUsage::RenderTarget).setMipLevels(1));
}

TEST_P(TextureTest, DescriptionResolvesFullMipChain) {
    TextureHandle t = device().createTexture(TextureDesc().setSize(16, 4).setMipLevels(0));
    EXPECT_EQ(t->desc().mipLevels, 5u);
    TextureHandle v = device().createTexture(
        TextureDesc().setDimension(TextureDimension::Texture3D).setSize(4, 4, 32).setMipLevels(0));
    EXPECT_EQ(v->desc().mipLevels, 6u) << "the depth of a 3D texture counts for its chain";
}

TEST_P(TextureTest, CopiesBufferToTextureSubresources) {
    TextureHandle flat = device().createTexture(TextureDesc().setSize(8, 8).setMipLevels(2));
    TextureHandle cube = device().createTexture(
        TextureDesc().setDimension(TextureDimension::TextureCube).setSize(8, 8).setMipLevels(2));
    TextureHandle volume = device().createTexture(
        TextureDesc().setDimension(TextureDimension::Texture3D).setSize(4, 4, 4));
    std::vector<std::byte> flatMip1 = texelData(Format::RGBA8_UNORM, 16, 1);
    std::vector<std::byte> cubeFace3Mip1 = texelData(Format::RGBA8_UNORM, 16, 2);
    std::vector<std::byte> slice2 = texelData(Format::RGBA8_UNORM, 16, 3);
    // One staging buffer, each image at its own 256-byte aligned offset.
    std::vector<std::byte> staging(768);
    std::copy(flatMip1.begin(), flatMip1.end(), staging.begin());
    std::copy(cubeFace3Mip1.begin(), cubeFace3Mip1.end(), staging.begin() + 256);
    std::copy(slice2.begin(), slice2.end(), staging.begin() + 512);
    BufferHandle buffer = createBuffer(BufferUsage::None, staging);
    submit([&](ICommandList& cmd) {
        cmd.copyBufferToTexture(flat, {1, 0}, buffer, 0);
        cmd.copyBufferToTexture(cube, {1, 3}, buffer, 256);
        cmd.copyBufferToTexture(volume, {0, 2}, buffer, 512);
    });
    EXPECT_EQ(device().readTexture(flat, {1, 0}), flatMip1);
    EXPECT_EQ(device().readTexture(cube, {1, 3}), cubeFace3Mip1);
    EXPECT_EQ(device().readTexture(volume, {0, 2}), slice2);
}

TEST_P(TextureTest, CopiesTextureSubresourcesToBuffer) {
    TextureHandle cube = device().createTexture(TextureDesc().setDimension(TextureDimension::TextureCube)
                                                    .setFormat(Format::RGBA32_FLOAT).setSize(4, 4).setMipLevels(2));
    TextureHandle volume = device().createTexture(TextureDesc().setDimension(TextureDimension::Texture3D)
                                                      .setFormat(Format::R32_UINT).setSize(4, 2, 3));
    std::vector<std::byte> face5Mip1 = texelData(Format::RGBA32_FLOAT, 4, 4);
    std::vector<std::byte> slice1 = texelData(Format::R32_UINT, 8, 5);
    device().writeTexture(cube, {1, 5}, face5Mip1.data(), face5Mip1.size());
    device().writeTexture(volume, {0, 1}, slice1.data(), slice1.size());
    BufferHandle buffer = createBuffer(BufferUsage::None, 512);
    std::vector<std::byte> zeros(512);
    device().writeBuffer(buffer, zeros.data(), zeros.size());
    submit([&](ICommandList& cmd) {
        cmd.copyTextureToBuffer(buffer, 64, cube, {1, 5});
        cmd.copyTextureToBuffer(buffer, 256, volume, {0, 1});
    });
    std::vector<std::byte> expected = zeros;
    std::copy(face5Mip1.begin(), face5Mip1.end(), expected.begin() + 64);
    std::copy(slice1.begin(), slice1.end(), expected.begin() + 256);
    EXPECT_EQ(device().readBuffer(buffer), expected);
}

TEST_P(TextureTest, CopiesBetweenTexturesFacesMipsAndSlices) {
    auto make = [&](TextureDimension dim, uint32_t depth, uint32_t mips) {
        return device().createTexture(TextureDesc().setDimension(dim).setSize(8, 8, depth).setMipLevels(mips));
    };
    TextureHandle flat = make(TextureDimension::Texture2D, 1, 2);
    TextureHandle cube = make(TextureDimension::TextureCube, 1, 2);
    TextureHandle volume = make(TextureDimension::Texture3D, 4, 1);
    TextureHandle flatCopy = make(TextureDimension::Texture2D, 1, 1);
    std::vector<std::byte> mip1 = texelData(Format::RGBA8_UNORM, 16, 6);
    std::vector<std::byte> face2 = texelData(Format::RGBA8_UNORM, 64, 7);
    std::vector<std::byte> untouched = texelData(Format::RGBA8_UNORM, 64, 8);
    device().writeTexture(flat, {1, 0}, mip1.data(), mip1.size());
    device().writeTexture(cube, {0, 2}, face2.data(), face2.size());
    for (uint32_t slice = 0; slice < 4; ++slice) device().writeTexture(volume, {0, slice}, untouched.data(), untouched.size());
    submit([&](ICommandList& cmd) {
        cmd.copyTexture(cube, {1, 4}, flat, {1, 0});        // 2D mip 1 -> cube face 4 mip 1
        cmd.copyTexture(volume, {0, 1}, cube, {0, 2});      // cube face 2 -> 3D slice 1
        cmd.copyTexture(flatCopy, {0, 0}, volume, {0, 1});  // 3D slice 1 -> 2D (sees the copy above)
    });
    EXPECT_EQ(device().readTexture(cube, {1, 4}), mip1) << "2D mip 1 -> cube face 4 mip 1";
    EXPECT_EQ(device().readTexture(volume, {0, 1}), face2) << "cube face 2 -> 3D slice 1";
    EXPECT_EQ(device().readTexture(flatCopy, {0, 0}), face2) << "3D slice 1 -> 2D, after the previous copy";
    for (uint32_t slice : {0u, 2u, 3u})
        EXPECT_EQ(device().readTexture(volume, {0, slice}), untouched) << "3D slice " << slice << " must not change";
}

// Each level must be the 2x2 box average of the level above it. Compared with the level above
// as read back, so errors do not accumulate. Tolerance 1/255: the specs leave the rounding of
// the filtered unorm value to the implementation (blit vs. glGenerateMipmap).
void expectBoxFiltered(IDevice& device, const TextureHandle& texture, uint32_t layer) {
    const TextureDesc& desc = texture->desc();
    std::vector<Rgba8> above = BackendTest::bytesAs<Rgba8>(device.readTexture(texture, {0, layer}));
    for (uint32_t mip = 1; mip < desc.mipLevels; ++mip) {
        uint32_t w = mipExtent(desc.width, mip), h = mipExtent(desc.height, mip), aboveW = mipExtent(desc.width, mip - 1);
        std::vector<Rgba8> level = BackendTest::bytesAs<Rgba8>(device.readTexture(texture, {mip, layer}));
        ASSERT_EQ(level.size(), size_t(w) * h);
        int worst = 0;
        std::string worstAt;
        for (uint32_t y = 0; y < h; ++y)
            for (uint32_t x = 0; x < w; ++x)
                for (int c = 0; c < 4; ++c) {
                    auto channel = [&](const Rgba8& p) { return (&p.r)[c]; };
                    float sum = 0;
                    for (uint32_t dy = 0; dy < 2; ++dy)
                        for (uint32_t dx = 0; dx < 2; ++dx) sum += channel(above[(2 * y + dy) * aboveW + 2 * x + dx]);
                    int diff = std::abs(int(channel(level[y * w + x])) - int(std::lround(sum / 4.0f)));
                    if (diff > worst) {
                        worst = diff;
                        worstAt = fmt::format("layer {} mip {} texel ({}, {}) channel {}: got {}, box average {}",
                                              layer, mip, x, y, c, channel(level[y * w + x]), sum / 4.0f);
                    }
                }
        EXPECT_LE(worst, 1) << worstAt;
        above = std::move(level);
    }
}

TEST_P(TextureTest, GenerateMips2DBoxFilters) {
    TextureHandle texture = device().createTexture(
        TextureDesc().setSize(16, 16).setMipLevels(0).setUsage(TextureUsage::Sampled | TextureUsage::RenderTarget));
    std::vector<std::byte> base = texelData(Format::RGBA8_UNORM, 256, 9);
    device().writeTexture(texture, {0, 0}, base.data(), base.size());
    submit([&](ICommandList& cmd) { cmd.generateMips(texture); });
    EXPECT_EQ(device().readTexture(texture, {0, 0}), base) << "mip 0 must not change";
    expectBoxFiltered(device(), texture, 0);
    std::vector<std::byte> last = device().readTexture(texture, {4, 0});
    EXPECT_EQ(last.size(), 4u) << "the 1x1 level exists";
}

// sRGB levels are averaged in linear space (what both blits and glGenerateMipmap do for sRGB
// on conforming drivers), then encoded: compare with the decoded-average-encoded reference of
// the level above, +-1 for the encode/decode rounding the specs allow.
TEST_P(TextureTest, GenerateMipsSrgbAveragesInLinearSpace) {
    TextureHandle texture = device().createTexture(TextureDesc().setFormat(Format::RGBA8_SRGB).setSize(4, 4).setMipLevels(0)
                                                       .setUsage(TextureUsage::Sampled | TextureUsage::RenderTarget));
    // Checkerboard of black and white: linear average 0.5 -> sRGB 188, not the 128 of a
    // (wrong) average of encoded values.
    std::vector<Rgba8> base(16);
    for (size_t i = 0; i < 16; ++i) base[i] = ((i % 4) + (i / 4)) % 2 ? Rgba8{255, 255, 255, 255} : Rgba8{0, 0, 0, 255};
    device().writeTexture(texture, {0, 0}, base.data(), base.size() * sizeof(Rgba8));
    submit([&](ICommandList& cmd) { cmd.generateMips(texture); });
    for (uint32_t mip : {1u, 2u}) {
        SCOPED_TRACE(fmt::format("mip {}", mip));
        for (const Rgba8& texel : readTextureAs<Rgba8>(texture, {mip, 0})) {
            EXPECT_NEAR(texel.r, 188, 1);
            EXPECT_NEAR(texel.g, 188, 1);
            EXPECT_NEAR(texel.b, 188, 1);
            EXPECT_EQ(texel.a, 255);
        }
    }
}

TEST_P(TextureTest, GenerateMipsCubeBoxFiltersEveryFace) {
    TextureHandle texture = device().createTexture(TextureDesc().setDimension(TextureDimension::TextureCube)
                                                       .setSize(8, 8).setMipLevels(0)
                                                       .setUsage(TextureUsage::Sampled | TextureUsage::RenderTarget));
    for (uint32_t face = 0; face < 6; ++face) {
        std::vector<std::byte> base = texelData(Format::RGBA8_UNORM, 64, 10 + face);
        device().writeTexture(texture, {0, face}, base.data(), base.size());
    }
    submit([&](ICommandList& cmd) { cmd.generateMips(texture); });
    for (uint32_t face = 0; face < 6; ++face) expectBoxFiltered(device(), texture, face);
}

}  // namespace
}  // namespace janus::rhi::test
