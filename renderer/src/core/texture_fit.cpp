#include "core/texture_fit.h"

#include <algorithm>
#include <cmath>

#include <fmt/format.h>
#include <stb/stb_image_resize.h>   // the implementation is in Debian's libstb

namespace janus::renderer {

TextureImage fitTextureToSize(const TextureImage& image, uint32_t maxSide) {
    if (maxSide == 0 || (image.width <= maxSide && image.height <= maxSide)) return image;
    const double scale = double(maxSide) / double(std::max(image.width, image.height));
    auto side = [&](uint32_t s) { return std::clamp(uint32_t(std::lround(double(s) * scale)), 1u, maxSide); };
    TextureImage fitted;
    fitted.name = image.name;
    fitted.srgb = image.srgb;
    fitted.sampling = image.sampling;
    fitted.width = side(image.width);
    fitted.height = side(image.height);
    fitted.rgba.resize(size_t(fitted.width) * fitted.height * 4);
    const int ok = image.srgb ? stbir_resize_uint8_srgb(image.rgba.data(), int(image.width), int(image.height), 0, fitted.rgba.data(),
                                                        int(fitted.width), int(fitted.height), 0, 4, 3, 0)
                              : stbir_resize_uint8(image.rgba.data(), int(image.width), int(image.height), 0, fitted.rgba.data(),
                                                   int(fitted.width), int(fitted.height), 0, 4);
    if (!ok)
        throw SceneError(fmt::format("texture '{}' ({}x{}) could not be downscaled to {}x{}", image.name, image.width, image.height,
                                     fitted.width, fitted.height));
    return fitted;
}

}  // namespace janus::renderer
