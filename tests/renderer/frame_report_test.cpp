// FrameReport::toJson and the FeaturePath names: what `janus render --report` and benchmarks read.
#include <gtest/gtest.h>

#include "janus/renderer/renderer.h"

namespace janus::renderer {
namespace {

TEST(FrameReport, JsonHasEveryFieldAndNullForMissingTimers) {
    FrameReport report;
    report.backend = "gles";
    report.path = "fallback";
    report.width = 128;
    report.height = 64;
    report.passes.push_back(PassReport{"forward", 1.5, 0.25, 18, 0});
    report.passes.push_back(PassReport{"tonemap-fallback", std::nullopt, 0.125, 1, 0});
    const nlohmann::json json = report.toJson();
    EXPECT_EQ(json.at("backend"), "gles");
    EXPECT_EQ(json.at("path"), "fallback");
    EXPECT_EQ(json.at("width"), 128);
    EXPECT_EQ(json.at("height"), 64);
    ASSERT_EQ(json.at("passes").size(), 2u);
    const nlohmann::json& forward = json["passes"][0];
    EXPECT_EQ(forward.at("name"), "forward");
    EXPECT_EQ(forward.at("gpuMs"), 1.5);
    EXPECT_EQ(forward.at("cpuMs"), 0.25);
    EXPECT_EQ(forward.at("draws"), 18);
    EXPECT_EQ(forward.at("dispatches"), 0);
    EXPECT_TRUE(json["passes"][1].at("gpuMs").is_null());
}

TEST(FeaturePath, NamesRoundTrip) {
    for (FeaturePath path : {FeaturePath::Compute, FeaturePath::Fallback}) EXPECT_EQ(parseFeaturePath(toString(path)), path);
    EXPECT_EQ(parseFeaturePath("Compute"), std::nullopt);
    EXPECT_EQ(parseFeaturePath(""), std::nullopt);
}

}  // namespace
}  // namespace janus::renderer
