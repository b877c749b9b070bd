#include "janus/renderer/renderer.h"

namespace janus::renderer {

nlohmann::json FrameReport::toJson() const {
    nlohmann::json passesJson = nlohmann::json::array();
    for (const PassReport& p : passes) {
        nlohmann::json j{{"name", p.name}, {"view", p.view}, {"cpuMs", p.cpuMs}, {"draws", p.draws}, {"dispatches", p.dispatches}};
        j["gpuMs"] = p.gpuMs ? nlohmann::json(*p.gpuMs) : nlohmann::json(nullptr);
        passesJson.push_back(std::move(j));
    }
    nlohmann::json viewsJson = nlohmann::json::array();
    for (const ViewReport& v : views) viewsJson.push_back({{"name", v.name}, {"width", v.width}, {"height", v.height}, {"samples", v.sampleCount}});
    nlohmann::json json{{"backend", backend}, {"path", path},        {"width", width},         {"height", height},
                        {"msaaSamples", msaaSamples}, {"alphaToCoverage", alphaToCoverage}, {"views", viewsJson}, {"passes", passesJson}};
    if (lightCulling) {
        const LightCullingReport& c = *lightCulling;
        json["lightCulling"] = {{"mode", toString(c.mode)},
                                {"builder", c.builder},
                                {"directionalLights", c.directionalLights},
                                {"localLights", c.localLights},
                                {"tileSize", c.tileSize},
                                {"tilesX", c.tilesX},
                                {"tilesY", c.tilesY},
                                {"maxLightsPerTile", c.maxLightsPerTile},
                                {"maxLightsPerTileAuto", c.maxLightsPerTileAuto},
                                {"listedLights", c.listedLights},
                                {"overflowTiles", c.overflowTiles},
                                {"droppedLights", c.droppedLights}, {"densestTileLights", c.densestTileLights}};
    }
    if (!probeUpdates.empty()) {
        nlohmann::json probes = nlohmann::json::array();
        for (const ProbeUpdateReport& u : probeUpdates)
            probes.push_back({{"probe", u.probe},
                              {"update", u.update},
                              {"step", u.step},
                              {"steps", u.steps},
                              {"shown", u.shown},
                              {"draws", u.draws},
                              {"dispatches", u.dispatches},
                              {"gpuMs", u.gpuMs ? nlohmann::json(*u.gpuMs) : nlohmann::json(nullptr)},
                              {"updateDraws", u.updateDraws},
                              {"updateDispatches", u.updateDispatches},
                              {"prefilterDraws", u.prefilterDraws},
                              {"prefilterDispatches", u.prefilterDispatches},
                              {"copies", u.copies},
                              {"msaaSamples", u.msaaSamples}});
        json["probeUpdates"] = std::move(probes);
    }
    json["performanceMessages"] = performanceMessages;
    return json;
}

}  // namespace janus::renderer
