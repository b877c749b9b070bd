// The Vulkan backend's binding sets (rhi-vulkan/src/vulkan_binding.cpp): what a per-draw bind
// reads. Binding sets are many and a pass binds a different one per draw, so each bind may miss
// the cache; everything a bind of a one-read set and its tracking read lies in the set's first
// cache line (BindingSet::bindBytes), and that set's one read is kept there (LayoutUse::onlyRead).
#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cstring>
#include <vector>

#include "backend_test.h"
#include "vulkan_backend.h"

namespace janus::rhi::test {
namespace {

class VulkanBindingSetTest : public BackendTest {
protected:
    void SetUp() override {
        BackendTest::SetUp();
        if (IsSkipped() || HasFatalFailure()) return;   // configuration not selected: no device
        if (backend() != Backend::Vulkan) GTEST_SKIP() << "the Vulkan backend's binding sets";
    }
};
JANUS_INSTANTIATE_BACKEND_TESTS(VulkanBindingSetTest);

TEST_P(VulkanBindingSetTest, AOneReadSetsBindReadsOneCacheLine) {
    BufferHandle uniforms = createBuffer(BufferUsage::Uniform, std::vector<std::byte>(1024));
    BindingSetHandle slice = device().createBindingSet(BindingSetDesc().add(BindingItem::uniformBuffer(0, uniforms, 256, 64)));
    PipelineHandle pipeline = fullscreenPipeline("bench_uniform_color_frag", Format::RGBA8_UNORM);
    TextureHandle target = createTexture2D(Format::RGBA8_UNORM, 4, 4, TextureUsage::RenderTarget);
    drawFullscreen(RenderPassDesc().addColor(Attachment::clear(target)), pipeline, {slice});   // makes the set's use

    const auto& set = dynamic_cast<const vulkan::BindingSet&>(*slice);
    const auto address = reinterpret_cast<uintptr_t>(&set);
    EXPECT_EQ(address % 64, 0u) << "the set is aligned to a cache line";
    EXPECT_LE(set.bindBytes(), 64u) << "a bind reads beyond the set's first line";
    const auto keepMark = reinterpret_cast<uintptr_t>(&keepMarkOf(set));
    EXPECT_LE(keepMark + sizeof(KeepMark), address + 64) << "a bind reads the keep mark in the first line";

    const auto& vkPipeline = dynamic_cast<const vulkan::Pipeline&>(*pipeline);
    const vulkan::DescriptorSetLayoutInfo& layout = *vkPipeline.sets[0];
    const vulkan::BindingSet::LayoutUse* use = set.findUse(layout.layout);
    ASSERT_EQ(use, &set.firstUse()) << "the first layout used is the inline one";
    EXPECT_EQ(use->onlyRead.resource, uniforms.get());
    EXPECT_EQ(use->onlyRead.range.begin, 256u);
    EXPECT_EQ(use->onlyRead.range.end, 320u);
    ASSERT_EQ(use->accesses.size(), 1u);
    EXPECT_EQ(layout.onlyBindingStages, use->accesses[0].stages) << "what the pass's reads are widened by";
    EXPECT_EQ(layout.onlyBindingStages, VkPipelineStageFlags(VK_PIPELINE_STAGE_FRAGMENT_SHADER_BIT));
}

// A dynamic uniform buffer's access is every window its offsets can select, from the item's
// offset to the buffer's end, so that no offset escapes the tracking; and the set never takes the
// straight-line binds, which pass no offsets (no one read, not a plain bind).
TEST_P(VulkanBindingSetTest, ADynamicSetsAccessCoversEveryWindow) {
    BufferHandle uniforms = createBuffer(BufferUsage::Uniform, std::vector<std::byte>(1024));
    BindingSetHandle slices = device().createBindingSet(
        BindingSetDesc().add(BindingItem::uniformBuffer(0, uniforms, 256, 64).setDynamicOffset()));
    PipelineHandle pipeline = fullscreenPipeline("bench_uniform_color_frag", Format::RGBA8_UNORM, {{0, 0}});
    TextureHandle target = createTexture2D(Format::RGBA8_UNORM, 4, 4, TextureUsage::RenderTarget);
    const std::array<uint32_t, 1> offset = {uint32_t(std::max<uint64_t>(caps().limits.uniformBufferOffsetAlignment, 64))};
    submit([&](ICommandList& cmd) {
        cmd.beginRenderPass(RenderPassDesc().addColor(Attachment::clear(target)));
        cmd.setPipeline(pipeline);
        cmd.setBindingSet(0, slices, offset);
        cmd.draw(3);
        cmd.endRenderPass();
    });
    const auto& set = dynamic_cast<const vulkan::BindingSet&>(*slices);
    const vulkan::BindingSet::LayoutUse* use = set.findUse(dynamic_cast<const vulkan::Pipeline&>(*pipeline).sets[0]->layout);
    ASSERT_NE(use, nullptr);
    ASSERT_EQ(use->accesses.size(), 1u);
    EXPECT_EQ(use->accesses[0].range.begin, 256u);
    EXPECT_EQ(use->accesses[0].range.end, 1024u) << "a window moved by an offset must stay inside the tracked range";
    EXPECT_EQ(use->onlyRead.resource, nullptr) << "bindInPass would bind it without its offsets";
    EXPECT_FALSE(use->plainBind) << "the straight-line dispatch would bind it without its offsets";
    EXPECT_EQ(use->dynamicCount, 1u);
}

// A set whose one access writes is tracked as a write by the general path: it has no one read.
TEST_P(VulkanBindingSetTest, AWrittenSetHasNoOneRead) {
    BufferHandle counter = createBufferFrom(BufferUsage::Storage, std::vector<uint32_t>{0});
    BindingSetHandle bindings = storageSlice(counter, 0, sizeof(uint32_t));
    PipelineHandle increment = computePipeline("bench_increment_comp");
    submit([&](ICommandList& cmd) {
        cmd.setPipeline(increment);
        cmd.setBindingSet(0, bindings);
        cmd.dispatch(1);
    });
    EXPECT_EQ(readBufferAs<uint32_t>(counter), std::vector<uint32_t>{1});
    const auto& set = dynamic_cast<const vulkan::BindingSet&>(*bindings);
    const vulkan::BindingSet::LayoutUse* use =
        set.findUse(dynamic_cast<const vulkan::Pipeline&>(*increment).sets[0]->layout);
    ASSERT_NE(use, nullptr);
    ASSERT_EQ(use->accesses.size(), 1u);
    EXPECT_TRUE(use->accesses[0].write);
    EXPECT_EQ(use->onlyRead.resource, nullptr);
}

}  // namespace
}  // namespace janus::rhi::test
