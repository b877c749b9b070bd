// DirectionalShadowMap: the fit on the CPU, and on every backend (validation on) the depth the
// shadow pass stores and what shadow_sampling.glsl makes of it, for a box floating over a ground
// quad.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <map>
#include <memory>
#include <optional>
#include <vector>

#include <fmt/format.h>
#include <glm/glm.hpp>
#include <glm/gtc/matrix_transform.hpp>

#include "janus/renderer/renderer.h"
#include "janus/renderer/scene.h"
#include "janus/rhi/rhi.h"
// Internal to the renderer; the test target sees only tests/ and the public include paths.
#include "../../renderer/src/shadows/shadow_map.h"
#include "../../shaders/include/janus/shaders/shaders.h"
#include "renderer/renderer_test_support.h"

namespace janus::renderer {
namespace {

const glm::vec3 kLightDirection = glm::normalize(glm::vec3(0.3f, -1.0f, 0.2f));
// Ground quad y = 0 over [-2, 2]^2; box [-0.5, 0.5] x [1, 1.5] x [-0.5, 0.5] floating above it.
constexpr float kGroundHalf = 2.0f;
const glm::vec3 kBoxMin(-0.5f, 1.0f, -0.5f), kBoxMax(0.5f, 1.5f, 0.5f);
const glm::vec3 kSceneMin(-kGroundHalf, 0.0f, -kGroundHalf), kSceneMax(kGroundHalf, 1.5f, kGroundHalf);

glm::vec3 project(const glm::mat4& m, const glm::vec3& p) {
    const glm::vec4 q = m * glm::vec4(p, 1.0f);
    return glm::vec3(q) / q.w;
}

// --- fit() on the CPU ------------------------------------------------------------------------

// fit() needs no GPU work, but the class is built around a device: the shared Vulkan device
// (every backend is expected where the suite runs, as in the rest of the renderer suite).
rhi::IDevice* anyDevice() { return &test_support::deviceFor(rhi::Backend::Vulkan); }

TEST(ShadowMapFit, EveryBoundCornerLandsInsideTheMap) {
    rhi::IDevice* device = anyDevice();
    DirectionalShadowMap shadows(*device, 256);
    const std::vector<glm::vec3> directions = {kLightDirection, {0, -1, 0}, {0, 1, 0}, {1, 0, 0}, {-0.5f, -0.2f, 0.8f}, {1e-3f, -1, 0}};
    const std::vector<std::pair<glm::vec3, glm::vec3>> boxes = {
        {kSceneMin, kSceneMax}, {{-100, -3, 7}, {250, 40, 9}}, {{5, 5, 5}, {5, 5, 5}}, {{1e4f, 0, 0}, {1e4f + 1, 1, 1}}};
    for (const glm::vec3& direction : directions) {
        for (const auto& [lo, hi] : boxes) {
            SCOPED_TRACE(fmt::format("direction ({}, {}, {}), box ({}, {}, {})-({}, {}, {})", direction.x, direction.y, direction.z,
                                     lo.x, lo.y, lo.z, hi.x, hi.y, hi.z));
            shadows.fit(direction, lo, hi);
            const glm::mat4 toShadow = shadows.worldToShadow();
            // The two-texel border is the fit's promise; one texel of it may go to the snap.
            const float border = shadows.texelSize();
            for (int corner = 0; corner < 8; ++corner) {
                const glm::vec3 p((corner & 1) ? hi.x : lo.x, (corner & 2) ? hi.y : lo.y, (corner & 4) ? hi.z : lo.z);
                const glm::vec3 s = project(toShadow, p);
                EXPECT_GE(s.x, border) << "corner " << corner;
                EXPECT_LE(s.x, 1.0f - border) << "corner " << corner;
                EXPECT_GE(s.y, border) << "corner " << corner;
                EXPECT_LE(s.y, 1.0f - border) << "corner " << corner;
                EXPECT_GT(s.z, 0.0f) << "corner " << corner;
                EXPECT_LT(s.z, 1.0f) << "corner " << corner;
            }
            // Depth grows along the light: a point further along the direction is deeper.
            const glm::vec3 center = (lo + hi) * 0.5f;
            EXPECT_LT(project(toShadow, center - direction * 1e-2f).z, project(toShadow, center + direction * 1e-2f).z);
        }
    }
}

TEST(ShadowMapFit, TexelGridStaysFixedWhileTheBoundsMove) {
    rhi::IDevice* device = anyDevice();
    DirectionalShadowMap a(*device, 128), b(*device, 128);
    a.fit(kLightDirection, kSceneMin, kSceneMax);
    b.fit(kLightDirection, kSceneMin, kSceneMax);
    EXPECT_EQ(std::memcmp(&a.lightViewProjection(), &b.lightViewProjection(), sizeof(glm::mat4)), 0) << "equal inputs, equal matrices";

    // Moving the bounds by a fraction of a texel moves the window by whole texels only, so a fixed
    // world point keeps its position within its texel.
    const float texel = a.texelWorldSize();
    const glm::vec3 probe(0.37f, 0.2f, -0.81f);
    const glm::vec3 before = project(a.worldToShadow(), probe) * float(a.size());
    for (const glm::vec3& shift : {glm::vec3(0.3f, 0.0f, 0.0f), glm::vec3(0.0f, 0.45f, 0.2f), glm::vec3(-2.7f, 0.1f, 1.3f)}) {
        b.fit(kLightDirection, kSceneMin + shift * texel, kSceneMax + shift * texel);
        const glm::vec3 after = project(b.worldToShadow(), probe) * float(b.size());
        for (int axis = 0; axis < 2; ++axis) {
            const float moved = after[axis] - before[axis];
            // Whole texels, up to float error in texel units of a map over a few world units.
            EXPECT_NEAR(moved, std::round(moved), 2e-3f) << "axis " << axis << " shift (" << shift.x << ", " << shift.y << ", " << shift.z << ")";
        }
    }
}

TEST(ShadowMapFit, RefusesADegenerateDirection) {
    rhi::IDevice* device = anyDevice();
    DirectionalShadowMap shadows(*device, 64);
    EXPECT_THROW(shadows.fit(glm::vec3(0.0f), kSceneMin, kSceneMax), RendererError);
    EXPECT_THROW(shadows.fit(glm::vec3(NAN, -1, 0), kSceneMin, kSceneMax), RendererError);
    EXPECT_THROW(shadows.fit(kLightDirection, glm::vec3(-INFINITY), kSceneMax), RendererError);
    EXPECT_THROW(DirectionalShadowMap(*device, 4), RendererError);
    uint32_t draws = 0;
    rhi::CommandListHandle cmd = device->createCommandList();
    cmd->begin();
    EXPECT_THROW(shadows.record(*cmd, {}, draws), RendererError) << "record() before fit()";
    cmd->end();
}

TEST(ShadowMapScene, BoundsCoverEveryInstanceAndTheBrightestDirectionalLightIsMain) {
    Scene scene;
    Mesh mesh;
    for (const glm::vec3& p : {glm::vec3(-1, 0, 0), glm::vec3(1, 2, 0), glm::vec3(0, 0, 3)})
        mesh.vertices.push_back(Vertex{p, glm::vec3(0, 1, 0), glm::vec2(0.0f), glm::vec4(0.0f)});
    mesh.indices = {0, 1, 2};
    scene.meshes.push_back(mesh);
    EXPECT_TRUE(sceneWorldBounds(scene).empty()) << "no instances, no bounds";
    Instance moved;
    moved.world = glm::translate(glm::mat4(1.0f), glm::vec3(10, 0, 0)) * glm::scale(glm::mat4(1.0f), glm::vec3(2.0f));
    scene.instances = {Instance{}, moved};
    const WorldBounds bounds = sceneWorldBounds(scene);
    ASSERT_FALSE(bounds.empty());
    EXPECT_EQ(bounds.min, glm::vec3(-1, 0, 0));
    EXPECT_EQ(bounds.max, glm::vec3(12, 4, 6));

    EXPECT_FALSE(mainDirectionalLight(scene).has_value()) << "no lights";
    auto light = [](LightType type, float intensity, glm::vec3 color = glm::vec3(1.0f)) {
        Light l;
        l.type = type;
        l.intensity = intensity;
        l.color = color;
        return l;
    };
    scene.lights = {light(LightType::Point, 100.0f), light(LightType::Directional, 0.0f)};
    EXPECT_FALSE(mainDirectionalLight(scene).has_value()) << "a dark directional light casts nothing";
    scene.lights = {light(LightType::Point, 100.0f), light(LightType::Directional, 2.0f), light(LightType::Directional, 1.0f, {0, 3, 0}),
                    light(LightType::Directional, 3.0f), light(LightType::Directional, 4.0f)};
    EXPECT_EQ(mainDirectionalLight(scene), std::optional<size_t>(4)) << "intensity 4 beats 3, 1 x green 3 and 2";
    EXPECT_EQ(mainDirectionalLight(scene, 3), std::optional<size_t>(2)) << "green 3 ties white 3: the first of equals";
    EXPECT_EQ(mainDirectionalLight(scene, 1), std::optional<size_t>(1)) << "only the first directional light is shaded";
}

// --- the shadow pass on every backend -------------------------------------------------------

constexpr uint32_t kMapSize = 64;   // small: llvmpipe/lavapipe render on two CPU cores

struct Geometry {
    std::vector<Vertex> vertices;
    std::vector<uint32_t> indices;
    void quad(glm::vec3 p0, glm::vec3 p1, glm::vec3 p2, glm::vec3 p3) {   // counter-clockwise seen from the front
        const uint32_t base = uint32_t(vertices.size());
        const glm::vec3 normal = glm::normalize(glm::cross(p1 - p0, p2 - p0));
        for (const glm::vec3& p : {p0, p1, p2, p3}) vertices.push_back(Vertex{p, normal, glm::vec2(0.0f), glm::vec4(0.0f)});
        for (uint32_t i : {0u, 1u, 2u, 0u, 2u, 3u}) indices.push_back(base + i);
    }
};

Geometry ground() {
    Geometry g;
    const float h = kGroundHalf;
    g.quad({-h, 0, -h}, {-h, 0, h}, {h, 0, h}, {h, 0, -h});   // faces +y, towards the light
    return g;
}

Geometry box(glm::vec3 lo, glm::vec3 hi) {
    Geometry g;
    // Each face counter-clockwise seen from outside, so back-face culling keeps the lit side.
    g.quad({lo.x, hi.y, lo.z}, {lo.x, hi.y, hi.z}, {hi.x, hi.y, hi.z}, {hi.x, hi.y, lo.z});   // +y
    g.quad({lo.x, lo.y, lo.z}, {hi.x, lo.y, lo.z}, {hi.x, lo.y, hi.z}, {lo.x, lo.y, hi.z});   // -y
    g.quad({hi.x, lo.y, lo.z}, {hi.x, hi.y, lo.z}, {hi.x, hi.y, hi.z}, {hi.x, lo.y, hi.z});   // +x
    g.quad({lo.x, lo.y, lo.z}, {lo.x, lo.y, hi.z}, {lo.x, hi.y, hi.z}, {lo.x, hi.y, lo.z});   // -x
    g.quad({lo.x, lo.y, hi.z}, {hi.x, lo.y, hi.z}, {hi.x, hi.y, hi.z}, {lo.x, hi.y, hi.z});   // +z
    g.quad({lo.x, lo.y, lo.z}, {lo.x, hi.y, lo.z}, {hi.x, hi.y, lo.z}, {hi.x, lo.y, lo.z});   // -z
    return g;
}

// Depth along the ray through shadow coordinates (u, v) at the first surface it meets: the CPU
// reference for one texel centre. nullopt: the ray misses both objects.
struct Hit {
    float depth;
    int object;   // 0 ground, 1 box
};
std::optional<Hit> traceTexel(const glm::mat4& shadowToWorld, float u, float v) {
    const glm::vec3 a = project(shadowToWorld, {u, v, 0.0f}), b = project(shadowToWorld, {u, v, 1.0f});
    const glm::vec3 d = b - a;   // depth t in [0, 1] along the ray is the stored depth (orthographic)
    std::optional<Hit> best;
    auto consider = [&](float t, int object) {
        if (t >= 0.0f && t <= 1.0f && (!best || t < best->depth)) best = Hit{t, object};
    };
    if (std::abs(d.y) > 0.0f) {
        const float t = -a.y / d.y;
        const glm::vec3 p = a + d * t;
        if (std::abs(p.x) <= kGroundHalf && std::abs(p.z) <= kGroundHalf) consider(t, 0);
    }
    float tNear = -INFINITY, tFar = INFINITY;
    for (int axis = 0; axis < 3; ++axis) {
        if (d[axis] == 0.0f) {
            if (a[axis] < kBoxMin[axis] || a[axis] > kBoxMax[axis]) tNear = INFINITY;
            continue;
        }
        float t0 = (kBoxMin[axis] - a[axis]) / d[axis], t1 = (kBoxMax[axis] - a[axis]) / d[axis];
        if (t0 > t1) std::swap(t0, t1);
        tNear = std::max(tNear, t0);
        tFar = std::min(tFar, t1);
    }
    if (tNear <= tFar) consider(tNear, 1);
    return best;
}

std::string joinMessages(const std::vector<rhi::DebugMessage>& messages) {
    std::string text;
    for (const rhi::DebugMessage& m : messages) text += "\n  " + m.text;
    return text;
}

class ShadowMapTest : public testing::TestWithParam<rhi::Backend> {
protected:
    void SetUp() override {
        try {
            m_device = rhi::createDevice(rhi::DeviceDesc{}.setBackend(GetParam()).setEnableValidation(true).setEnableSynchronizationValidation(true));
        } catch (const rhi::Error& e) {
            // Every backend is expected where the suite runs (CI has all three): not a skip.
            FAIL() << rhi::toString(GetParam()) << " could not start: " << e.what();
        }
    }
    void TearDown() override {
        if (!m_device) return;
        m_device->waitIdle();
        const std::vector<rhi::DebugMessage> messages = m_device->takeDebugMessages();
        EXPECT_TRUE(messages.empty()) << "validation / debug messages:" << joinMessages(messages);
    }

    rhi::BufferHandle buffer(rhi::BufferUsage usage, const void* data, size_t size) {
        rhi::BufferHandle b = m_device->createBuffer(rhi::BufferDesc{}.setSize(size).setUsage(usage));
        m_device->writeBuffer(b, data, size);
        return b;
    }
    ShadowCaster caster(const Geometry& g, bool doubleSided) {
        return ShadowCaster{buffer(rhi::BufferUsage::Vertex, g.vertices.data(), g.vertices.size() * sizeof(Vertex)),
                            buffer(rhi::BufferUsage::Index, g.indices.data(), g.indices.size() * sizeof(uint32_t)),
                            uint32_t(g.indices.size()), glm::mat4(1.0f), doubleSided};
    }

    // Renders ground + box into a fitted map; returns the stored depths, row 0 first.
    std::vector<float> renderMap(DirectionalShadowMap& shadows, std::vector<ShadowCaster>& casters) {
        shadows.fit(kLightDirection, kSceneMin, kSceneMax);
        shadows.setCasters(casters);
        rhi::CommandListHandle cmd = m_device->createCommandList();
        uint32_t draws = 0;
        cmd->begin();
        shadows.record(*cmd, casters, draws);
        cmd->end();
        m_device->execute(cmd);
        EXPECT_EQ(draws, casters.size());
        const std::vector<std::byte> bytes = m_device->readTexture(shadows.texture(), {});
        std::vector<float> depth(bytes.size() / sizeof(float));
        std::memcpy(depth.data(), bytes.data(), depth.size() * sizeof(float));
        return depth;
    }

    std::unique_ptr<rhi::IDevice> m_device;
};

// Every texel holds the depth of the first surface along its ray (a CPU ray cast through the
// inverse of worldToShadow, so a wrong row order or winding shows), pushed back by no more than
// the polygon offset. Texels whose 3x3 neighbourhood sees more than one surface are skipped:
// which of them a texel on a silhouette gets is up to the rasteriser.
TEST_P(ShadowMapTest, StoresTheNearestSurfaceDepthPerTexel) {
    DirectionalShadowMap shadows(*m_device, kMapSize);
    // The box single-sided (back faces culled), the ground double-sided: both pipelines run.
    std::vector<ShadowCaster> casters = {caster(box(kBoxMin, kBoxMax), false), caster(ground(), true)};
    const std::vector<float> depth = renderMap(shadows, casters);
    ASSERT_EQ(depth.size(), size_t(kMapSize) * kMapSize);

    const glm::mat4 shadowToWorld = glm::inverse(shadows.worldToShadow());
    std::vector<std::optional<Hit>> expected(depth.size());
    for (uint32_t y = 0; y < kMapSize; ++y)
        for (uint32_t x = 0; x < kMapSize; ++x)
            expected[y * kMapSize + x] = traceTexel(shadowToWorld, (x + 0.5f) / kMapSize, (y + 0.5f) / kMapSize);

    int compared = 0, boxTexels = 0, failures = 0;
    for (uint32_t y = 1; y + 1 < kMapSize; ++y) {
        for (uint32_t x = 1; x + 1 < kMapSize; ++x) {
            const std::optional<Hit>& hit = expected[y * kMapSize + x];
            bool uniform = true;
            float slope = 0.0f;   // largest depth change to a neighbour texel
            for (int dy = -1; dy <= 1; ++dy)
                for (int dx = -1; dx <= 1; ++dx) {
                    const std::optional<Hit>& n = expected[(y + dy) * kMapSize + (x + dx)];
                    if (n.has_value() != hit.has_value() || (n && n->object != hit->object)) uniform = false;
                    else if (n && std::abs(dx) + std::abs(dy) == 1) slope = std::max(slope, std::abs(n->depth - hit->depth));
                }
            if (!uniform) continue;
            ++compared;
            const float stored = depth[y * kMapSize + x];
            if (!hit) {
                if (stored != 1.0f && failures++ < 10)
                    ADD_FAILURE() << "texel (" << x << ", " << y << ") sees nothing but holds " << stored;
                continue;
            }
            boxTexels += hit->object == 1;
            // Polygon offset adds up to kDepthBiasSlope x the depth slope per texel (the specs
            // allow the slope to be taken as |dz/dx| + |dz/dy|, hence the factor 2) plus a few
            // ulps of constant bias and interpolation error.
            const float allowedBias = 2.0f * DirectionalShadowMap::kDepthBiasSlope * slope + 1e-5f;
            if ((stored < hit->depth - 1e-5f || stored > hit->depth + allowedBias) && failures++ < 10)
                ADD_FAILURE() << "texel (" << x << ", " << y << ") holds " << stored << ", expected " << hit->depth << " + [0, "
                              << allowedBias << "] of the " << (hit->object ? "box" : "ground");
        }
    }
    EXPECT_EQ(failures, 0);
    EXPECT_GT(compared, int(kMapSize * kMapSize) / 2) << "too few texels away from silhouettes to mean anything";
    EXPECT_GT(boxTexels, 20) << "the box covers a good patch of the map";

    // Known points: the box's top centre lands on its texel, nearer than the ground beside it.
    const glm::vec3 top = project(shadows.worldToShadow(), {0.0f, kBoxMax.y, 0.0f});
    const uint32_t tx = uint32_t(top.x * kMapSize), ty = uint32_t(top.y * kMapSize);
    ASSERT_TRUE(tx > 0 && ty > 0 && tx + 1 < kMapSize && ty + 1 < kMapSize);
    const std::optional<Hit>& centre = expected[ty * kMapSize + tx];
    ASSERT_TRUE(centre && centre->object == 1) << "texel (" << tx << ", " << ty << ") sees the box top";
    const float topSlope = std::max(std::abs(expected[ty * kMapSize + tx + 1]->depth - centre->depth),
                                    std::abs(expected[(ty + 1) * kMapSize + tx]->depth - centre->depth));
    // The point lies within half a texel of the texel centre in x and y (up to one slope of
    // depth either way), and the polygon offset pushes the stored value back as above.
    EXPECT_GE(depth[ty * kMapSize + tx], top.z - topSlope - 1e-5f);
    EXPECT_LE(depth[ty * kMapSize + tx], top.z + topSlope * (1.0f + 2.0f * DirectionalShadowMap::kDepthBiasSlope) + 1e-5f)
        << "box top centre at texel (" << tx << ", " << ty << ")";
    const glm::vec3 open = project(shadows.worldToShadow(), {-1.8f, 0.0f, 1.8f});
    EXPECT_LT(depth[ty * kMapSize + tx] + 0.1f, open.z) << "the box is well above the ground";
}

// shadow_sampling.glsl on the map: ground points in the box's shadow are dark, open ground and
// the box top are fully lit (no acne), points outside the map are lit.
TEST_P(ShadowMapTest, SamplingShadowsTheGroundUnderTheBoxOnly) {
    DirectionalShadowMap shadows(*m_device, kMapSize);
    std::vector<ShadowCaster> casters = {caster(box(kBoxMin, kBoxMax), false), caster(ground(), false)};
    renderMap(shadows, casters);

    // Where the box's centre line meets the ground, following the light.
    const glm::vec3 boxCentre = (kBoxMin + kBoxMax) * 0.5f;
    const glm::vec3 umbra = boxCentre + kLightDirection * (boxCentre.y / -kLightDirection.y);
    struct Probe {
        glm::vec3 point;
        float lit;
        const char* what;
    };
    const std::vector<Probe> probes = {
        {umbra, 0.0f, "ground under the box"},
        {umbra + glm::vec3(0.15f, 0.0f, -0.1f), 0.0f, "ground under the box, off centre"},
        {{-1.7f, 0.0f, -1.7f}, 1.0f, "open ground"},
        {{1.6f, 0.0f, 1.7f}, 1.0f, "open ground"},
        {{-1.5f, 0.0f, 1.2f}, 1.0f, "open ground"},
        {{1.7f, 0.0f, -1.5f}, 1.0f, "open ground"},
        {{0.0f, kBoxMax.y, 0.0f}, 1.0f, "box top"},
        {{0.2f, kBoxMax.y, -0.25f}, 1.0f, "box top"},
        {{50.0f, 0.0f, 0.0f}, 1.0f, "outside the map"},
        {{0.0f, -80.0f, 0.0f}, 1.0f, "beyond the far plane"},
    };

    struct Lookups {
        glm::mat4 worldToShadow;
        glm::vec4 params;
        glm::vec4 points[16];
    } lookups{};
    static_assert(sizeof(Lookups) == 64 + 16 + 16 * 16, "Lookups must match std140 in shadow_sampling_test.frag");
    lookups.worldToShadow = shadows.worldToShadow();
    lookups.params = glm::vec4(shadows.texelSize(), shadows.normalOffset(), 0.0f, 0.0f);
    for (size_t i = 0; i < probes.size(); ++i) lookups.points[i] = glm::vec4(probes[i].point, 1.0f);
    rhi::BufferHandle uniforms = buffer(rhi::BufferUsage::Uniform, &lookups, sizeof(lookups));
    rhi::BindingSetHandle bindings = m_device->createBindingSet(
        rhi::BindingSetDesc{}.add(rhi::BindingItem::uniformBuffer(0, uniforms)).add(shadows.binding(1)));

    auto shader = [&](rhi::ShaderStage stage, const char* name) {
        return m_device->createShader(rhi::ShaderDesc{}.setStage(stage).setSpirv(shaders::get(name)).setDebugName(name));
    };
    rhi::PipelineHandle pipeline = m_device->createGraphicsPipeline(
        rhi::GraphicsPipelineDesc{}
            .setShaders(shader(rhi::ShaderStage::Vertex, "fullscreen_vert"), shader(rhi::ShaderStage::Fragment, "shadow_sampling_test_frag"))
            .addColorFormat(rhi::Format::RGBA8_UNORM));
    rhi::TextureHandle target = m_device->createTexture(
        rhi::TextureDesc{}.setFormat(rhi::Format::RGBA8_UNORM).setSize(uint32_t(probes.size()), 1).setUsage(rhi::TextureUsage::RenderTarget));
    rhi::CommandListHandle cmd = m_device->createCommandList();
    cmd->begin();
    cmd->beginRenderPass(rhi::RenderPassDesc{}.addColor(rhi::Attachment::clear(target)));
    cmd->setPipeline(pipeline);
    cmd->setBindingSet(0, bindings);
    cmd->draw(3);
    cmd->endRenderPass();
    cmd->end();
    m_device->execute(cmd);

    const std::vector<std::byte> pixels = m_device->readTexture(target, {});
    ASSERT_EQ(pixels.size(), probes.size() * 4);
    for (size_t i = 0; i < probes.size(); ++i) {
        const int seen = int(std::to_integer<uint8_t>(pixels[i * 4]));
        // Exact: each probe is several texels from any shadow edge, so all 16 texels of the PCF
        // footprint agree and the filter returns exactly 0 or 1.
        EXPECT_EQ(seen, int(probes[i].lit * 255.0f))
            << probes[i].what << " at (" << probes[i].point.x << ", " << probes[i].point.y << ", " << probes[i].point.z << ")";
    }
}

INSTANTIATE_TEST_SUITE_P(Backends, ShadowMapTest, testing::Values(rhi::Backend::Vulkan, rhi::Backend::GL, rhi::Backend::GLES),
                         [](const testing::TestParamInfo<rhi::Backend>& info) { return std::string(rhi::toString(info.param)); });

}  // namespace
}  // namespace janus::renderer
