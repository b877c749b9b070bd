// Threads: what docs/ARCHITECTURE.md "Threads" promises, on every backend. Command lists record
// on any threads at once and handles are released on any thread; device calls come from several
// threads at once where Capability::ConcurrentDeviceCalls says so (Vulkan), else from one thread at
// a time, handed over by detachFromThread() or by the thread's exit (GL, whose context is current
// on one thread at a time).
#include "backend_test.h"

#include <atomic>
#include <future>
#include <thread>

namespace janus::rhi::test {
namespace {

class ThreadingTest : public BackendTest {};
JANUS_INSTANTIATE_BACKEND_TESTS(ThreadingTest);

// Runs `body` on a new thread and waits for it to end; an exception there is rethrown here.
void onAnotherThread(const std::function<void()>& body) {
    std::exception_ptr failure;
    std::thread thread([&] {
        try {
            body();
        } catch (...) {
            failure = std::current_exception();
        }
    });
    thread.join();
    if (failure) std::rethrow_exception(failure);
}

constexpr std::array<uint32_t, 4> kFirst{1, 2, 3, 4}, kSecond{5, 6, 7, 8};

TEST_P(ThreadingTest, AThreadThatEndsLetsGoOfTheDevice) {
    BufferHandle buffer = createBufferFrom(BufferUsage::Uniform, std::vector<uint32_t>(kFirst.begin(), kFirst.end()));
    device().detachFromThread();
    std::vector<uint32_t> readThere;
    onAnotherThread([&] {
        readThere = readBufferAs<uint32_t>(buffer);
        device().writeBuffer(buffer, kSecond.data(), sizeof kSecond);
        // No detachFromThread(): the thread's end lets go of the device.
    });
    EXPECT_EQ(readThere, std::vector<uint32_t>(kFirst.begin(), kFirst.end()));
    EXPECT_EQ(readBufferAs<uint32_t>(buffer), std::vector<uint32_t>(kSecond.begin(), kSecond.end()));
}

TEST_P(ThreadingTest, DetachFromThreadHandsTheDeviceToAThreadThatLivesOn) {
    BufferHandle buffer = createBufferFrom(BufferUsage::Uniform, std::vector<uint32_t>(kFirst.begin(), kFirst.end()));
    device().detachFromThread();
    std::promise<void> workerDone, mainDone;
    std::exception_ptr failure;
    std::thread worker([&] {
        try {
            device().writeBuffer(buffer, kSecond.data(), sizeof kSecond);
            device().detachFromThread();
        } catch (...) {
            failure = std::current_exception();
        }
        workerDone.set_value();
        mainDone.get_future().wait();   // alive while this thread uses the device
    });
    workerDone.get_future().wait();
    std::vector<uint32_t> read;
    EXPECT_NO_THROW(read = readBufferAs<uint32_t>(buffer));
    mainDone.set_value();
    worker.join();
    if (failure) std::rethrow_exception(failure);
    EXPECT_EQ(read, std::vector<uint32_t>(kSecond.begin(), kSecond.end()));
}

// GL: the context is current on the thread that used the device last; another thread's call is
// refused with a message saying what to do, and the holder goes on undisturbed. Vulkan: the call
// is simply made.
TEST_P(ThreadingTest, ACallWhileAnotherThreadHoldsTheDeviceIsRefusedUnlessConcurrentCallsAreSupported) {
    BufferHandle buffer = createBufferFrom(BufferUsage::Uniform, std::vector<uint32_t>(kFirst.begin(), kFirst.end()));
    std::vector<uint32_t> readThere;
    auto readOnAnotherThread = [&] { onAnotherThread([&] { readThere = readBufferAs<uint32_t>(buffer); }); };
    if (caps().concurrentDeviceCalls) {
        EXPECT_NO_THROW(readOnAnotherThread());
        EXPECT_EQ(readThere, std::vector<uint32_t>(kFirst.begin(), kFirst.end()));
    } else {
        EXPECT_TRUE(throwsRhiError(readOnAnotherThread, ErrorCode::InvalidUsage,
                                   {"current on another thread", "detachFromThread()", "ConcurrentDeviceCalls"}));
    }
    device().writeBuffer(buffer, kSecond.data(), sizeof kSecond);
    EXPECT_EQ(readBufferAs<uint32_t>(buffer), std::vector<uint32_t>(kSecond.begin(), kSecond.end()));
}

// Each thread records its own command list with objects all of them share (the pipeline, the
// vertex buffer, a binding set sampling one texture): recording makes no API calls on GL, and on
// Vulkan each list has its own pool. The lists then execute on this thread.
TEST_P(ThreadingTest, CommandListsRecordOnSeveralThreadsAtOnce) {
    constexpr uint32_t kThreads = 4, kDrawsPerList = 16;
    PipelineHandle sampling = fullscreenPipeline("rt_sample_2d_frag", Format::RGBA8_UNORM);
    PipelineHandle colors = colorPipeline(Format::RGBA8_UNORM);
    TextureHandle texture = createTexture2D(Format::RGBA8_UNORM, 1, 1);
    const Rgba8 texel{10, 200, 30, 255};
    device().writeTexture(texture, {}, &texel, sizeof texel);
    BindingSetHandle shared =
        device().createBindingSet(BindingSetDesc().add(BindingItem::sampledTexture(0, texture, nearestClampSampler())));
    // The right half of each target: the thread's own colour, over the sampled left half.
    std::vector<TextureHandle> targets;
    std::vector<BufferHandle> halves;
    std::vector<Rgba8> threadColors;
    std::vector<CommandListHandle> lists;
    for (uint32_t t = 0; t < kThreads; ++t) {
        targets.push_back(createTexture2D(Format::RGBA8_UNORM, 4, 4, TextureUsage::RenderTarget));
        // 8-bit values exactly: 0.5 is 127.5 steps, which drivers round either way (NVIDIA: 127).
        const std::array<float, 4> color{float(64 * t) / 255.0f, 1.0f, 128.0f / 255.0f, 1.0f};
        threadColors.push_back(toRgba8(color));
        halves.push_back(createBufferFrom(BufferUsage::Vertex, rectangle(0.0f, -1.0f, 1.0f, 1.0f, color)));
        lists.push_back(device().createCommandList());
    }

    std::atomic<uint32_t> ready{0};
    std::vector<std::exception_ptr> failures(kThreads);
    std::vector<std::thread> threads;
    for (uint32_t t = 0; t < kThreads; ++t) {
        threads.emplace_back([&, t] {
            try {
                ++ready;
                while (ready.load() < kThreads) std::this_thread::yield();   // record at the same time
                ICommandList& cmd = *lists[t];
                cmd.begin();
                cmd.beginRenderPass(RenderPassDesc().addColor(Attachment::clear(targets[t])));
                cmd.setPipeline(sampling);
                for (uint32_t i = 0; i < kDrawsPerList; ++i) {
                    cmd.setBindingSet(0, shared);
                    cmd.draw(3);
                }
                cmd.setPipeline(colors);
                cmd.setVertexBuffer(0, halves[t]);
                cmd.draw(6);
                cmd.endRenderPass();
                cmd.end();
            } catch (...) {
                failures[t] = std::current_exception();
            }
        });
    }
    for (std::thread& thread : threads) thread.join();
    for (const std::exception_ptr& failure : failures)
        if (failure) std::rethrow_exception(failure);

    for (uint32_t t = 0; t < kThreads; ++t) {
        device().execute(lists[t]);
        std::vector<Rgba8> expected(16);
        for (size_t i = 0; i < expected.size(); ++i) expected[i] = i % 4 < 2 ? texel : threadColors[t];
        EXPECT_TRUE(imagesEqual(readTextureAs<Rgba8>(targets[t]), expected, 4)) << "list of thread " << t;
    }
}

// Handles may be released on any thread. GL deletes an object whose context is current elsewhere
// at the context's next use on its own thread; before that fix, one release on another thread left
// the context "unreachable at teardown" for good and every later GL object to the driver.
TEST_P(ThreadingTest, HandlesReleasedOnAnotherThreadLeaveTheDeviceWhole) {
    std::vector<BufferHandle> buffers;
    for (int i = 0; i < 8; ++i) buffers.push_back(createBuffer(BufferUsage::Uniform, 256));
    TextureHandle texture = createTexture2D(Format::RGBA8_UNORM, 4, 4, TextureUsage::RenderTarget);
    testing::internal::CaptureStderr();
    onAnotherThread([&] {
        buffers.clear();
        texture.reset();
    });
    // The device goes on: new objects, a render pass, a readback.
    TextureHandle target = createTexture2D(Format::RGBA8_UNORM, 2, 2, TextureUsage::RenderTarget);
    submit([&](ICommandList& cmd) {
        cmd.beginRenderPass(RenderPassDesc().addColor(Attachment::clear(target, {0, 0, 1, 1})));
        cmd.endRenderPass();
    });
    EXPECT_EQ(readTextureAs<Rgba8>(target), std::vector<Rgba8>(4, Rgba8{0, 0, 255, 255}));
    target.reset();
    EXPECT_EQ(testing::internal::GetCapturedStderr(), "");
}

// Several threads creating, recording, executing and reading back at once, where the device says
// it takes concurrent calls.
TEST_P(ThreadingTest, ConcurrentDeviceCallsWhereTheCapabilitySaysSo) {
    if (!caps().concurrentDeviceCalls) GTEST_SKIP() << "no Capability::ConcurrentDeviceCalls on " << GetParam().name;
    constexpr uint32_t kThreads = 4, kRounds = 8;
    PipelineHandle colors = colorPipeline(Format::RGBA8_UNORM);
    std::atomic<uint32_t> ready{0};
    std::vector<std::exception_ptr> failures(kThreads);
    std::vector<std::string> mismatches(kThreads);
    std::vector<std::thread> threads;
    for (uint32_t t = 0; t < kThreads; ++t) {
        threads.emplace_back([&, t] {
            try {
                ++ready;
                while (ready.load() < kThreads) std::this_thread::yield();
                for (uint32_t round = 0; round < kRounds && mismatches[t].empty(); ++round) {
                    // Exact 8-bit values (t / 4 or round / 8 may be 127.5 steps, rounded either way).
                    const std::array<float, 4> color{float(64 * t) / 255.0f, float(32 * round) / 255.0f, 1.0f, 1.0f};
                    TextureHandle target = createTexture2D(Format::RGBA8_UNORM, 4, 4, TextureUsage::RenderTarget);
                    BufferHandle vertices = createBufferFrom(BufferUsage::Vertex, rectangle(-1, -1, 1, 1, color));
                    CommandListHandle list = device().createCommandList();
                    list->begin();
                    list->beginRenderPass(RenderPassDesc().addColor(Attachment::clear(target)));
                    list->setPipeline(colors);
                    list->setVertexBuffer(0, vertices);
                    list->draw(6);
                    list->endRenderPass();
                    list->end();
                    device().execute(list);
                    const std::vector<Rgba8> pixels = readTextureAs<Rgba8>(target);
                    if (pixels != std::vector<Rgba8>(16, toRgba8(color)))
                        mismatches[t] = fmt::format("round {}: wrong pixels", round);
                }
            } catch (...) {
                failures[t] = std::current_exception();
            }
        });
    }
    for (std::thread& thread : threads) thread.join();
    for (uint32_t t = 0; t < kThreads; ++t) {
        if (failures[t]) std::rethrow_exception(failures[t]);
        EXPECT_EQ(mismatches[t], "") << "thread " << t;
    }
}

}  // namespace
}  // namespace janus::rhi::test
