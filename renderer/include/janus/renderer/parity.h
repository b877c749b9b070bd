// Whether two renders of one scene agree: the rule the renderer suite and `janus parity` / `janus
// check` share (docs/TESTING.md, "The renderer suite"; docs/CLI.md, "janus parity").
#pragma once

#include <cstdint>
#include <string>

#include "janus/renderer/image.h"
#include "janus/rhi/rhi.h"

namespace janus::renderer {

// Every channel within `tolerance` steps of 1/255, but for `edgePixels` pixels, however far off:
// a pixel centre on (or within rounding of) an edge between two triangles may go to either on GL
// and Vulkan, which apply the tie-break rule with y up and y down.
//
// Between two shader compilers, besides, one pixel in `roundingOnePixelIn` may be up to
// `roundingSteps` off. GLSL and SPIR-V both let a compiler fuse and reorder arithmetic, a vendor's
// GLSL and SPIR-V front ends do so differently, and steep shading (a normal-mapped highlight, a
// prefilter's long sums) turns ulps into steps. Seen on NVIDIA 580 (H100): DamagedHelmet under a
// sky at 128x128, gl against vulkan, 14 pixels of 16384 two or three steps off. A feature gone
// wrong moves pixels by tens of steps (the labels NVIDIA's GL sampled at mip 0 after a discard:
// up to 121), which no allowance here lets through.
struct ParityRule {
    uint32_t tolerance = 1;
    uint64_t edgePixels = 4;
    uint32_t roundingSteps = 0;
    uint64_t roundingOnePixelIn = 0;   // 0: no rounding allowance
};

inline constexpr uint32_t kCompilerRoundingSteps = 4;
inline constexpr uint64_t kCompilerRoundingOnePixelIn = 400;

// `rule` with the two-compiler allowance (kCompilerRoundingSteps in one pixel of
// kCompilerRoundingOnePixelIn).
ParityRule withCompilerRounding(ParityRule rule);

struct ParityVerdict {
    bool agrees = false;
    ImageDifference difference;          // at the rule's tolerance
    uint64_t roundingPixels = 0;         // pixels the rounding allowance let through
    std::string problem;                 // empty when they agree; else how far off, and what the rule allows
};

// Throws std::invalid_argument for images of different sizes.
ParityVerdict judgeParity(const ImageRGBA8& a, const ImageRGBA8& b, const ParityRule& rule);

// Whether two devices compile their shaders with one compiler, so that their images may be held
// to the last bit of shading math: the same backend on the same device; gl and gles on one device
// (one GLSL compiler: NVIDIA's gl and gles images were identical); or both Mesa's llvmpipe, whose
// Vulkan (lavapipe) and GL drivers compile through the same gallivm.
bool shareShaderCompiler(const rhi::DeviceInfo& a, const rhi::DeviceInfo& b);

}  // namespace janus::renderer
