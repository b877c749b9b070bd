// janus::renderer: renders a Scene with a janus::rhi device.
//
// The frame is planned from the scene: a pass exists only if the scene needs it. Every feature
// has a compute path (needs Capability::Compute) and a fallback path (fragment shaders / CPU),
// and both run on every backend that can run them.
#pragma once

#include <cstdint>
#include <memory>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include <nlohmann/json.hpp>

#include "janus/renderer/image.h"
#include "janus/renderer/scene.h"
#include "janus/rhi/rhi.h"

namespace janus::renderer {

enum class FeaturePath { Compute, Fallback };
const char* toString(FeaturePath path);          // "compute", "fallback"
std::optional<FeaturePath> parseFeaturePath(std::string_view name);

struct RenderSettings {
    uint32_t width = 256;
    uint32_t height = 256;
    FeaturePath path = FeaturePath::Compute;
};

// One pass of one frame: what ran and what it cost.
struct PassReport {
    std::string name;
    std::optional<double> gpuMs;   // nullopt when the device has no timers
    double cpuMs = 0.0;            // recording time on the CPU
    uint32_t draws = 0;
    uint32_t dispatches = 0;
};

struct FrameReport {
    std::string backend;           // "vulkan", "gl", "gles"
    std::string path;              // "compute", "fallback"
    uint32_t width = 0, height = 0;
    std::vector<PassReport> passes;
    nlohmann::json toJson() const;
};

class RendererError : public std::runtime_error {
public:
    using std::runtime_error::runtime_error;
};

class Renderer {
public:
    // Uploads the scene. Throws RendererError for settings the device cannot honour (absurd
    // sizes; the compute path on a device without compute names the capability).
    Renderer(rhi::IDevice& device, const Scene& scene, const RenderSettings& settings);
    ~Renderer();
    Renderer(const Renderer&) = delete;
    Renderer& operator=(const Renderer&) = delete;

    FrameReport renderFrame();
    ImageRGBA8 readDisplayImage();   // tonemapped, sRGB-encoded: what PNGs and parity use
    ImageRGBAF readHdrImage();       // linear scene radiance before tonemapping: EXR / PFM

private:
    struct Impl;
    std::unique_ptr<Impl> m_impl;
};

}  // namespace janus::renderer
