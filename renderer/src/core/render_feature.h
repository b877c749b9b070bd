// What every feature module is to the renderer's core (internal to the renderer): something that
// adds its passes for a view to a frame's pass graph. The core makes the features in order and
// calls addPasses for every view it renders; features find their inputs and publish their
// outputs on the graph's blackboard under the names below, so adding a feature adds a folder
// and one line where the features are made, and nothing else in the core.
#pragma once

#include <vector>

#include "core/pass_graph.h"
#include "janus/renderer/scene_view.h"

namespace janus::renderer {

// Blackboard names (PassGraph::publish / find).
namespace frame_resources {
inline constexpr const char* kHdr = "hdr";                // per view: RGBA16F radiance the scene is shaded into
inline constexpr const char* kDepth = "depth";            // per view: D32F depth
// Per view with SceneView::sampleCount > 1: the single-sampled RGBA16F "hdr" resolves into, which
// the resolve then publishes as "hdr" for what comes after it (tonemap, readback).
inline constexpr const char* kHdrResolved = "hdr-resolved";
inline constexpr const char* kDisplay = "display";        // per view, optional: the RGBA8 image people look at
inline constexpr const char* kShadowMap = "shadow-map";   // frame-wide: the main directional light's map
inline constexpr const char* kTileLists = "tile-lists";   // per view: Forward+ light lists
}  // namespace frame_resources

class RenderFeature {
public:
    virtual ~RenderFeature() = default;
    // Adds this feature's passes for `view`, or nothing when the view does not call for it.
    // Called for each view in the order views are rendered, features in the order they were made.
    virtual void addPasses(PassGraph& graph, const SceneView& view) = 0;
    // Work the feature did once while the renderer was made (e.g. filtering a static sky), for
    // the first frame's report; returned once, then empty.
    virtual std::vector<PassReport> takeStartupReports() { return {}; }
    // Work of this frame that runs before the frame's graph, on its own submissions (e.g. a time
    // slice of reflection-probe updates): it appends its passes and its report to `frame`.
    virtual void beginFrame(FrameReport& frame) { (void)frame; }
};

}  // namespace janus::renderer
