#include "core/pass_graph.h"

#include <algorithm>
#include <chrono>
#include <optional>

#include <fmt/format.h>

#include "core/gpu_util.h"
#include "janus/renderer/settings.h"

namespace janus::renderer {

PassGraph::ResourceId PassGraph::addResource(std::string name, std::function<void()> create) {
    if (m_compiled) throw RendererError(fmt::format("pass graph: resource '{}' added after compile()", name));
    m_resources.push_back(Resource{std::move(name), std::move(create)});
    return ResourceId(m_resources.size() - 1);
}

PassGraph::ResourceId PassGraph::importResource(std::string name) {
    const ResourceId id = addResource(std::move(name));
    m_resources[id].imported = true;
    return id;
}

void PassGraph::addPass(PassDesc pass) {
    if (m_compiled) throw RendererError(fmt::format("pass graph: pass '{}' added after compile()", pass.name));
    for (ResourceId id : pass.reads)
        if (id >= m_resources.size()) throw RendererError(fmt::format("pass graph: pass '{}' reads an unknown resource", pass.name));
    for (ResourceId id : pass.writes)
        if (id >= m_resources.size()) throw RendererError(fmt::format("pass graph: pass '{}' writes an unknown resource", pass.name));
    if (bool(pass.record) == bool(pass.run))
        throw RendererError(fmt::format("pass graph: pass '{}' must have either a record (GPU) or a run (CPU) function", pass.name));
    m_passes.push_back(Pass{std::move(pass)});
}

void PassGraph::markOutput(ResourceId resource) { m_resources.at(resource).output = true; }

void PassGraph::compile(rhi::IDevice& device) {
    if (m_compiled) return;
    // Every read needs an earlier writer (or an import): the order passes were added is the
    // order they run in, so a later writer would be read before it wrote.
    std::vector<bool> written(m_resources.size(), false);
    for (const Pass& pass : m_passes) {
        for (ResourceId id : pass.desc.reads)
            if (!written[id] && !m_resources[id].imported)
                throw RendererError(fmt::format("pass graph: pass '{}' reads '{}', which no earlier pass writes", pass.desc.name,
                                                m_resources[id].name));
        for (ResourceId id : pass.desc.writes) written[id] = true;
    }

    // Walk back from the outputs: a pass is kept when something kept (or the frame) needs what
    // it writes; what it reads is then needed too.
    std::vector<bool> needed(m_resources.size(), false);
    for (size_t r = 0; r < m_resources.size(); ++r) needed[r] = m_resources[r].output;
    for (auto it = m_passes.rbegin(); it != m_passes.rend(); ++it) {
        Pass& pass = *it;
        pass.kept = pass.desc.sideEffect ||
                    std::any_of(pass.desc.writes.begin(), pass.desc.writes.end(), [&](ResourceId id) { return bool(needed[id]); });
        if (!pass.kept) continue;
        for (ResourceId id : pass.desc.reads) needed[id] = true;
    }

    for (const Pass& pass : m_passes) {
        if (!pass.kept) continue;
        for (ResourceId id : pass.desc.reads) m_resources[id].used = true;
        for (ResourceId id : pass.desc.writes) m_resources[id].used = true;
    }
    for (Resource& resource : m_resources)
        if (resource.used && resource.create) resource.create();
    const bool timers = device.capabilities().timestampQueries;
    for (Pass& pass : m_passes) {
        if (!pass.kept) continue;
        if (pass.desc.setup) pass.desc.setup();
        if (timers && pass.desc.record) pass.timer = device.createTimerQuery();
    }
    m_compiled = true;
}

std::vector<PassReport> PassGraph::execute(rhi::IDevice& device, const rhi::CommandListHandle& commandList) {
    if (!m_compiled) throw RendererError("pass graph: execute() before compile()");
    std::vector<PassReport> reports;
    std::vector<const Pass*> timed;
    rhi::ICommandList& cmd = *commandList;
    bool recording = false;
    auto submit = [&] {
        if (!recording) return;
        cmd.end();
        device.execute(commandList);
        recording = false;
    };
    for (const Pass& pass : m_passes) {
        if (!pass.kept || (pass.desc.skip && pass.desc.skip())) continue;
        PassReport report;
        report.name = pass.desc.name;
        report.view = pass.desc.view;
        if (pass.desc.run) {
            submit();
            pass.desc.run(report);
        } else {
            if (!recording) {
                cmd.begin();
                recording = true;
            }
            const auto start = std::chrono::steady_clock::now();
            if (pass.timer) cmd.beginTimer(pass.timer);
            cmd.pushDebugGroup(pass.desc.view.empty() ? pass.desc.name : pass.desc.view + ": " + pass.desc.name);
            pass.desc.record(cmd, report);
            cmd.popDebugGroup();
            if (pass.timer) cmd.endTimer(pass.timer);
            report.cpuMs = millisecondsSince(start);
        }
        reports.push_back(std::move(report));
        timed.push_back(&pass);
    }
    submit();
    for (size_t i = 0; i < timed.size(); ++i) {
        if (!timed[i]->timer) continue;
        if (std::optional<double> seconds = device.timerSeconds(timed[i]->timer)) reports[i].gpuMs = *seconds * 1000.0;
    }
    return reports;
}

std::vector<std::string> PassGraph::keptPasses() const {
    std::vector<std::string> names;
    for (const Pass& pass : m_passes)
        if (pass.kept) names.push_back(pass.desc.name);
    return names;
}

std::vector<std::string> PassGraph::culledPasses() const {
    std::vector<std::string> names;
    for (const Pass& pass : m_passes)
        if (!pass.kept) names.push_back(pass.desc.name);
    return names;
}

bool PassGraph::isKept(const std::string& passName) const {
    return std::any_of(m_passes.begin(), m_passes.end(), [&](const Pass& p) { return p.kept && p.desc.name == passName; });
}

void PassGraph::publish(const std::string& view, const std::string& name, const ViewTarget& target) {
    if (target.resource >= m_resources.size())
        throw RendererError(fmt::format("pass graph: '{}' published for view '{}' names an unknown resource", name, view));
    m_blackboard[{view, name}] = target;
}

const ViewTarget* PassGraph::find(const std::string& view, const std::string& name) const {
    auto it = m_blackboard.find({view, name});
    if (it == m_blackboard.end()) it = m_blackboard.find({std::string(), name});
    return it == m_blackboard.end() ? nullptr : &it->second;
}

bool PassGraph::isUsed(ResourceId resource) const { return m_resources.at(resource).used; }

}  // namespace janus::renderer
