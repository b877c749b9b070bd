#include "msaa/msaa_resolve.h"

#include <algorithm>

#include <fmt/format.h>

namespace janus::renderer {


void MsaaResolve::addPasses(PassGraph& graph, const SceneView& view) {
    if (view.sampleCount <= 1) return;
    const ViewTarget* samples = graph.find(view.name, frame_resources::kHdr);
    const ViewTarget* resolved = graph.find(view.name, frame_resources::kHdrResolved);
    if (!samples || !resolved)
        throw RendererError(fmt::format("msaa resolve: view '{}' has {} samples but no '{}' and '{}' targets", view.name,
                                        view.sampleCount, frame_resources::kHdr, frame_resources::kHdrResolved));
    auto it = std::find_if(m_views.begin(), m_views.end(), [&](const auto& s) { return s->view == view.name; });
    if (it == m_views.end()) it = m_views.insert(m_views.end(), std::make_unique<ViewState>(ViewState{view.name, {}, {}}));
    ViewState* state = it->get();
    state->samples = *samples;
    state->resolved = *resolved;

    PassGraph::PassDesc pass;
    pass.name = "msaa-resolve";
    pass.view = view.name;
    pass.reads = {samples->resource};
    pass.writes = {resolved->resource};
    // A pass without draws: it loads the samples and resolves them at its end. The samples need
    // not be stored again (nothing reads them after the resolve).
    pass.record = [state](rhi::ICommandList& cmd, PassReport&) {
        rhi::Attachment attachment = rhi::Attachment::load(state->samples.texture, state->samples.subresource);
        attachment.storeOp = rhi::StoreOp::DontCare;
        attachment.resolveTo(state->resolved.texture, state->resolved.subresource);
        cmd.beginRenderPass(rhi::RenderPassDesc{}.addColor(attachment));
        cmd.endRenderPass();
    };
    graph.addPass(std::move(pass));
    graph.publish(view.name, frame_resources::kHdr, *resolved);
}

}  // namespace janus::renderer
