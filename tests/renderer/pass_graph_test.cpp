// The pass graph (renderer/src/core/pass_graph.h): passes whose outputs nobody reads are culled
// and their resources never created; the kept ones run in order, CPU steps between submissions.
// And the renderer's frame report lists its views.
#include <gtest/gtest.h>

#include <string>
#include <vector>

#include "core/pass_graph.h"
#include "janus/renderer/renderer.h"
#include "renderer/renderer_test_support.h"

namespace janus::renderer {
namespace {

using Names = std::vector<std::string>;

// A GPU pass that records only its name into `log` (no GPU work).
PassGraph::PassDesc gpuPass(std::string name, std::vector<PassGraph::ResourceId> reads, std::vector<PassGraph::ResourceId> writes,
                            Names& log, Names& setups) {
    PassGraph::PassDesc pass;
    pass.name = name;
    pass.view = "main";
    pass.reads = std::move(reads);
    pass.writes = std::move(writes);
    pass.setup = [&setups, name] { setups.push_back(name); };
    pass.record = [&log, name](rhi::ICommandList&, PassReport& report) {
        log.push_back(name);
        report.draws = 1;
    };
    return pass;
}

rhi::IDevice& device() { return test_support::deviceFor(rhi::Backend::Vulkan); }

TEST(PassGraphTest, DropsAPassWhoseOutputNobodyReadsAndNeverCreatesItsResource) {
    PassGraph graph;
    int createdUsed = 0, createdUnused = 0;
    Names log, setups;
    const auto used = graph.addResource("used", [&] { ++createdUsed; });
    const auto unused = graph.addResource("unused", [&] { ++createdUnused; });
    const auto output = graph.importResource("display");
    graph.addPass(gpuPass("producer", {}, {used}, log, setups));
    graph.addPass(gpuPass("orphan", {}, {unused}, log, setups));
    graph.addPass(gpuPass("consumer", {used}, {output}, log, setups));
    graph.markOutput(output);
    graph.compile(device());

    EXPECT_EQ(graph.keptPasses(), (Names{"producer", "consumer"}));
    EXPECT_EQ(graph.culledPasses(), (Names{"orphan"}));
    EXPECT_EQ(createdUsed, 1);
    EXPECT_EQ(createdUnused, 0) << "a culled pass's resource was created";
    EXPECT_EQ(setups, (Names{"producer", "consumer"})) << "a culled pass was set up";
    EXPECT_FALSE(graph.isUsed(unused));

    const rhi::CommandListHandle cmd = device().createCommandList();
    const std::vector<PassReport> reports = graph.execute(device(), cmd);
    EXPECT_EQ(log, (Names{"producer", "consumer"}));
    ASSERT_EQ(reports.size(), 2u);
    EXPECT_EQ(reports[0].name, "producer");
    EXPECT_EQ(reports[1].name, "consumer");
    EXPECT_EQ(reports[1].view, "main");
    EXPECT_EQ(reports[1].draws, 1u);
}

TEST(PassGraphTest, KeepsEveryPassTheOutputDependsOnThroughACpuStep) {
    PassGraph graph;
    Names log, setups;
    const auto depth = graph.addResource("depth");
    const auto lists = graph.addResource("lists");
    const auto output = graph.importResource("hdr");
    graph.addPass(gpuPass("prepass", {}, {depth}, log, setups));
    PassGraph::PassDesc cpu;
    cpu.name = "cpu-step";
    cpu.reads = {depth};
    cpu.writes = {lists};
    cpu.run = [&log](PassReport& report) {
        log.push_back("cpu-step");
        report.cpuMs = 0.5;
    };
    graph.addPass(std::move(cpu));
    graph.addPass(gpuPass("shade", {lists}, {output}, log, setups));
    graph.markOutput(output);
    graph.compile(device());
    EXPECT_TRUE(graph.culledPasses().empty());
    const std::vector<PassReport> reports = graph.execute(device(), device().createCommandList());
    EXPECT_EQ(log, (Names{"prepass", "cpu-step", "shade"}));
    ASSERT_EQ(reports.size(), 3u);
    EXPECT_EQ(reports[1].cpuMs, 0.5);
}

TEST(PassGraphTest, WithoutOutputsOnlySideEffectPassesRun) {
    PassGraph graph;
    Names log, setups;
    const auto a = graph.addResource("a");
    const auto b = graph.addResource("b");
    graph.addPass(gpuPass("writes-a", {}, {a}, log, setups));
    PassGraph::PassDesc sideEffect = gpuPass("readback", {a}, {b}, log, setups);
    sideEffect.sideEffect = true;
    graph.addPass(std::move(sideEffect));
    graph.compile(device());
    EXPECT_EQ(graph.keptPasses(), (Names{"writes-a", "readback"}));
}

// A pass whose skip() says its result is still valid is left out of that execution: not
// recorded, not reported; its readers run. Asked again at every execution.
TEST(PassGraphTest, ASkippedPassIsNeitherRecordedNorReportedThatTime) {
    PassGraph graph;
    Names log, setups;
    const auto map = graph.addResource("map");
    const auto output = graph.importResource("display");
    bool valid = false;
    PassGraph::PassDesc producer = gpuPass("producer", {}, {map}, log, setups);
    producer.skip = [&valid] { return valid; };
    graph.addPass(std::move(producer));
    graph.addPass(gpuPass("consumer", {map}, {output}, log, setups));
    graph.markOutput(output);
    graph.compile(device());
    EXPECT_EQ(graph.keptPasses(), (Names{"producer", "consumer"}));
    auto executed = [&] {
        log.clear();
        Names reported;
        for (const PassReport& report : graph.execute(device(), device().createCommandList())) reported.push_back(report.name);
        EXPECT_EQ(reported, log);
        return log;
    };
    EXPECT_EQ(executed(), (Names{"producer", "consumer"}));
    valid = true;
    EXPECT_EQ(executed(), (Names{"consumer"}));
    valid = false;
    EXPECT_EQ(executed(), (Names{"producer", "consumer"}));
}

TEST(PassGraphTest, AReadWithoutAnEarlierWriterIsAnError) {
    PassGraph graph;
    Names log, setups;
    const auto late = graph.addResource("late");
    const auto output = graph.importResource("display");
    graph.addPass(gpuPass("reader", {late}, {output}, log, setups));
    graph.addPass(gpuPass("writer", {}, {late}, log, setups));
    graph.markOutput(output);
    try {
        graph.compile(device());
        FAIL() << "compile() accepted a read before any write";
    } catch (const RendererError& e) {
        EXPECT_NE(std::string(e.what()).find("'reader' reads 'late'"), std::string::npos) << e.what();
    }
}

TEST(PassGraphTest, BlackboardFindsTheViewsTargetBeforeTheFramesAndNothingElse) {
    PassGraph graph;
    const auto frameWide = graph.importResource("shadow");
    const auto mainHdr = graph.importResource("main hdr");
    const auto faceHdr = graph.importResource("face hdr");
    graph.publish("", "shadow-map", ViewTarget{frameWide, nullptr, {}});
    graph.publish("main", "hdr", ViewTarget{mainHdr, nullptr, {}});
    graph.publish("cube +X", "hdr", ViewTarget{faceHdr, nullptr, {0, 0}});
    ASSERT_NE(graph.find("main", "hdr"), nullptr);
    EXPECT_EQ(graph.find("main", "hdr")->resource, mainHdr);
    EXPECT_EQ(graph.find("cube +X", "hdr")->resource, faceHdr);
    ASSERT_NE(graph.find("cube +X", "shadow-map"), nullptr);
    EXPECT_EQ(graph.find("cube +X", "shadow-map")->resource, frameWide);
    EXPECT_EQ(graph.find("cube -X", "hdr"), nullptr);
    EXPECT_EQ(graph.find("main", "display"), nullptr);
    EXPECT_THROW(graph.publish("main", "display", ViewTarget{99, nullptr, {}}), RendererError);
}

TEST(PassGraphTest, APassNeedsExactlyOneOfRecordAndRun) {
    PassGraph graph;
    PassGraph::PassDesc pass;
    pass.name = "nothing";
    EXPECT_THROW(graph.addPass(pass), RendererError);
}

}  // namespace
}  // namespace janus::renderer
