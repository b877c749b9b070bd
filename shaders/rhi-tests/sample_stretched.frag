#version 450
// Samples `tex` with implicit derivatives stretched 8:1: over a 16x16 target, u advances 8 texels
// of a 16x16 texture per pixel in x and v one texel per pixel in y. An isotropic filter picks lod
// log2(8) = 3; a 16x anisotropic one lod 0 (the minor axis). SamplingTest.AnisotropicSamplerWorks.
layout(set = 0, binding = 0) uniform sampler2D tex;
layout(location = 0) out vec4 outColor;

void main() { outColor = texture(tex, gl_FragCoord.xy / 16.0 * vec2(8.0, 1.0)); }
