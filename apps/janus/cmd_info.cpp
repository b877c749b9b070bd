// `janus info`: which backends start here, what they are, and what they can do.
#include <algorithm>
#include <array>
#include <cstdio>
#include <memory>

#include <fmt/format.h>
#include <nlohmann/json.hpp>

#include "cli_common.h"

namespace janus::cli {
namespace {

struct InfoOptions {
    std::string glPlatform = "egl";
    bool json = false;
};

struct BackendReport {
    rhi::Backend backend;
    bool available = false;
    std::string reason;   // why it is unavailable
    rhi::DeviceInfo info;
    rhi::Capabilities caps;
    std::vector<rhi::FormatCapabilities> formats;   // indexed by rhi::Format
};

constexpr std::array kBackends = {rhi::Backend::Vulkan, rhi::Backend::GL, rhi::Backend::GLES};

std::vector<BackendReport> probe(rhi::GLPlatform platform) {
    std::vector<BackendReport> reports;
    for (rhi::Backend backend : kBackends) {
        BackendReport report{backend};
        try {
            rhi::DeviceDesc desc;
            desc.setBackend(backend).setGLPlatform(platform);
            std::unique_ptr<rhi::IDevice> device = rhi::createDevice(desc);
            report.info = device->info();
            report.caps = device->capabilities();
            report.formats = device->properties().formats;
            report.available = true;
        } catch (const std::exception& e) {
            // An unavailable backend is information here, not a failure of the command.
            report.reason = e.what();
        }
        reports.push_back(std::move(report));
    }
    return reports;
}

std::string workGroupTriple(const std::array<uint32_t, 3>& v) { return fmt::format("{}x{}x{}", v[0], v[1], v[2]); }

// Limits as (label, value) rows; shared by the table and the JSON so both list the same ones.
std::vector<std::pair<std::string, std::string>> limitRows(const rhi::Limits& l) {
    return {
        {"max texture 2D", std::to_string(l.maxTextureSize2D)},
        {"max texture 3D", std::to_string(l.maxTextureSize3D)},
        {"max texture cube", std::to_string(l.maxTextureSizeCube)},
        {"max texture array layers", std::to_string(l.maxTextureArrayLayers)},
        {"max colour attachments", std::to_string(l.maxColorAttachments)},
        {"max uniform buffer range", std::to_string(l.maxUniformBufferRange)},
        {"max storage buffer range", std::to_string(l.maxStorageBufferRange)},
        {"max compute work groups", workGroupTriple(l.maxComputeWorkGroupCount)},
        {"max compute group size", workGroupTriple(l.maxComputeWorkGroupSize)},
        {"max compute invocations", std::to_string(l.maxComputeWorkGroupInvocations)},
        {"uniform offset alignment", std::to_string(l.uniformBufferOffsetAlignment)},
        {"storage offset alignment", std::to_string(l.storageBufferOffsetAlignment)},
        {"max buffer size", std::to_string(l.maxBufferSize)},
        {"max vertex buffers", std::to_string(l.maxVertexBuffers)},
        {"max vertex attributes", std::to_string(l.maxVertexAttributes)},
        {"max vertex stride", std::to_string(l.maxVertexStride)},
        {"max viewport size", std::to_string(l.maxViewportSize)},
        {"viewport bounds", fmt::format("[{:g}, {:g}]", l.viewportBoundsRange[0], l.viewportBoundsRange[1])},
        {"max sampler anisotropy", fmt::format("{:g}", l.maxSamplerAnisotropy)},
    };
}

rhi::FormatCapabilities formatCaps(const BackendReport& r, rhi::Format format) {
    return size_t(format) < r.formats.size() ? r.formats[size_t(format)] : rhi::FormatCapabilities{};
}

// The format table of one backend: what each format is (static) and what this device can do with it.
std::string formatTableText(const BackendReport& r) {
    std::vector<std::vector<std::string>> rows{{"format", "kind", "bytes", "srgb"}};
    for (rhi::FormatCapability cap : rhi::kAllFormatCapabilities) rows[0].push_back(rhi::toString(cap));
    rows[0].push_back("samples");
    for (const rhi::FormatInfo& info : rhi::allFormats()) {
        std::vector<std::string> row{info.name, rhi::toString(info.kind), std::to_string(info.bytesPerPixel),
                                     info.srgb ? "yes" : "-"};
        const rhi::FormatCapabilities caps = formatCaps(r, info.format);
        for (rhi::FormatCapability cap : rhi::kAllFormatCapabilities) row.push_back(caps.has(cap) ? "yes" : "-");
        row.push_back(caps.sampleCounts ? rhi::FormatCapabilities::sampleCountText(caps.sampleCounts, ",") : "-");
        rows.push_back(std::move(row));
    }
    return formatTable(rows);
}

nlohmann::json toJson(const std::vector<BackendReport>& reports, rhi::GLPlatform platform) {
    nlohmann::json backends = nlohmann::json::array();
    for (const BackendReport& r : reports) {
        nlohmann::json entry{{"name", rhi::toString(r.backend)}, {"available", r.available}};
        if (!r.available) {
            entry["reason"] = r.reason;
            backends.push_back(std::move(entry));
            continue;
        }
        entry["apiVersion"] = r.info.apiVersion;
        entry["device"] = r.info.deviceName;
        entry["driver"] = r.info.driverInfo;
        entry["platform"] = r.info.platform;
        entry["shadingLanguage"] = r.info.shadingLanguage;
        entry["driverSettings"] = r.info.driverSettings;
        nlohmann::json caps = nlohmann::json::object();
        for (rhi::Capability cap : rhi::kAllCapabilities) caps[rhi::toString(cap)] = r.caps.has(cap);
        entry["capabilities"] = caps;
        const rhi::Limits& l = r.caps.limits;
        entry["limits"] = {
            {"maxTextureSize2D", l.maxTextureSize2D},
            {"maxTextureSize3D", l.maxTextureSize3D},
            {"maxTextureSizeCube", l.maxTextureSizeCube},
            {"maxTextureArrayLayers", l.maxTextureArrayLayers},
            {"maxColorAttachments", l.maxColorAttachments},
            {"maxUniformBufferRange", l.maxUniformBufferRange},
            {"maxStorageBufferRange", l.maxStorageBufferRange},
            {"maxComputeWorkGroupCount", l.maxComputeWorkGroupCount},
            {"maxComputeWorkGroupSize", l.maxComputeWorkGroupSize},
            {"maxComputeWorkGroupInvocations", l.maxComputeWorkGroupInvocations},
            {"uniformBufferOffsetAlignment", l.uniformBufferOffsetAlignment},
            {"storageBufferOffsetAlignment", l.storageBufferOffsetAlignment},
            {"maxBufferSize", l.maxBufferSize},
            {"maxVertexBuffers", l.maxVertexBuffers},
            {"maxVertexAttributes", l.maxVertexAttributes},
            {"maxVertexStride", l.maxVertexStride},
            {"maxViewportSize", l.maxViewportSize},
            {"viewportBoundsRange", l.viewportBoundsRange},
            {"maxSamplerAnisotropy", l.maxSamplerAnisotropy},
        };
        nlohmann::json formats = nlohmann::json::object();
        for (const rhi::FormatInfo& info : rhi::allFormats()) {
            nlohmann::json format{{"kind", rhi::toString(info.kind)}, {"bytesPerPixel", info.bytesPerPixel},
                                  {"channels", info.channels}, {"srgb", info.srgb}};
            const rhi::FormatCapabilities caps = formatCaps(r, info.format);
            for (rhi::FormatCapability cap : rhi::kAllFormatCapabilities) format[rhi::toString(cap)] = caps.has(cap);
            nlohmann::json samples = nlohmann::json::array();
            for (uint32_t n = 1; n <= caps.sampleCounts && n; n <<= 1)
                if (caps.sampleCounts & n) samples.push_back(n);
            format["sampleCounts"] = std::move(samples);
            formats[info.name] = std::move(format);
        }
        entry["formats"] = std::move(formats);
        entry["conventions"] = {
            {"nativeClipDepthZeroToOne", r.caps.conventions.nativeClipDepthZeroToOne},
            {"nativeFramebufferOriginTopLeft", r.caps.conventions.nativeFramebufferOriginTopLeft},
            {"presentedClipDepth", "[0, 1]"},
            {"presentedRow0", "top (v = 0)"},
        };
        backends.push_back(std::move(entry));
    }
    nlohmann::json eglDevices = nlohmann::json::array();
    for (const rhi::EglDeviceListing& d : rhi::listEglDevices())
        eglDevices.push_back({{"index", d.index}, {"names", d.names}});
    return {{"glPlatform", rhi::toString(platform)}, {"backends", backends}, {"eglDevices", eglDevices}};
}

void printText(const std::vector<BackendReport>& reports, rhi::GLPlatform platform) {
    std::string out = fmt::format("Backends (GL platform: {})\n", rhi::toString(platform));
    for (const BackendReport& r : reports) {
        out += fmt::format("\n  {}: {}\n", rhi::toString(r.backend), r.available ? "available" : "unavailable");
        if (!r.available) {
            out += fmt::format("    reason: {}\n", r.reason);
            continue;
        }
        std::vector<std::vector<std::string>> rows{{"API version", r.info.apiVersion},
                                                   {"device", r.info.deviceName},
                                                   {"driver", r.info.driverInfo},
                                                   {"platform", r.info.platform},
                                                   {"shading language", r.info.shadingLanguage}};
        if (!r.info.driverSettings.empty()) rows.push_back({"driver settings", r.info.driverSettings});
        out += formatTable(rows, 4);
    }

    // What JANUS_EGL_DEVICE can name (its index or any of its names).
    const std::vector<rhi::EglDeviceListing> eglDevices = rhi::listEglDevices();
    if (eglDevices.empty()) {
        out += "\nEGL devices: none listed (this EGL cannot enumerate devices)\n";
    } else {
        std::vector<std::vector<std::string>> rows;
        for (const rhi::EglDeviceListing& d : eglDevices) {
            std::string names;
            for (const std::string& name : d.names) names += (names.empty() ? "" : ", ") + name;
            rows.push_back({std::to_string(d.index), names.empty() ? "(no name: use the index)" : names});
        }
        out += "\nEGL devices (JANUS_EGL_DEVICE=<index or name>)\n" + formatTable(rows);
    }

    if (std::none_of(reports.begin(), reports.end(), [](const BackendReport& r) { return r.available; })) {
        out += "\nNo backend started, so there are no capabilities to show.\n";
        std::fputs(out.c_str(), stdout);
        return;
    }

    // One column per backend; "-" where the backend did not start.
    std::vector<std::string> header{""};
    for (const BackendReport& r : reports) header.push_back(rhi::toString(r.backend));
    auto cell = [](const BackendReport& r, const std::string& value) { return r.available ? value : std::string("-"); };

    std::vector<std::vector<std::string>> caps{header};
    for (rhi::Capability cap : rhi::kAllCapabilities) {
        std::vector<std::string> row{rhi::toString(cap)};
        for (const BackendReport& r : reports) row.push_back(cell(r, r.caps.has(cap) ? "yes" : "no"));
        caps.push_back(std::move(row));
    }
    out += "\nCapabilities\n" + formatTable(caps);

    std::vector<std::vector<std::string>> limits{header};
    for (const auto& [label, unused] : limitRows(rhi::Limits{})) limits.push_back({label});
    for (const BackendReport& r : reports) {
        const auto values = limitRows(r.caps.limits);
        for (size_t i = 0; i < values.size(); ++i) limits[i + 1].push_back(cell(r, values[i].second));
    }
    out += "\nLimits\n" + formatTable(limits);

    // What the RHI presents is the same everywhere; what differs is how much is translated.
    std::vector<std::vector<std::string>> conventions{header};
    std::vector<std::string> depthRow{"clip depth [0, 1]"}, originRow{"row 0 = top (v = 0)"};
    for (const BackendReport& r : reports) {
        depthRow.push_back(cell(r, r.caps.conventions.nativeClipDepthZeroToOne ? "native" : "emulated"));
        originRow.push_back(cell(r, r.caps.conventions.nativeFramebufferOriginTopLeft ? "native" : "translated"));
    }
    conventions.push_back(depthRow);
    conventions.push_back(originRow);
    out += "\nConventions (presented identically by every backend; native = no translation needed)\n" +
           formatTable(conventions);

    // What each backend can do with each format (the validation layer checks every use against it).
    for (const BackendReport& r : reports) {
        if (!r.available) continue;
        out += fmt::format("\nFormats on {} (yes = the device can; checked by validation)\n", rhi::toString(r.backend)) +
               formatTableText(r);
    }
    std::fputs(out.c_str(), stdout);
}

}  // namespace

Command addInfoCommand(CLI::App& parent) {
    auto options = std::make_shared<InfoOptions>();
    CLI::App* app = parent.add_subcommand("info", "Show each backend (vulkan, gl, gles): availability, device, "
                                                  "capabilities, limits, conventions, format capabilities");
    addGLPlatformOption(*app, options->glPlatform);
    app->add_flag("--json", options->json, "Print JSON instead of a table");
    app->footer(kExitCodeHelp);
    return {app, [options] {
                const rhi::GLPlatform platform = parseGLPlatformOption(options->glPlatform);
                const std::vector<BackendReport> reports = probe(platform);
                if (options->json)
                    std::fputs((toJson(reports, platform).dump(2) + "\n").c_str(), stdout);
                else
                    printText(reports, platform);
                return 0;
            }};
}

}  // namespace janus::cli
