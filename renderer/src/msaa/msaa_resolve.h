// Multisample resolve (internal to the renderer): for a view with SceneView::sampleCount > 1, the
// passes before it shade into multisampled "hdr" and "depth"; this feature adds "msaa-resolve",
// which averages each pixel's samples of "hdr" into the single-sampled "hdr-resolved" and
// publishes that as "hdr", so what comes after it (the tonemap, HDR readback) reads one sample a
// pixel as without multisampling. Views of one sample get nothing.
#pragma once

#include <memory>
#include <string>
#include <vector>

#include "core/pass_graph.h"
#include "core/render_feature.h"

namespace janus::renderer {

class MsaaResolve final : public RenderFeature {
public:
    void addPasses(PassGraph& graph, const SceneView& view) override;

private:
    // Per view name: the multisampled target and what it resolves into.
    struct ViewState {
        std::string view;
        ViewTarget samples, resolved;
    };
    std::vector<std::unique_ptr<ViewState>> m_views;   // the graph's passes point at them
};

}  // namespace janus::renderer
