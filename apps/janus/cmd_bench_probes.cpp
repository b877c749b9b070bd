// `janus bench probes`: accuracy vs. time of the GGX prefilter that updates a reflection probe.
// Sweeps samples per mip and face size on each path and backend; per mip the relative RMSE and max
// relative error against the CPU reference (GgxReference on a texel subset), beside the prefilter
// pass's GPU time; probes.md / probes.json / probes.png (docs/BENCHMARKS.md).
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <memory>
#include <sstream>

#include <fmt/format.h>
#include <nlohmann/json.hpp>

#include "cli_common.h"
#include "janus/renderer/ibl_bench.h"
#include "plot.h"

namespace janus::cli {
namespace {

struct ProbesOptions {
    std::string samples = "8,16,34,64,128,256,1024";
    std::string sizes = "64,128,256";
    std::string env;
    BenchTargets targets{"compute,fallback", "vulkan,gl,gles"};
    uint32_t runs = 5;
    uint32_t grid = 8;
    uint32_t brightTexels = renderer::kDefaultProbeBrightTexels;
    bool quick = false;
};

struct Row {
    std::string backend, path;
    uint32_t faceSize = 0, samples = 0;   // 0: the default ramp
    double referenceCpuMs = 0.0;
    renderer::ProbeMeasurement m;
};

int runProbes(const ProbesOptions& options) {
    // "default" in --samples: the prefilter's default ramp (21, 34, 55, 89, 89, 89; the last repeats), listed first.
    std::string counts;
    bool withDefault = false;
    {
        std::stringstream stream(options.quick ? std::string("16,64") : options.samples);
        for (std::string item; std::getline(stream, item, ',');) {
            if (item == "default") {
                withDefault = true;
                continue;
            }
            counts += (counts.empty() ? "" : ",") + item;
        }
    }
    std::vector<uint32_t> samples;
    if (!counts.empty() || !withDefault)
        samples = parseCountList(counts.empty() ? options.samples : counts, "--samples", 1, renderer::kMaxProbeSamplesPerMip, false);
    if (withDefault) samples.insert(samples.begin(), 0u);
    if (options.brightTexels > renderer::kMaxProbeBrightTexels)
        throw UsageError(fmt::format("--bright-texels {} must be 0..{}", options.brightTexels, renderer::kMaxProbeBrightTexels));
    const std::vector<uint32_t> sizes = parseCountList(options.quick ? "32" : options.sizes, "--sizes", 4, 2048, true);
    const auto [paths, backends] = parseBenchTargets(options.targets, options.quick, "compute", "vulkan");
    if (options.runs < 1 || options.runs > 100) throw UsageError(fmt::format("--runs {} must be 1..100", options.runs));
    if (options.grid < 1 || options.grid > 256) throw UsageError(fmt::format("--grid {} must be 1..256", options.grid));
    const uint32_t runs = options.quick ? std::min(options.runs, 3u) : options.runs;
    EnvironmentOptions envOptions;
    envOptions.map = options.env;
    const EnvironmentOverride env = parseEnvironmentOptions(envOptions);   // exit 2 bad extension, 3 missing
    const std::filesystem::path outDir = benchOutputDir(options.targets.out, "probes");

    std::string envLabel;
    renderer::ImageRGBAF sky;
    if (env.map) {
        sky = lowerCaseExtension(*env.map) == ".exr" ? renderer::readEXR(*env.map) : renderer::readRadianceHDR(*env.map);
        envLabel = fmt::format("{} ({}x{} equirect)", env.map->filename().string(), sky.width, sky.height);
    } else {
        sky = renderer::syntheticProbeSky();
        envLabel = "synthetic smooth sky (512x256 equirect: gradient 0.2 + 0.3 (0.5 + 0.5 d) plus a soft lobe "
                   "(4, 3, 2) max(0, d.s)^8, s = normalize(0.4, 0.7, -0.6))";
    }

    std::vector<Row> rows;
    std::vector<std::string> skipped;
    for (rhi::Backend backend : backends) {
        rhi::DeviceDesc desc;
        desc.setBackend(backend).setGLPlatform(parseGLPlatformOption(options.targets.glPlatform));
        std::unique_ptr<rhi::IDevice> device = rhi::createDevice(desc);
        for (renderer::FeaturePath path : paths) {
            if (std::optional<std::string> why = renderer::probeBenchUnsupported(*device, path)) {
                skipped.push_back(fmt::format("{}: {}", configurationLabel(backend, path), *why));
                std::fprintf(stderr, "  %s skipped: %s\n", configurationLabel(backend, path).c_str(), why->c_str());
                continue;
            }
            for (uint32_t size : sizes) {
                if (size > device->capabilities().limits.maxTextureSizeCube) {
                    skipped.push_back(fmt::format("{} {}^2: above the cube limit {}", configurationLabel(backend, path), size,
                                                  device->capabilities().limits.maxTextureSizeCube));
                    continue;
                }
                renderer::ProbeAccuracyBench bench(*device, sky, size, path, options.grid);
                for (uint32_t n : samples) {
                    Row row{rhi::toString(backend), renderer::toString(path), size, n, bench.referenceCpuMs(),
                            bench.measure(n == 0 ? renderer::defaultProbeSamplesPerMip() : std::vector<uint32_t>{n}, runs, 1, options.brightTexels)};
                    std::fprintf(stderr, "  %s %4u^2 %7s samples: %8.3f ms, mip 1 RMSE %.2f %%, %u bright texels%s\n",
                                 configurationLabel(backend, path).c_str(), size, n == 0 ? "default" : std::to_string(n).c_str(), row.m.gpuMs,
                                 row.m.mips.empty() ? 0.0 : 100.0 * row.m.mips[0].rmse, row.m.brightFound,
                                 row.m.brightOverflow ? " (too many: no split)" : "");
                    rows.push_back(std::move(row));
                }
            }
        }
        reportDebugMessages(rhi::toString(backend), device->takeDebugMessages());
    }
    if (rows.empty()) throw UnavailableError("bench probes: no configuration could run (" + fmt::format("{}", fmt::join(skipped, "; ")) + ")");

    const bool timed = std::all_of(rows.begin(), rows.end(), [](const Row& r) { return r.m.gpuTimed; });
    std::string md = fmt::format(
        "# Reflection probes: GGX prefilter accuracy vs time\n\n"
        "Environment: {}. Each probe update = one `ggx-prefilter-*` pass (generateMips, mip-0 copies, mips 1..N-1), "
        "the same samples on every mip; {} = median of {} runs after one warm-up{}.\n"
        "Errors per mip against the double-precision CPU reference (GgxReference over every texel of the converted cube's mip 0), "
        "on up to {}x{} texels per face (a regular grid; every texel of smaller mips): relative RMSE / max relative error in %.\n"
        "Samples per mip are capped at {} (the sample block is 16 KiB, the minimum uniform block size of GLES 3.0 / GL / Vulkan); "
        "\"default\" = the prefilter's default ramp 21, 34, 55, 89, 89, 89 (the last repeats).\n"
        "Bright texels (docs/IBL.md): {}.\n",
        envLabel, timed ? "GPU ms" : "ms", runs, timed ? "" : " (CPU recording ms where the device has no timers)", options.grid,
        options.grid, renderer::kMaxProbeSamplesPerMip,
        options.brightTexels == 0
            ? std::string("off (--bright-texels 0): plain filtered importance sampling")
            : fmt::format("up to {} texels at least 64x the mean taken out and summed exactly (--bright-texels {}); \"bright\" = how many "
                          "the source has",
                          options.brightTexels, options.brightTexels));
    nlohmann::json json = {{"environment", envLabel},
                           {"synthetic", !env.map},
                           {"runs", runs},
                           {"gridPerFace", options.grid},
                           {"sampleCap", renderer::kMaxProbeSamplesPerMip},
                           {"brightTexels", options.brightTexels},
                           {"configurations", nlohmann::json::array()},
                           {"skipped", skipped}};
    for (uint32_t size : sizes) {
        std::vector<const Row*> sized;
        for (const Row& row : rows)
            if (row.faceSize == size) sized.push_back(&row);
        if (sized.empty()) continue;
        const std::vector<renderer::ProbeMipError>& mips = sized.front()->m.mips;
        md += fmt::format("\n## {}² faces ({} mips)\n\n| backend | path | samples | GPU ms |", size, mips.size() + 1);
        std::string rule = "|---|---|---:|---:|";
        for (const renderer::ProbeMipError& e : mips) {
            md += fmt::format(" mip {} (r {:.2f}) |", e.mip, e.roughness);
            rule += "---:|";
        }
        if (options.brightTexels) {
            md += " bright |";
            rule += "---:|";
        }
        md += "\n" + rule + "\n";
        for (const Row* row : sized) {
            md += fmt::format("| {} | {} | {} | {:.3f} |", row->backend, row->path, row->samples == 0 ? std::string("default") : std::to_string(row->samples),
                              row->m.gpuMs);
            for (const renderer::ProbeMipError& e : row->m.mips) md += fmt::format(" {:.2f} / {:.2f} |", 100.0 * e.rmse, 100.0 * e.maxRel);
            if (options.brightTexels)
                md += row->m.brightOverflow ? fmt::format(" {} (over) |", row->m.brightFound) : fmt::format(" {} |", row->m.brightFound);
            md += "\n";
        }
    }
    if (!skipped.empty()) {
        md += "\nSkipped:\n\n";
        for (const std::string& s : skipped) md += "- " + s + "\n";
    }
    std::vector<PlotSeries> series;
    for (const Row& row : rows) {
        nlohmann::json mips = nlohmann::json::array();
        double worst = 0.0;
        for (const renderer::ProbeMipError& e : row.m.mips) {
            mips.push_back({{"mip", e.mip}, {"roughness", e.roughness}, {"samplesRequested", e.samplesRequested},
                            {"samplesUsed", e.samplesUsed}, {"texelsCompared", e.texelsCompared}, {"rmse", e.rmse},
                            {"maxRel", std::isfinite(e.maxRel) ? e.maxRel : 1e30}});
            worst = std::max(worst, e.rmse);
        }
        json["configurations"].push_back(
            {{"backend", row.backend}, {"path", row.path}, {"faceSize", row.faceSize},
             {"samplesPerMip", row.samples == 0 ? nlohmann::json("default") : nlohmann::json(row.samples)},
             {"samplesPerMipList", row.samples == 0 ? renderer::defaultProbeSamplesPerMip() : std::vector<uint32_t>{row.samples}}, {"gpuMs", row.m.gpuMs},
             {"gpuMsRuns", row.m.gpuMsRuns}, {"gpuTimed", row.m.gpuTimed}, {"referenceCpuMs", row.referenceCpuMs},
             {"brightFound", row.m.brightFound}, {"brightOverflow", row.m.brightOverflow}, {"mips", mips}});
        // Plot: worst-mip relative RMSE (%) vs GPU ms, one line per backend/path/size.
        const std::string name = fmt::format("{}/{} {}", row.backend, row.path, row.faceSize);
        PlotSeries& line = seriesNamed(series, name);
        if (row.m.gpuMs > 0.0 && worst > 0.0) line.points.push_back({row.m.gpuMs, 100.0 * worst});
    }
    md += "\nPlot (probes.png): worst-mip relative RMSE (%) against GPU ms per update, log-log, one line per backend/path/face "
          "size, points in order of samples.\n";
    writeBenchOutputs(outDir, "probes", md, json, drawLogXPlot(series, "GPU MS PER UPDATE", "WORST MIP RELATIVE RMSE (PERCENT)"));
    return 0;
}

}  // namespace

std::function<int()> addBenchProbesCommand(CLI::App& bench) {
    auto options = std::make_shared<ProbesOptions>();
    CLI::App* probes = bench.add_subcommand(
        "probes", "GGX prefilter (reflection probe update): error against the CPU reference vs GPU time, per samples per mip, "
                  "face size, path and backend; writes probes.md, probes.json, probes.png to --out");
    probes->add_option("--samples", options->samples, "Comma-separated samples per mip (1..1024, or 'default': 21,34,55,89,89,89)")
        ->default_str(options->samples);
    probes->add_option("--sizes", options->sizes, "Comma-separated probe face sizes (powers of two, 4..2048)")->default_str(options->sizes);
    probes->add_option("--env", options->env, "Equirectangular .hdr/.exr sky; default: a synthetic smooth sky")->type_name("FILE");
    probes->add_option("--runs", options->runs, "Timed prefilter runs per configuration (median)")->default_str("5");
    probes->add_option("--grid", options->grid, "Reference texels per face and mip: a grid of at most N x N")->default_str("8");
    probes->add_option("--bright-texels", options->brightTexels,
                       "The prefilter's bright-texel split: at most N texels taken out and summed exactly (0 = off)")
        ->default_str(std::to_string(renderer::kDefaultProbeBrightTexels));
    probes->add_flag("--quick", options->quick,
                     "Tiny run for tests: samples 16,64 at 32^2, 3 runs, vulkan/compute unless --backends/--paths are given");
    addBenchTargetOptions(*probes, options->targets);
    probes->footer(kExitCodeHelp);
    return [options, probes] {
        noteBenchTargetsGiven(*probes, options->targets);
        return runProbes(*options);
    };
}

}  // namespace janus::cli
