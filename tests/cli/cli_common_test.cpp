// Pieces of apps/janus/cli_common.cpp that need no device.
#include <gtest/gtest.h>

#include <nlohmann/json.hpp>

#include "cli_common.h"

namespace janus::cli {
namespace {

// The benches' medians: the middle run, or the mean of the middle two (shadows took the upper
// one until session 35).
TEST(BenchMedian, MiddleRunOrMeanOfTheMiddleTwo) {
    EXPECT_EQ(median({}), 0.0);
    EXPECT_EQ(median({3.0}), 3.0);
    EXPECT_EQ(median({5.0, 1.0, 3.0}), 3.0);
    EXPECT_EQ(median({4.0, 1.0, 2.0, 8.0}), 3.0);
}

TEST(ValidUtf8, KeepsValidTextAndEscapesEveryInvalidByte) {
    EXPECT_EQ(validUtf8("plain/path.gltf"), "plain/path.gltf");
    EXPECT_EQ(validUtf8("caf\xC3\xA9 \xE2\x82\xAC \xF0\x9F\x98\x80"), "caf\xC3\xA9 \xE2\x82\xAC \xF0\x9F\x98\x80");
    EXPECT_EQ(validUtf8("bad\xFFname.gltf"), "bad\\xFFname.gltf");
    EXPECT_EQ(validUtf8("\xC3"), "\\xC3");                       // truncated sequence
    EXPECT_EQ(validUtf8("\xC0\xAF"), "\\xC0\\xAF");              // overlong '/'
    EXPECT_EQ(validUtf8("\xED\xA0\x80"), "\\xED\\xA0\\x80");     // a surrogate
    EXPECT_EQ(validUtf8("\xF4\x90\x80\x80"), "\\xF4\\x90\\x80\\x80");   // above U+10FFFF
    EXPECT_EQ(validUtf8("\xE2\x82x"), "\\xE2\\x82x");
}

TEST(ValidUtf8, JsonFileTextNeverThrowsOnFileNames) {
    const nlohmann::json json = {{"path", "dir/bad\xFFname.gltf"}, {"list", {"ok", "\xFE"}}, {"key\xFF", 1}};
    EXPECT_THROW((void)json.dump(), nlohmann::json::type_error);
    const nlohmann::json parsed = nlohmann::json::parse(jsonFileText(json));
    EXPECT_EQ(parsed["path"], "dir/bad\\xFFname.gltf");
    EXPECT_EQ(parsed["list"][1], "\\xFE");
    EXPECT_EQ(parsed["key\\xFF"], 1);
}

}  // namespace
}  // namespace janus::cli
