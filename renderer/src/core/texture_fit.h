// Scene textures larger than the device's largest 2D texture are uploaded downscaled
// (docs/SCENES.md, "Limits").
#pragma once

#include <cstdint>

#include "janus/renderer/scene.h"

namespace janus::renderer {

// `image` scaled down so that neither side exceeds `maxSide`, keeping the aspect ratio (each
// side rounded, at least 1), with stb_image_resize's default downsampling filter (Mitchell);
// sRGB textures are filtered in linear light with alpha weighting, linear ones (normals, data)
// per channel. An image that fits (or maxSide 0) is returned as it is.
TextureImage fitTextureToSize(const TextureImage& image, uint32_t maxSide);

}  // namespace janus::renderer
