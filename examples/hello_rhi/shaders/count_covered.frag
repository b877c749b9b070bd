#version 450
// The fallback path, for devices without compute (OpenGL ES 3.0): one fragment of a 1x1 target
// walks the whole image and writes the count in base 256 into its red, green and blue bytes.
layout(set = 0, binding = 0) uniform sampler2D image;
layout(location = 0) out vec4 result;

void main() {
    const ivec2 size = textureSize(image, 0);
    uint covered = 0u;
    for (int y = 0; y < size.y; ++y)
        for (int x = 0; x < size.x; ++x)
            if (texelFetch(image, ivec2(x, y), 0).a > 0.5) ++covered;
    result = vec4(uvec3(covered, covered >> 8u, covered >> 16u) & 255u, 0u) / 255.0;
}
