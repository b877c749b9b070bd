// The frame's pass graph (internal to the renderer; docs/ARCHITECTURE.md, "Pass graph").
//
// Feature modules add passes; each pass declares the resources it reads and writes. Resources
// are names for whatever flows between passes: a texture, a buffer, or data a CPU step makes.
// The frame marks what it must produce (e.g. the display image); compile() then keeps exactly
// the passes that contribute to those outputs, walking back from them, and drops the rest.
// Only then are resources and pass state created, and only for what was kept: a pass nobody
// reads from costs neither time nor memory. This is Filament's FrameGraph idea kept small:
// passes run in the order they were added (features add them in dependency order, and
// compile() checks that every read has an earlier writer), there is no aliasing of transient
// memory, and the graph is compiled once per renderer rather than once per frame.
//
// A GPU pass records into the frame's command list, wrapped in a debug group, a CPU stopwatch
// and (with Capability::TimestampQueries) a GPU timer. A CPU pass runs between submissions:
// everything recorded before it is executed first, and the passes after it go into a new
// submission.
#pragma once

#include <cstdint>
#include <functional>
#include <map>
#include <utility>
#include <string>
#include <vector>

#include "janus/renderer/frame_report.h"
#include "janus/rhi/rhi.h"

namespace janus::renderer {

// A render target of a view: the graph resource and the texture subresource passes write.
struct ViewTarget {
    uint32_t resource = 0;   // PassGraph::ResourceId
    rhi::TextureHandle texture;
    rhi::TextureSubresource subresource;
};

class PassGraph {
public:
    using ResourceId = uint32_t;

    // A resource the passes exchange. `create` (optional) makes its GPU object; compile() calls
    // it once, before any pass setup, and only when a kept pass reads or writes the resource.
    // Imported resources exist outside the graph (the frame's targets): they need no writer
    // before they are read.
    ResourceId addResource(std::string name, std::function<void()> create = {});
    ResourceId importResource(std::string name);

    struct PassDesc {
        std::string name;
        std::string view;                      // the SceneView it works for ("" = none)
        std::vector<ResourceId> reads;
        std::vector<ResourceId> writes;
        // Runs once at compile() for a kept pass, after its resources exist: pipelines, binding
        // sets. A culled pass never runs it.
        std::function<void()> setup;
        // Exactly one of these: a GPU pass records, a CPU pass runs between submissions.
        std::function<void(rhi::ICommandList&, PassReport&)> record;
        std::function<void(PassReport&)> run;
        // Kept even when nothing reads what it writes (e.g. a readback for the report).
        bool sideEffect = false;
        // Asked at every execute() (optional): true leaves the pass out of that execution (nothing
        // recorded, no report), for work whose result is still valid from an earlier one, as a
        // static scene's shadow map. Its readers read what the resource holds.
        std::function<bool()> skip;
    };
    void addPass(PassDesc pass);

    // The frame must produce this resource: the passes that (transitively) write it are kept.
    void markOutput(ResourceId resource);

    // Culls, checks and creates. Throws RendererError for a pass that reads a resource no
    // earlier pass writes (and that is not imported), or that has both or neither of record/run.
    void compile(rhi::IDevice& device);

    // Runs the kept passes in order on `commandList`, submitting as described above, and
    // returns one report per kept pass. Call only after compile().
    std::vector<PassReport> execute(rhi::IDevice& device, const rhi::CommandListHandle& commandList);

    // The blackboard (Filament's): named targets features publish for each other. A name belongs
    // to a view ("hdr" of "cube +X") or, with view "", to the whole frame ("shadow-map"); find()
    // looks in the view first, then frame-wide. Names: core/frame_resources.h.
    void publish(const std::string& view, const std::string& name, const ViewTarget& target);
    const ViewTarget* find(const std::string& view, const std::string& name) const;

    bool compiled() const { return m_compiled; }
    // Names of the passes compile() kept / culled, in the order they were added.
    std::vector<std::string> keptPasses() const;
    std::vector<std::string> culledPasses() const;
    bool isKept(const std::string& passName) const;
    // Whether a kept pass uses the resource (so compile() created it).
    bool isUsed(ResourceId resource) const;
    const std::string& resourceName(ResourceId resource) const { return m_resources.at(resource).name; }

private:
    struct Resource {
        std::string name;
        std::function<void()> create;
        bool imported = false;
        bool output = false;
        bool used = false;
    };
    struct Pass {
        PassDesc desc;
        bool kept = false;
        rhi::TimerQueryHandle timer;
    };

    std::vector<Resource> m_resources;
    std::vector<Pass> m_passes;
    std::map<std::pair<std::string, std::string>, ViewTarget> m_blackboard;
    bool m_compiled = false;
};


}  // namespace janus::renderer
