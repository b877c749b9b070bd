// `janus check PATH...`: every .gltf / .glb under the paths, on every configuration this machine
// has, at a small size: rendered / refused / failed, the glTF features each file uses, and
// whether the configurations agree. What a user runs on an asset folder before porting.
#include <algorithm>
#include <cctype>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <memory>
#include <set>

#include <fmt/format.h>
#include <nlohmann/json.hpp>

#include "cli_common.h"
#include "configurations.h"
#include "gltf_features.h"

namespace janus::cli {
namespace {

struct CheckOptions {
    std::vector<std::string> paths;
    std::string out;
    std::string size = "64x64";
    std::string tolerance = "1";
    std::string edgePixels = std::to_string(kDefaultEdgePixels);
    std::string compilerRounding = "auto";
    std::string glPlatform = "egl";
    bool validation = false;
    bool allowOutsidePaths = false;
    EnvironmentOptions environment;
};

// ---- finding the files ----------------------------------------------------------------------

bool isGltfName(const std::filesystem::path& path) {
    const std::string extension = lowerCaseExtension(path);
    return extension == ".gltf" || extension == ".glb";
}

// The files in argument order; each folder's files sorted by path (bytewise), so the order, and
// with it the contact sheets' grid, is the same on every run. A file named twice (also through a
// folder) is checked once, where it first appears.
std::vector<std::filesystem::path> findGltfFiles(const std::vector<std::string>& arguments) {
    std::vector<std::filesystem::path> files;
    std::set<std::filesystem::path> seen;
    auto add = [&](const std::filesystem::path& file) {
        std::error_code ec;
        std::filesystem::path key = std::filesystem::weakly_canonical(file, ec);
        if (ec) key = std::filesystem::absolute(file).lexically_normal();
        if (seen.insert(key).second) files.push_back(file);
    };
    for (const std::string& argument : arguments) {
        const std::filesystem::path path = argument;
        std::error_code ec;
        if (!std::filesystem::exists(path, ec))
            throw InputError(fmt::format("PATH '{}' does not exist; give .gltf / .glb files or folders that hold some", argument));
        if (!std::filesystem::is_directory(path, ec)) {
            if (!isGltfName(path))
                throw InputError(fmt::format("PATH '{}' is not a .gltf or .glb file; give one, or a folder to search", argument));
            if (const std::string kind = notRegularFileKind(path); !kind.empty())
                throw InputError(fmt::format("PATH '{}' is {}, not a regular file; give .gltf / .glb files or folders that hold some",
                                             argument, kind));
            add(path);
            continue;
        }
        std::vector<std::filesystem::path> found;
        std::filesystem::recursive_directory_iterator it(path, std::filesystem::directory_options::skip_permission_denied, ec);
        for (; !ec && it != std::filesystem::recursive_directory_iterator(); it.increment(ec)) {
            std::error_code fileEc;
            if (isGltfName(it->path()) && it->is_regular_file(fileEc)) found.push_back(it->path());
        }
        if (ec) throw InputError(fmt::format("cannot search folder '{}': {}", argument, ec.message()));
        if (found.empty())
            throw InputError(fmt::format("no .gltf or .glb file under '{}' (its subfolders were searched too)", argument));
        std::sort(found.begin(), found.end(), [](const auto& a, const auto& b) { return a.generic_string() < b.generic_string(); });
        for (const std::filesystem::path& file : found) add(file);
    }
    return files;
}

// ---- results --------------------------------------------------------------------------------

enum class FileStatus { Rendered, Diverged, Failed, Refused };
enum class ConfigStatus { Rendered, Failed, Unavailable, NotRun };

const char* toString(FileStatus status) {
    switch (status) {
        case FileStatus::Rendered: return "rendered";
        case FileStatus::Diverged: return "diverged";
        case FileStatus::Failed: return "failed";
        case FileStatus::Refused: return "refused";
    }
    return "?";
}

const char* toString(ConfigStatus status) {
    switch (status) {
        case ConfigStatus::Rendered: return "rendered";
        case ConfigStatus::Failed: return "failed";
        case ConfigStatus::Unavailable: return "unavailable";
        case ConfigStatus::NotRun: return "not-run";
    }
    return "?";
}

struct ConfigOutcome {
    ConfigStatus status = ConfigStatus::NotRun;
    std::string error;   // failed: why
    std::string image;   // rendered: thumbnail, relative to --out
};

struct PairOutcome {
    std::string a, b;   // file stems, "vulkan-compute"
    renderer::ImageDifference difference;
    bool passed = false;
    std::string heatmap;   // relative to --out; only for pairs beyond the tolerance
};

struct FileResult {
    std::filesystem::path path;
    GltfUsage usage;
    FileStatus status = FileStatus::Rendered;
    std::string reason;   // refused: the loader's message
    std::vector<std::string> warnings;   // the loader's (renderer::Scene::warnings): what it ignored
    std::vector<ConfigOutcome> configs;   // one per kConfigurations entry
    std::vector<PairOutcome> pairs;       // the pairs of configurations that both rendered
    double seconds = 0.0;

    std::optional<uint32_t> maxDifference() const {
        std::optional<uint32_t> max;
        for (const PairOutcome& pair : pairs) max = std::max(max.value_or(0), pair.difference.maxChannelDifference);
        return max;
    }
};

// ---- contact sheets -------------------------------------------------------------------------

// Each thumbnail sits in a frame of this many pixels whose colour tells the file's status.
constexpr uint32_t kSheetBorder = 2;

struct Rgb {
    uint8_t r, g, b;
};
constexpr Rgb kFrameOk{40, 40, 40};            // rendered or refused
constexpr Rgb kFrameDiverged{255, 140, 0};     // orange
constexpr Rgb kFrameFailed{220, 0, 0};         // red
constexpr Rgb kRefusedTile{110, 110, 110};     // grey with a darker cross
constexpr Rgb kRefusedCross{60, 60, 60};
constexpr Rgb kFailedTile{110, 0, 0};          // dark red with a lighter cross
constexpr Rgb kFailedCross{200, 60, 60};
constexpr Rgb kEmptyCell{0, 0, 0};             // cells past the last file

struct SheetLayout {
    uint32_t columns = 0, rows = 0;
    uint32_t tileWidth = 0, tileHeight = 0;
    uint32_t cellWidth() const { return tileWidth + 2 * kSheetBorder; }
    uint32_t cellHeight() const { return tileHeight + 2 * kSheetBorder; }
    uint32_t width() const { return columns * cellWidth(); }
    uint32_t height() const { return rows * cellHeight(); }
};

// As square as possible: columns = ceil(sqrt(files)), rows = ceil(files / columns).
SheetLayout sheetLayout(size_t files, ImageSize tile) {
    SheetLayout layout;
    layout.columns = 1;
    while (uint64_t(layout.columns) * layout.columns < files) ++layout.columns;
    layout.rows = uint32_t((files + layout.columns - 1) / layout.columns);
    layout.tileWidth = tile.width;
    layout.tileHeight = tile.height;
    return layout;
}

void setPixel(renderer::ImageRGBA8& image, uint32_t x, uint32_t y, Rgb colour) {
    uint8_t* p = &image.pixels[(size_t(y) * image.width + x) * 4];
    p[0] = colour.r, p[1] = colour.g, p[2] = colour.b, p[3] = 255;
}

void fillRect(renderer::ImageRGBA8& image, uint32_t x0, uint32_t y0, uint32_t w, uint32_t h, Rgb colour) {
    for (uint32_t y = y0; y < y0 + h; ++y)
        for (uint32_t x = x0; x < x0 + w; ++x) setPixel(image, x, y, colour);
}

renderer::ImageRGBA8 emptySheet(const SheetLayout& layout) {
    renderer::ImageRGBA8 sheet{layout.width(), layout.height(), {}};
    sheet.pixels.resize(size_t(sheet.width) * sheet.height * 4);
    fillRect(sheet, 0, 0, sheet.width, sheet.height, kEmptyCell);
    return sheet;
}

// Cell `index` (row-major): the frame, then the thumbnail or a placeholder with a diagonal cross.
void paintCell(renderer::ImageRGBA8& sheet, const SheetLayout& layout, size_t index, Rgb frame, const renderer::ImageRGBA8* thumbnail,
               Rgb placeholder, Rgb cross) {
    const uint32_t x0 = uint32_t(index % layout.columns) * layout.cellWidth();
    const uint32_t y0 = uint32_t(index / layout.columns) * layout.cellHeight();
    fillRect(sheet, x0, y0, layout.cellWidth(), layout.cellHeight(), frame);
    const uint32_t tx = x0 + kSheetBorder, ty = y0 + kSheetBorder;
    if (thumbnail && thumbnail->width == layout.tileWidth && thumbnail->height == layout.tileHeight) {
        for (uint32_t y = 0; y < layout.tileHeight; ++y)
            std::copy_n(&thumbnail->pixels[size_t(y) * layout.tileWidth * 4], size_t(layout.tileWidth) * 4,
                        &sheet.pixels[(size_t(ty + y) * sheet.width + tx) * 4]);
        return;
    }
    fillRect(sheet, tx, ty, layout.tileWidth, layout.tileHeight, placeholder);
    const uint32_t w = layout.tileWidth, h = layout.tileHeight;
    const uint32_t steps = std::max(w, h);
    for (uint32_t i = 0; i < steps; ++i) {
        const uint32_t x = uint32_t(uint64_t(i) * w / steps), y = uint32_t(uint64_t(i) * h / steps);
        setPixel(sheet, tx + x, ty + y, cross);
        setPixel(sheet, tx + (w - 1 - x), ty + y, cross);
    }
}

// ---- report text ----------------------------------------------------------------------------

// Safe in a Markdown table cell: no column breaks, no line breaks.
std::string cell(std::string_view text) {
    std::string out;
    for (char c : text) {
        if (c == '|') out += "\\|";
        else if (c == '\n' || c == '\r') out += ' ';
        else out += c;
    }
    return out;
}

std::string joined(const std::vector<std::string>& items, std::string_view separator, std::string_view none = "-") {
    if (items.empty()) return std::string(none);
    std::string out;
    for (const std::string& item : items) out += (out.empty() ? "" : std::string(separator)) + item;
    return out;
}

// Used extensions, "(required)" after those the file also requires (and any required but not listed as used).
std::vector<std::string> extensionLabels(const GltfUsage& usage) {
    std::vector<std::string> labels;
    auto required = [&](const std::string& name) {
        return std::find(usage.extensionsRequired.begin(), usage.extensionsRequired.end(), name) != usage.extensionsRequired.end();
    };
    for (const std::string& name : usage.extensionsUsed) labels.push_back(required(name) ? name + " (required)" : name);
    for (const std::string& name : usage.extensionsRequired)
        if (std::find(usage.extensionsUsed.begin(), usage.extensionsUsed.end(), name) == usage.extensionsUsed.end())
            labels.push_back(name + " (required)");
    return labels;
}

std::string configCell(const ConfigOutcome& outcome) {
    switch (outcome.status) {
        case ConfigStatus::Rendered: return "ok";
        case ConfigStatus::Failed: return "FAILED";
        case ConfigStatus::Unavailable: return "n/a";
        case ConfigStatus::NotRun: return "-";
    }
    return "?";
}

nlohmann::json pairJson(const PairOutcome& pair) {
    const renderer::ImageDifference& diff = pair.difference;
    nlohmann::json json{{"a", pair.a},
                        {"b", pair.b},
                        {"maxChannelDifference", diff.maxChannelDifference},
                        {"identical", std::isinf(diff.psnr)},
                        {"psnr", std::isinf(diff.psnr) ? nlohmann::json(nullptr) : nlohmann::json(diff.psnr)},
                        {"differingPixels", diff.differingPixels},
                        {"totalPixels", diff.totalPixels},
                        {"passed", pair.passed}};
    if (!pair.heatmap.empty()) json["heatmap"] = pair.heatmap;
    return json;
}

nlohmann::json fileJson(const FileResult& file, size_t index) {
    nlohmann::json json{{"index", index},
                        {"path", file.path.generic_string()},
                        {"status", toString(file.status)},
                        {"extensionsUsed", file.usage.extensionsUsed},
                        {"extensionsRequired", file.usage.extensionsRequired},
                        {"features", file.usage.features}};
    if (!file.usage.error.empty()) json["featuresError"] = file.usage.error;
    if (!file.reason.empty()) json["reason"] = file.reason;
    json["warnings"] = file.warnings;
    nlohmann::json configs = nlohmann::json::array();
    for (size_t c = 0; c < kConfigurations.size(); ++c) {
        const ConfigOutcome& outcome = file.configs[c];
        nlohmann::json entry{{"configuration", configurationLabel(kConfigurations[c].backend, kConfigurations[c].path)},
                             {"status", toString(outcome.status)}};
        if (!outcome.error.empty()) entry["error"] = outcome.error;
        if (!outcome.image.empty()) entry["image"] = outcome.image;
        configs.push_back(std::move(entry));
    }
    json["configurations"] = std::move(configs);
    if (file.status == FileStatus::Refused) {
        json["parity"] = nullptr;
    } else {
        nlohmann::json pairs = nlohmann::json::array();
        bool passed = true;
        for (const PairOutcome& pair : file.pairs) {
            pairs.push_back(pairJson(pair));
            passed = passed && pair.passed;
        }
        const std::optional<uint32_t> max = file.maxDifference();
        json["parity"] = {{"pairsCompared", file.pairs.size()},
                          {"maxChannelDifference", max ? nlohmann::json(*max) : nlohmann::json(nullptr)},
                          {"passed", passed},
                          {"pairs", std::move(pairs)}};
    }
    return json;
}

struct Counts {
    size_t rendered = 0, diverged = 0, failed = 0, refused = 0;
    void add(FileStatus status) {
        switch (status) {
            case FileStatus::Rendered: ++rendered; break;
            case FileStatus::Diverged: ++diverged; break;
            case FileStatus::Failed: ++failed; break;
            case FileStatus::Refused: ++refused; break;
        }
    }
    bool passed() const { return diverged == 0 && failed == 0; }
};

struct Report {
    std::vector<std::string> paths;
    ImageSize size;
    uint32_t tolerance = 1;
    uint64_t edgePixels = kDefaultEdgePixels;
    bool compilerRounding = true;   // --compiler-rounding auto
    std::string glPlatform;
    std::vector<ConfigurationAvailability> availability;
    std::vector<std::string> sheets;   // per configuration: contact sheet file name, "" when unavailable
    SheetLayout layout;
    std::vector<FileResult> files;
    Counts counts;
};

std::string countsText(const Report& report) {
    return fmt::format("{} file(s): {} rendered, {} diverged, {} failed, {} refused", report.files.size(), report.counts.rendered,
                       report.counts.diverged, report.counts.failed, report.counts.refused);
}

std::string markdown(const Report& report) {
    const Counts& counts = report.counts;
    std::string md = "# janus check\n\n";
    std::vector<std::string> quoted;
    for (const std::string& path : report.paths) quoted.push_back(fmt::format("`{}`", path));
    md += fmt::format("- paths: {}\n", joined(quoted, ", "));
    md += fmt::format("- {}\n", countsText(report));
    md += fmt::format("- size {}x{}, tolerance {} step(s) of 1/255, up to {} edge pixel(s) beyond it, compiler rounding {}\n",
                      report.size.width, report.size.height, report.tolerance, report.edgePixels,
                      report.compilerRounding ? "auto" : "off");
    md += fmt::format("- result: **{}** (exit {})\n\n", counts.passed() ? "PASSED" : "FAILED",
                      counts.passed() ? 0 : int(ExitCode::ComparisonFailed));

    md += "## Configurations\n\n| configuration | available | device or reason | contact sheet |\n|---|---|---|---|\n";
    for (size_t c = 0; c < report.availability.size(); ++c) {
        const ConfigurationAvailability& a = report.availability[c];
        md += fmt::format("| {} | {} | {} | {} |\n", configurationLabel(a.config.backend, a.config.path), a.available ? "yes" : "no",
                          cell(a.available ? a.device : a.reason), report.sheets[c].empty() ? "-" : report.sheets[c]);
    }

    md += "\n## Files\n\n| # | file | status | max diff |";
    std::string rule = "|---|---|---|---|";
    for (const Configuration& config : kConfigurations) {
        md += fmt::format(" {} |", configurationLabel(config.backend, config.path));
        rule += "---|";
    }
    md += " features | extensions |\n" + rule + "---|---|\n";
    for (size_t i = 0; i < report.files.size(); ++i) {
        const FileResult& file = report.files[i];
        const std::optional<uint32_t> max = file.maxDifference();
        md += fmt::format("| {} | {} | {} | {} |", i + 1, cell(file.path.generic_string()), toString(file.status),
                          max ? std::to_string(*max) : "-");
        for (const ConfigOutcome& outcome : file.configs) md += fmt::format(" {} |", configCell(outcome));
        const std::string features = file.usage.error.empty() ? joined(file.usage.features, ", ") : "? (" + file.usage.error + ")";
        md += fmt::format(" {} | {} |\n", cell(features), cell(joined(extensionLabels(file.usage), ", ")));
    }
    md += "\nPer configuration: ok = rendered, FAILED = did not render (reason below), n/a = configuration unavailable on this "
          "machine, - = not run (file refused). max diff: the largest channel difference, in 1/255 steps, over every pair of "
          "configurations that rendered.\n";

    if (!counts.passed() || counts.refused > 0) {
        md += "\n## Refused, failed and diverged files\n";
        for (size_t i = 0; i < report.files.size(); ++i) {
            const FileResult& file = report.files[i];
            if (file.status == FileStatus::Rendered) continue;
            md += fmt::format("\n### {}. `{}`: {}\n\n", i + 1, file.path.generic_string(), toString(file.status));
            if (!file.reason.empty()) md += fmt::format("{}\n", file.reason);
            for (size_t c = 0; c < kConfigurations.size(); ++c)
                if (file.configs[c].status == ConfigStatus::Failed)
                    md += fmt::format("- {}: {}\n", configurationLabel(kConfigurations[c].backend, kConfigurations[c].path),
                                      file.configs[c].error);
            if (file.status == FileStatus::Diverged) {
                md += fmt::format("| pair | max diff | PSNR dB | pixels > {} step(s) | heat map |\n|---|---|---|---|---|\n", report.tolerance);
                for (const PairOutcome& pair : file.pairs)
                    if (!pair.passed)
                        md += fmt::format("| {} vs {} | {} | {} | {} / {} | {} |\n", pair.a, pair.b, pair.difference.maxChannelDifference,
                                          psnrText(pair.difference.psnr), pair.difference.differingPixels, pair.difference.totalPixels,
                                          pair.heatmap);
            }
        }
    }

    const bool anyWarnings =
        std::any_of(report.files.begin(), report.files.end(), [](const FileResult& file) { return !file.warnings.empty(); });
    if (anyWarnings) {
        md += "\n## Loader warnings\n\nWhat the loader ignored (the file loads and renders without it; docs/SCENES.md, \"glTF coverage\").\n";
        for (size_t i = 0; i < report.files.size(); ++i) {
            const FileResult& file = report.files[i];
            if (file.warnings.empty()) continue;
            md += fmt::format("\n### {}. `{}`\n\n", i + 1, file.path.generic_string());
            for (const std::string& warning : file.warnings) md += fmt::format("- {}\n", warning);
        }
    }

    const SheetLayout& l = report.layout;
    md += fmt::format(
        "\n## Contact sheets\n\n"
        "One per available configuration, `contact-<backend>-<path>.png`, {}x{} pixels: {} column(s) x {} row(s) of {}x{} thumbnails, "
        "each in a {}-pixel frame, in the order of the table above, row by row: file #k at row ceil(k / {}), column "
        "((k - 1) mod {}) + 1. Frame: grey = rendered (or refused), orange = diverged, red = failed. Tile: that configuration's "
        "render; grey with a dark cross = refused by the loader; dark red with a light cross = that configuration failed. "
        "Thumbnails are also in `thumbnails/`.\n",
        l.width(), l.height(), l.columns, l.rows, l.tileWidth, l.tileHeight, kSheetBorder, l.columns, l.columns);

    std::set<std::string> seen;
    for (const FileResult& file : report.files) seen.insert(file.usage.features.begin(), file.usage.features.end());
    if (!seen.empty()) {
        md += "\n## Features\n\n| feature | files | meaning |\n|---|---|---|\n";
        for (const GltfFeature& feature : gltfFeatures()) {
            if (!seen.count(std::string(feature.name))) continue;
            size_t files = 0;
            for (const FileResult& file : report.files)
                files += size_t(std::count(file.usage.features.begin(), file.usage.features.end(), feature.name));
            md += fmt::format("| {} | {} | {} |\n", feature.name, files, feature.description);
        }
    }
    return md;
}

nlohmann::json reportJson(const Report& report) {
    nlohmann::json configs = nlohmann::json::array();
    for (size_t c = 0; c < report.availability.size(); ++c) {
        const ConfigurationAvailability& a = report.availability[c];
        nlohmann::json entry{{"configuration", configurationLabel(a.config.backend, a.config.path)},
                             {"backend", rhi::toString(a.config.backend)},
                             {"path", renderer::toString(a.config.path)},
                             {"available", a.available}};
        if (a.available) {
            entry["device"] = a.device;
            entry["contactSheet"] = report.sheets[c];
        } else {
            entry["reason"] = a.reason;
        }
        configs.push_back(std::move(entry));
    }
    nlohmann::json features = nlohmann::json::array();
    for (const GltfFeature& feature : gltfFeatures()) features.push_back({{"name", feature.name}, {"description", feature.description}});
    nlohmann::json files = nlohmann::json::array();
    for (size_t i = 0; i < report.files.size(); ++i) files.push_back(fileJson(report.files[i], i));
    const SheetLayout& l = report.layout;
    const Counts& counts = report.counts;
    return {{"paths", report.paths},
            {"width", report.size.width},
            {"height", report.size.height},
            {"tolerance", report.tolerance},
            {"edgePixels", report.edgePixels},
            {"compilerRounding", report.compilerRounding ? "auto" : "off"},
            {"glPlatform", report.glPlatform},
            {"passed", counts.passed()},
            {"exitCode", counts.passed() ? 0 : int(ExitCode::ComparisonFailed)},
            {"counts",
             {{"files", report.files.size()},
              {"rendered", counts.rendered},
              {"diverged", counts.diverged},
              {"failed", counts.failed},
              {"refused", counts.refused}}},
            {"configurations", std::move(configs)},
            {"contactSheet",
             {{"columns", l.columns},
              {"rows", l.rows},
              {"tileWidth", l.tileWidth},
              {"tileHeight", l.tileHeight},
              {"border", kSheetBorder},
              {"width", l.width()},
              {"height", l.height()}}},
            {"featureTable", std::move(features)},
            {"files", std::move(files)}};
}

// ---- the command ----------------------------------------------------------------------------

// A file name part made of [A-Za-z0-9._-] only.
std::string safeStem(const std::filesystem::path& path) {
    std::string stem = path.stem().string();
    for (char& c : stem)
        if (!(std::isalnum(static_cast<unsigned char>(c)) || c == '.' || c == '_' || c == '-')) c = '_';
    return stem.empty() ? "file" : stem;
}

// What the thumbnails of files[index] start with: its 1-based number (so names sort in the order
// checked and two files of one name stay apart) and its stem.
std::string thumbnailPrefix(size_t index, size_t indexDigits, const std::filesystem::path& path) {
    return fmt::format("{:0{}}-{}", index + 1, indexDigits, safeStem(path));
}

// The loader's message without the "<path>: " it starts with (the report names the file already).
std::string loaderReason(std::string_view message, const std::filesystem::path& path) {
    const std::string prefix = path.string() + ": ";
    if (message.size() > prefix.size() && message.substr(0, prefix.size()) == prefix) message.remove_prefix(prefix.size());
    return std::string(message);
}

// Renders `file` on every available configuration and paints its cells in the contact sheets.
FileResult checkFile(const std::filesystem::path& path, size_t index, size_t indexDigits, const Report& report,
                     const RenderRequest& base, const CheckOptions& options, const EnvironmentOverride& environment,
                     const std::filesystem::path& outDir, std::vector<renderer::ImageRGBA8>& sheets) {
    FileResult result;
    result.path = path;
    result.usage = scanGltfFile(path);
    result.configs.resize(kConfigurations.size());

    std::optional<renderer::Scene> scene;
    try {
        renderer::SceneLoadOptions loadOptions;
        loadOptions.allowPathsOutsideSceneFolder = options.allowOutsidePaths;
        scene = renderer::loadScene(path, loadOptions);
        result.warnings = scene->warnings;
        applyEnvironmentOverride(*scene, environment);
        if (environment.map) {   // read once, before the first file (run)
            scene->environment.image = environment.image;
            scene->environment.map.clear();
        }
    } catch (const renderer::SceneError& e) {
        result.status = FileStatus::Refused;
        result.reason = loaderReason(e.what(), path);
    } catch (const renderer::ImageIOError& e) {
        result.status = FileStatus::Refused;
        result.reason = loaderReason(e.what(), path);
    } catch (const std::bad_alloc&) {
        result.status = FileStatus::Failed;
        result.reason = "out of host memory while loading";
    } catch (const std::exception& e) {
        // The loader should refuse with a SceneError; anything else is a bug worth reporting.
        result.status = FileStatus::Failed;
        result.reason = fmt::format("internal error while loading: {} (please report this)", e.what());
    }

    const std::string prefix = thumbnailPrefix(index, indexDigits, path);
    std::vector<std::optional<renderer::ImageRGBA8>> images(kConfigurations.size());
    std::vector<std::optional<rhi::DeviceInfo>> devices(kConfigurations.size());
    for (size_t c = 0; c < kConfigurations.size(); ++c) {
        ConfigOutcome& outcome = result.configs[c];
        if (!report.availability[c].available) {
            outcome.status = ConfigStatus::Unavailable;
            continue;
        }
        if (!scene) continue;   // refused (or failed to load): not run
        try {
            ConfigurationResult run = runConfiguration(*scene, kConfigurations[c], base);
            if (run.ran()) {
                outcome.status = ConfigStatus::Rendered;
                outcome.image = fmt::format("thumbnails/{}-{}.png", prefix, run.stem);
                renderer::writePNG(outDir / outcome.image, run.outcome->display);
                images[c] = std::move(run.outcome->display);
                devices[c] = run.outcome->device;
            } else {
                outcome.status = ConfigStatus::Failed;
                outcome.error = run.failure;
            }
        } catch (const renderer::SceneError& e) {
            // Loaded, but this configuration cannot take it (e.g. a texture it cannot fit).
            outcome.status = ConfigStatus::Failed;
            outcome.error = fmt::format("scene: {}", e.what());
        }
    }

    if (scene) {
        std::vector<const renderer::ImageRGBA8*> pointers;
        for (const auto& image : images) pointers.push_back(image ? &*image : nullptr);
        std::vector<const rhi::DeviceInfo*> devicePointers;
        for (const auto& device : devices) devicePointers.push_back(device && report.compilerRounding ? &*device : nullptr);
        for (const PairComparison& comparison :
             compareAllPairs(pointers, renderer::ParityRule{report.tolerance, report.edgePixels}, devicePointers)) {
            if (!comparison.difference) continue;
            const Configuration& a = kConfigurations[comparison.a];
            const Configuration& b = kConfigurations[comparison.b];
            PairOutcome pair{configurationFileStem(a.backend, a.path), configurationFileStem(b.backend, b.path), *comparison.difference,
                             comparison.passed};
            if (!pair.passed) {
                pair.heatmap = fmt::format("thumbnails/{}-diff-{}-vs-{}.png", prefix, pair.a, pair.b);
                renderer::writePNG(outDir / pair.heatmap,
                                   renderer::differenceHeatmap(*images[comparison.a], *images[comparison.b], kHeatmapFullScaleSteps));
            }
            result.pairs.push_back(std::move(pair));
        }
        const bool anyFailed = std::any_of(result.configs.begin(), result.configs.end(),
                                           [](const ConfigOutcome& o) { return o.status == ConfigStatus::Failed; });
        const bool anyDiverged = std::any_of(result.pairs.begin(), result.pairs.end(), [](const PairOutcome& p) { return !p.passed; });
        result.status = anyFailed ? FileStatus::Failed : anyDiverged ? FileStatus::Diverged : FileStatus::Rendered;
    }

    const Rgb frame = result.status == FileStatus::Failed     ? kFrameFailed
                      : result.status == FileStatus::Diverged ? kFrameDiverged
                                                              : kFrameOk;
    for (size_t c = 0; c < kConfigurations.size(); ++c) {
        if (sheets[c].pixels.empty()) continue;
        const bool refused = result.status == FileStatus::Refused;
        paintCell(sheets[c], report.layout, index, frame, images[c] ? &*images[c] : nullptr, refused ? kRefusedTile : kFailedTile,
                  refused ? kRefusedCross : kFailedCross);
    }
    return result;
}

// Every file a check writes in --out: the reports, a contact sheet per configuration, and per
// glTF file a thumbnail per configuration and a difference heatmap per pair.
std::vector<std::string> checkOutputNames(const std::vector<std::filesystem::path>& files, size_t indexDigits) {
    std::vector<std::string> names{"check.md", "check.json"};
    std::vector<std::string> stems;
    for (const Configuration& config : kConfigurations) stems.push_back(configurationFileStem(config.backend, config.path));
    for (const std::string& stem : stems) names.push_back(fmt::format("contact-{}.png", stem));
    for (size_t i = 0; i < files.size(); ++i) {
        const std::string prefix = thumbnailPrefix(i, indexDigits, files[i]);
        for (size_t a = 0; a < stems.size(); ++a) {
            names.push_back(fmt::format("thumbnails/{}-{}.png", prefix, stems[a]));
            for (size_t b = a + 1; b < stems.size(); ++b) names.push_back(fmt::format("thumbnails/{}-diff-{}-vs-{}.png", prefix, stems[a], stems[b]));
        }
    }
    return names;
}

// The console line for a finished file.
std::string progressLine(const FileResult& file, size_t index, size_t total) {
    const int width = int(std::to_string(total).size());
    std::string line = fmt::format("[{:>{}}/{}] {:<8}  {}", index + 1, width, total, toString(file.status), file.path.string());
    if (file.status == FileStatus::Refused || !file.reason.empty()) return line + ": " + file.reason;
    for (size_t c = 0; c < kConfigurations.size(); ++c)
        if (file.configs[c].status == ConfigStatus::Failed)
            line += fmt::format("; {} failed: {}", configurationLabel(kConfigurations[c].backend, kConfigurations[c].path),
                                file.configs[c].error);
    if (const std::optional<uint32_t> max = file.maxDifference()) line += fmt::format("; max diff {}", *max);
    for (const PairOutcome& pair : file.pairs)
        if (!pair.passed) line += fmt::format(" ({} vs {}: {})", pair.a, pair.b, pair.difference.maxChannelDifference);
    return line + fmt::format(" ({:.1f} s)", file.seconds);
}

int run(const CheckOptions& options) {
    // Options first, then the paths, then the devices: a typo fails at once and leaves nothing behind.
    RenderRequest base;
    base.size = parseSize(options.size);
    base.glPlatform = parseGLPlatformOption(options.glPlatform);
    base.validation = options.validation;
    const uint32_t tolerance = parseTolerance(options.tolerance);
    const uint64_t edgePixels = parseEdgePixels(options.edgePixels);
    const bool compilerRounding = parseCompilerRounding(options.compilerRounding);
    if (options.paths.empty())
        throw UsageError("give at least one PATH: a .gltf / .glb file or a folder to search, e.g. 'janus check assets --out report'");
    if (options.out.empty()) throw UsageError("--out DIR is required: where to write check.md, check.json and the contact sheets");
    const std::filesystem::path outDir = options.out;
    std::error_code ec;
    if (std::filesystem::exists(outDir, ec) && !std::filesystem::is_directory(outDir, ec))
        throw InputError(fmt::format("--out '{}' is a file; give a directory for the report", options.out));
    EnvironmentOverride environment = parseEnvironmentOptions(options.environment);

    const std::vector<std::filesystem::path> files = findGltfFiles(options.paths);
    if (environment.map) {
        // The sky every file is lit by, read once and now: one that cannot be read is exit 3.
        renderer::Scene sky;
        sky.environment.map = *environment.map;
        loadEnvironmentImage(sky, true, "");
        environment.image = sky.environment.image;
    }

    Report report;
    report.paths = options.paths;
    report.size = base.size;
    report.tolerance = tolerance;
    report.edgePixels = edgePixels;
    report.compilerRounding = compilerRounding;
    report.glPlatform = options.glPlatform;
    report.availability = probeConfigurations(base.glPlatform, base.size);
    if (std::none_of(report.availability.begin(), report.availability.end(), [](const auto& a) { return a.available; })) {
        std::string reasons;
        for (const ConfigurationAvailability& a : report.availability)
            reasons += fmt::format("{}{}: {}", reasons.empty() ? "" : "; ", configurationLabel(a.config.backend, a.config.path), a.reason);
        throw UnavailableError(fmt::format("no configuration can render on this machine ({}); run 'janus info'", reasons));
    }

    const size_t indexDigits = std::max<size_t>(3, std::to_string(files.size()).size());
    std::vector<NamedPath> inputs;
    for (const std::filesystem::path& file : files) {
        inputs.emplace_back("a file being checked", file);
        for (const std::filesystem::path& read : gltfReferencedFiles(file)) inputs.emplace_back(fmt::format("a file '{}' reads", file.string()), read);
    }
    if (environment.map) inputs.emplace_back("the --env file", *environment.map);
    checkFolderOutputs(outDir, "--out", checkOutputNames(files, indexDigits), inputs);

    std::filesystem::create_directories(outDir / "thumbnails", ec);
    if (ec)
        throw InputError(fmt::format("cannot create --out directory '{}': {}; choose another path", options.out, ec.message()));
    checkOutputFile(outDir / "check.json", "--out");

    report.layout = sheetLayout(files.size(), base.size);
    std::vector<renderer::ImageRGBA8> sheets(kConfigurations.size());
    report.sheets.resize(kConfigurations.size());
    std::string unavailable;
    for (size_t c = 0; c < kConfigurations.size(); ++c) {
        const Configuration& config = kConfigurations[c];
        if (report.availability[c].available) {
            sheets[c] = emptySheet(report.layout);
            report.sheets[c] = fmt::format("contact-{}.png", configurationFileStem(config.backend, config.path));
        } else {
            unavailable += fmt::format("\n  {} unavailable, not checked: {}", configurationLabel(config.backend, config.path),
                                       report.availability[c].reason);
        }
    }

    std::printf("check: %zu glTF file(s) at %ux%u, tolerance %u step(s)%s\n\n", files.size(), base.size.width, base.size.height,
                tolerance, unavailable.c_str());
    std::fflush(stdout);

    const auto started = std::chrono::steady_clock::now();
    for (size_t i = 0; i < files.size(); ++i) {
        const auto fileStarted = std::chrono::steady_clock::now();
        FileResult result = checkFile(files[i], i, indexDigits, report, base, options, environment, outDir, sheets);
        result.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - fileStarted).count();
        std::printf("%s\n", progressLine(result, i, files.size()).c_str());
        std::fflush(stdout);
        report.counts.add(result.status);
        report.files.push_back(std::move(result));
    }
    const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - started).count();

    for (size_t c = 0; c < kConfigurations.size(); ++c)
        if (!report.sheets[c].empty()) renderer::writePNG(outDir / report.sheets[c], sheets[c]);
    renderer::writeFileAtomically(outDir / "check.md", markdown(report));
    renderer::writeFileAtomically(outDir / "check.json", jsonFileText(reportJson(report)));

    const bool passed = report.counts.passed();
    std::printf("\ncheck %s: %s in %.1f s\nreport: %s, check.json, contact-*.png\n", passed ? "PASSED" : "FAILED",
                countsText(report).c_str(), seconds, (outDir / "check.md").c_str());
    return passed ? 0 : static_cast<int>(ExitCode::ComparisonFailed);
}

}  // namespace

Command addCheckCommand(CLI::App& parent) {
    auto options = std::make_shared<CheckOptions>();
    CLI::App* app = parent.add_subcommand(
        "check",
        "Render every .gltf/.glb under PATH... on every available configuration at a small size; report rendered / refused / "
        "failed, the glTF features and extensions each file uses, and parity per file (check.md, check.json, contact sheets)");
    app->footer(std::string("A configuration this machine cannot run (backend missing, no compute) is reported as unavailable and "
                            "skipped; it does not fail the check. A file the loader refuses is reported with the reason and "
                            "does not fail the check either.\n\n"
                            "Exit codes:\n"
                            "  0  every file rendered on every available configuration and agreed within --tolerance (or was refused)\n"
                            "  1  a file failed on some configuration, or two configurations diverged beyond --tolerance\n"
                            "  2  usage error (no PATH, no --out, bad --size or --tolerance, unknown option)\n"
                            "  3  input/output error (a PATH missing, not a glTF, a folder without any; --out a file or unwritable)\n"
                            "  4  no configuration can run on this machine\n"
                            "  5  internal error (a bug; please report it)\n"));
    app->add_option("PATH", options->paths, ".gltf / .glb files, or folders searched recursively (sorted); at least one")->type_name("");
    app->add_option("--out,-o", options->out,
                    "Directory for check.md, check.json, contact-<backend>-<path>.png and thumbnails/ (created if missing); required")
        ->type_name("DIR");
    app->add_option("--size,-s", options->size, "Thumbnail size WIDTHxHEIGHT, each configuration renders at it")
        ->default_str("64x64")
        ->type_name("WxH");
    app->add_option("--tolerance,-t", options->tolerance,
                    "Largest allowed channel difference, in steps of 1/255, for two configurations to agree")
        ->default_str("1")
        ->type_name("STEPS");
    addEdgePixelsOption(*app, options->edgePixels);
    addCompilerRoundingOption(*app, options->compilerRounding);
    addGLPlatformOption(*app, options->glPlatform);
    addEnvironmentOptions(*app, options->environment);
    addAllowOutsidePathsFlag(*app, options->allowOutsidePaths);
    app->add_flag("--validation", options->validation,
                  "Enable Vulkan validation layers / GL debug output; a configuration with errors fails for that file");
    return {app, [options] { return run(*options); }};
}

}  // namespace janus::cli
