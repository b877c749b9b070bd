// The probe GI's CPU reference path tracer on Embree 3 (janus/renderer/gi_reference.h).
#include "janus/renderer/gi_reference.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <optional>
#include <string>

#include <embree3/rtcore.h>
#include <fmt/format.h>

#include "core/parallel.h"
#include "gi/gi_bake.h"           // giSampleDirections
#include "ibl/environment_map.h"  // equirectUv
#include "ibl/image_based_lighting.h"
#include "ibl/spherical_harmonics.h"
#include "janus/renderer/light_grid.h"   // packLocalLights (the renderer's attenuation and cone), makeView/makeProjection

namespace janus::renderer {
namespace {

constexpr double kPi = 3.14159265358979323846;
// Converged paths play Russian roulette from this bounce on. Late, because roulette is unbiased but
// noisy: by then a path's throughput is albedo^8 (under 2 % of what it started with at albedo 0.6).
constexpr uint32_t kRouletteFrom = 8;

// PCG32 (O'Neill): small, fast, and the same stream on every platform.
struct Random {
    uint64_t state = 0, increment = 1;
    Random(uint64_t seed, uint64_t stream) : increment((stream << 1u) | 1u) {
        next();
        state += seed;
        next();
    }
    uint32_t next() {
        const uint64_t old = state;
        state = old * 6364136223846793005ull + increment;
        const uint32_t xorshifted = uint32_t(((old >> 18u) ^ old) >> 27u);
        const uint32_t rot = uint32_t(old >> 59u);
        return (xorshifted >> rot) | (xorshifted << ((32u - rot) & 31u));
    }
    double uniform() { return next() * (1.0 / 4294967296.0); }   // [0, 1)
};

// A direction around unit `n` with density cos(theta) / pi, from two numbers in [0, 1).
glm::dvec3 cosineDirection(const glm::dvec3& n, double u1, double u2) {
    const double r = std::sqrt(u1), phi = 2.0 * kPi * u2;
    const double x = r * std::cos(phi), y = r * std::sin(phi), z = std::sqrt(std::max(0.0, 1.0 - u1));
    // Orthonormal basis (Duff et al. 2017).
    const double sign = std::copysign(1.0, n.z);
    const double a = -1.0 / (sign + n.z), b = n.x * n.y * a;
    const glm::dvec3 t(1.0 + sign * n.x * n.x * a, sign * b, -sign * n.x);
    const glm::dvec3 s(b, sign + n.y * n.y * a, -n.y);
    return glm::normalize(x * t + y * s + z * n);
}

double srgbToLinear(double c) { return c <= 0.04045 ? c / 12.92 : std::pow((c + 0.055) / 1.055, 2.4); }

double wrapCoordinate(double t, TextureWrap wrap) {
    switch (wrap) {
        case TextureWrap::ClampToEdge: return std::clamp(t, 0.0, 1.0);
        case TextureWrap::MirroredRepeat: {
            const double period = t - 2.0 * std::floor(t * 0.5);
            return period > 1.0 ? 2.0 - period : period;
        }
        case TextureWrap::Repeat: break;
    }
    return t - std::floor(t);
}

// A texture as linear RGBA doubles (sRGB decoded where the image is colour), bilinear at mip 0.
struct LinearTexture {
    uint32_t width = 0, height = 0;
    std::vector<glm::dvec4> texels;
    TextureSampling sampling;

    explicit LinearTexture(const TextureImage& image) : width(image.width), height(image.height), sampling(image.sampling) {
        std::array<double, 256> fromSrgb{}, fromUnorm{};
        for (int i = 0; i < 256; ++i) {
            fromUnorm[i] = i / 255.0;
            fromSrgb[i] = srgbToLinear(i / 255.0);
        }
        const auto& rgbLut = image.srgb ? fromSrgb : fromUnorm;
        texels.resize(size_t(width) * height);
        for (size_t i = 0; i < texels.size(); ++i)
            texels[i] = glm::dvec4(rgbLut[image.rgba[i * 4]], rgbLut[image.rgba[i * 4 + 1]], rgbLut[image.rgba[i * 4 + 2]],
                                   fromUnorm[image.rgba[i * 4 + 3]]);
    }
    glm::dvec4 texel(int64_t x, int64_t y) const {
        x = std::clamp<int64_t>(x, 0, int64_t(width) - 1);
        y = std::clamp<int64_t>(y, 0, int64_t(height) - 1);
        return texels[size_t(y) * width + size_t(x)];
    }
    glm::dvec4 sample(glm::dvec2 uv) const {
        if (width == 0 || height == 0) return glm::dvec4(1.0);
        if (!std::isfinite(uv.x) || !std::isfinite(uv.y)) uv = glm::dvec2(0.0);
        const double u = wrapCoordinate(uv.x, sampling.wrapU) * width - 0.5, v = wrapCoordinate(uv.y, sampling.wrapV) * height - 0.5;
        const double fx = std::floor(u), fy = std::floor(v);
        const double tx = u - fx, ty = v - fy;
        auto at = [&](int64_t x, int64_t y) {
            // Repeat wraps texel indices; the other modes clamp them.
            if (sampling.wrapU == TextureWrap::Repeat) x = ((x % int64_t(width)) + width) % width;
            if (sampling.wrapV == TextureWrap::Repeat) y = ((y % int64_t(height)) + height) % height;
            return texel(x, y);
        };
        const int64_t x0 = int64_t(fx), y0 = int64_t(fy);
        return glm::mix(glm::mix(at(x0, y0), at(x0 + 1, y0), tx), glm::mix(at(x0, y0 + 1), at(x0 + 1, y0 + 1), tx), ty);
    }
};

// One instance's triangles in world space, with what shading needs per vertex.
struct TraceMesh {
    std::vector<glm::dvec3> normals;   // world, per vertex (may be zero: the geometric normal is used)
    std::vector<glm::dvec2> uvs, uvs1;   // TEXCOORD_0, TEXCOORD_1
    std::vector<glm::dvec4> colors;      // COLOR_0 (white without)
    bool unlit = false;                  // the material's or the mesh's: emits its base colour, reflects nothing
    std::vector<uint32_t> indices;
    double frontSign = 1.0;            // -1 for a mirrored instance: its front faces wind clockwise in world space
    uint32_t renderingLayers = 1u;
    int32_t material = -1;
};

// Base colour and alpha at barycentrics (u, v) of triangle `primitive`: factor x vertex colour x
// texture (its UV set and KHR_texture_transform, as forward_common.glsl's materialUv).
glm::dvec4 baseColorAt(const TraceMesh& mesh, const Material& material, const LinearTexture* texture, uint32_t primitive, double u,
                       double v) {
    const uint32_t i0 = mesh.indices[size_t(primitive) * 3], i1 = mesh.indices[size_t(primitive) * 3 + 1],
                   i2 = mesh.indices[size_t(primitive) * 3 + 2];
    const double w = 1.0 - u - v;
    glm::dvec4 base = glm::dvec4(material.baseColorFactor) * (w * mesh.colors[i0] + u * mesh.colors[i1] + v * mesh.colors[i2]);
    if (texture) {
        const TextureTransform& transform = material.baseColorTransform;
        const bool second = transform.texCoord == 1;
        const glm::dvec2 uv = second ? w * mesh.uvs1[i0] + u * mesh.uvs1[i1] + v * mesh.uvs1[i2]
                                     : w * mesh.uvs[i0] + u * mesh.uvs[i1] + v * mesh.uvs[i2];
        base *= texture->sample(glm::dvec2(glm::dmat3(transform.matrix()) * glm::dvec3(uv, 1.0)));
    }
    return base;
}

// What the ray filters need of one geometry: Embree passes it back as user data.
struct GeometryFilterData {
    const std::vector<glm::dvec3>* positions = nullptr;
    const TraceMesh* mesh = nullptr;
    double frontSign = 1.0;
    bool singleSided = true;
    // alphaMode MASK: a hit where the alpha test discards (alpha below the cutoff) is no hit.
    bool masked = false;
    const Material* material = nullptr;
    const LinearTexture* baseColorTexture = nullptr;
};

// Rays pass an alpha-masked surface where its alpha test discards, as the forward pass, the
// depth prepass, the shadow map and the GI bake's G-buffer do.
bool cutOut(const GeometryFilterData& data, const RTCFilterFunctionNArguments* args, unsigned i) {
    if (!data.masked) return false;
    const uint32_t primitive = RTCHitN_primID(args->hit, args->N, i);
    const double u = RTCHitN_u(args->hit, args->N, i), v = RTCHitN_v(args->hit, args->N, i);
    return baseColorAt(*data.mesh, *data.material, data.baseColorTexture, primitive, u, v).a < double(data.material->alphaCutoff);
}

void passWhereCutOut(const RTCFilterFunctionNArguments* args) {
    const auto* data = static_cast<const GeometryFilterData*>(args->geometryUserPtr);
    for (unsigned i = 0; i < args->N; ++i)
        if (args->valid[i] == -1 && cutOut(*data, args, i)) args->valid[i] = 0;
}

// A single-sided surface casts a shadow only where the light meets its front face: the renderer's
// shadow map draws single-sided casters back-face culled from the light's side, so light passes a
// surface that faces away from it (the cornell box's ceiling, facing down, lets the sun in). The
// reference follows, so that the light it bounces is the light the image shows. A shadow ray runs
// from the receiver towards the light: it passes where it meets a front face. Double-sided
// materials block from both sides.
void passWhereLightMeetsABackFaceOrCutOut(const RTCFilterFunctionNArguments* args) {
    const auto* data = static_cast<const GeometryFilterData*>(args->geometryUserPtr);
    for (unsigned i = 0; i < args->N; ++i) {
        if (args->valid[i] != -1) continue;
        if (cutOut(*data, args, i)) {
            args->valid[i] = 0;
            continue;
        }
        if (!data->singleSided) continue;
        const uint32_t primitive = RTCHitN_primID(args->hit, args->N, i);
        const std::vector<glm::dvec3>& p = *data->positions;
        const uint32_t* tri = data->mesh->indices.data() + size_t(primitive) * 3;
        const glm::dvec3 front = glm::cross(p[tri[1]] - p[tri[0]], p[tri[2]] - p[tri[0]]) * data->frontSign;
        const glm::dvec3 direction(RTCRayN_dir_x(args->ray, args->N, i), RTCRayN_dir_y(args->ray, args->N, i), RTCRayN_dir_z(args->ray, args->N, i));
        if (glm::dot(front, direction) < 0.0) args->valid[i] = 0;   // the light meets its back face: not a hit
    }
}

struct Hit {
    glm::dvec3 position, normal, geometricNormal;   // normals face the side the ray came from
    glm::dvec3 albedo, emission;
    uint32_t renderingLayers = 1u;
};

struct DirectionalLightData {
    glm::dvec3 towardLight, irradiance;
    uint32_t renderingLayers = 1u;
};

}  // namespace

struct GiReference::Impl {
    RTCDevice device = nullptr;
    RTCScene scene = nullptr;
    std::vector<std::vector<glm::dvec3>> meshPositions;   // world positions, per geometry
    std::vector<std::unique_ptr<GeometryFilterData>> filters;
    std::vector<TraceMesh> meshes;
    std::vector<Material> materials;
    std::vector<LinearTexture> textures;
    std::vector<DirectionalLightData> directional;
    std::vector<PackedLight> local;
    std::optional<ImageRGBAF> sky;
    double skyIntensity = 1.0;
    glm::dvec3 ambient{0.0};
    double epsilon = 1e-4;

    ~Impl() {
        if (scene) rtcReleaseScene(scene);
        if (device) rtcReleaseDevice(device);
    }

    glm::dvec3 skyRadiance(const glm::dvec3& direction) const {
        if (!sky) return ambient;
        const glm::dvec2 uv = equirectUv(direction);
        const double x = uv.x * sky->width - 0.5, y = uv.y * sky->height - 0.5;
        const double fx = std::floor(x), fy = std::floor(y);
        auto at = [&](int64_t px, int64_t py) {
            px = ((px % int64_t(sky->width)) + sky->width) % sky->width;   // wraps in longitude
            py = std::clamp<int64_t>(py, 0, int64_t(sky->height) - 1);
            const float* p = &sky->pixels[(size_t(py) * sky->width + size_t(px)) * 4];
            return glm::dvec3(p[0], p[1], p[2]);
        };
        const int64_t x0 = int64_t(fx), y0 = int64_t(fy);
        const double tx = x - fx, ty = y - fy;
        return skyIntensity * glm::mix(glm::mix(at(x0, y0), at(x0 + 1, y0), tx), glm::mix(at(x0, y0 + 1), at(x0 + 1, y0 + 1), tx), ty);
    }

    std::optional<Hit> intersect(const glm::dvec3& origin, const glm::dvec3& direction) const {
        RTCIntersectContext context;
        rtcInitIntersectContext(&context);
        RTCRayHit query{};
        query.ray.org_x = float(origin.x), query.ray.org_y = float(origin.y), query.ray.org_z = float(origin.z);
        query.ray.dir_x = float(direction.x), query.ray.dir_y = float(direction.y), query.ray.dir_z = float(direction.z);
        query.ray.tnear = 0.0f;
        query.ray.tfar = std::numeric_limits<float>::infinity();
        query.ray.mask = ~0u;
        query.hit.geomID = RTC_INVALID_GEOMETRY_ID;
        query.hit.instID[0] = RTC_INVALID_GEOMETRY_ID;
        rtcIntersect1(scene, &context, &query);
        if (query.hit.geomID == RTC_INVALID_GEOMETRY_ID) return std::nullopt;

        const TraceMesh& mesh = meshes[query.hit.geomID];
        const std::vector<glm::dvec3>& p = meshPositions[query.hit.geomID];
        const uint32_t i0 = mesh.indices[query.hit.primID * 3], i1 = mesh.indices[query.hit.primID * 3 + 1],
                       i2 = mesh.indices[query.hit.primID * 3 + 2];
        const double u = query.hit.u, v = query.hit.v, w = 1.0 - u - v;
        Hit hit;
        hit.position = w * p[i0] + u * p[i1] + v * p[i2];
        glm::dvec3 front = glm::cross(p[i1] - p[i0], p[i2] - p[i0]) * mesh.frontSign;
        const double frontLength = glm::length(front);
        front = frontLength > 0.0 ? front / frontLength : -direction;
        const Material defaultMaterial{};
        const Material& material = mesh.material >= 0 ? materials[size_t(mesh.material)] : defaultMaterial;
        const bool backFace = glm::dot(front, direction) > 0.0;
        if (backFace && !material.doubleSided) {
            hit.albedo = hit.emission = glm::dvec3(0.0);
            hit.normal = hit.geometricNormal = glm::dvec3(0.0);   // marks "sends nothing"
            return hit;
        }
        hit.geometricNormal = backFace ? -front : front;
        glm::dvec3 normal = w * mesh.normals[i0] + u * mesh.normals[i1] + v * mesh.normals[i2];
        const double normalLength = glm::length(normal);
        normal = normalLength > 1e-12 ? normal / normalLength : front;
        hit.normal = backFace ? -normal : normal;
        const glm::dvec2 uv0 = w * mesh.uvs[i0] + u * mesh.uvs[i1] + v * mesh.uvs[i2];
        const glm::dvec2 uv1 = w * mesh.uvs1[i0] + u * mesh.uvs1[i1] + v * mesh.uvs1[i2];
        // The texture's UV set and KHR_texture_transform, as forward_common.glsl's materialUv.
        auto uvFor = [&](const TextureTransform& transform) {
            return glm::dvec2(glm::dmat3(transform.matrix()) * glm::dvec3(transform.texCoord == 1 ? uv1 : uv0, 1.0));
        };

        const glm::dvec4 base = baseColorAt(mesh, material, material.baseColorTexture >= 0 ? &textures[size_t(material.baseColorTexture)] : nullptr,
                                            query.hit.primID, u, v);
        hit.renderingLayers = mesh.renderingLayers;
        if (mesh.unlit) {   // as gi_gbuffer.frag: an unlit surface shows its colour whatever lights it
            hit.albedo = glm::dvec3(0.0);
            hit.emission = glm::clamp(glm::dvec3(base), 0.0, 65000.0);
            return hit;
        }
        double metallic = material.metallicFactor;
        if (material.metallicRoughnessTexture >= 0)
            metallic *= textures[size_t(material.metallicRoughnessTexture)].sample(uvFor(material.metallicRoughnessTransform)).b;
        hit.albedo = glm::clamp(glm::dvec3(base), 0.0, 1.0) * (1.0 - std::clamp(metallic, 0.0, 1.0));
        hit.emission = glm::dvec3(material.emissiveFactor) * double(material.emissiveStrength);
        if (material.emissiveTexture >= 0)
            hit.emission *= glm::dvec3(textures[size_t(material.emissiveTexture)].sample(uvFor(material.emissiveTransform)));
        return hit;
    }

    // What the centre of pixel (x, y) of a width x height view sees (NDC y = -1 is row 0; depth 0..1).
    std::optional<Hit> intersectPixel(const glm::dmat4& inverseViewProjection, uint32_t x, size_t y, uint32_t width, uint32_t height) const {
        const glm::dvec2 ndc((x + 0.5) / width * 2.0 - 1.0, (y + 0.5) / height * 2.0 - 1.0);
        const glm::dvec4 nearPoint = inverseViewProjection * glm::dvec4(ndc, 0.0, 1.0);
        const glm::dvec4 farPoint = inverseViewProjection * glm::dvec4(ndc, 1.0, 1.0);
        const glm::dvec3 origin = glm::dvec3(nearPoint) / nearPoint.w;
        return intersect(origin, glm::normalize(glm::dvec3(farPoint) / farPoint.w - origin));
    }

    bool occluded(const glm::dvec3& origin, const glm::dvec3& direction, double distance) const {
        RTCIntersectContext context;
        rtcInitIntersectContext(&context);
        RTCRay ray{};
        ray.org_x = float(origin.x), ray.org_y = float(origin.y), ray.org_z = float(origin.z);
        ray.dir_x = float(direction.x), ray.dir_y = float(direction.y), ray.dir_z = float(direction.z);
        ray.tnear = 0.0f;
        ray.tfar = float(distance);
        ray.mask = ~0u;
        rtcOccluded1(scene, &context, &ray);
        return ray.tfar < 0.0f;
    }

    glm::dvec3 offsetFrom(const Hit& hit) const {
        const double scale = std::max({1.0, std::abs(hit.position.x), std::abs(hit.position.y), std::abs(hit.position.z)});
        return hit.position + hit.geometricNormal * (epsilon * scale);
    }

    // Direct irradiance from every light at a hit, shadowed by rays.
    glm::dvec3 directIrradiance(const Hit& hit) const {
        const glm::dvec3 origin = offsetFrom(hit);
        glm::dvec3 sum(0.0);
        for (const DirectionalLightData& light : directional) {
            if ((light.renderingLayers & hit.renderingLayers) == 0) continue;
            const double cosine = glm::dot(hit.normal, light.towardLight);
            if (cosine <= 0.0 || glm::dot(hit.geometricNormal, light.towardLight) <= 0.0) continue;
            if (!occluded(origin, light.towardLight, std::numeric_limits<double>::infinity())) sum += light.irradiance * cosine;
        }
        for (const PackedLight& light : local) {
            if ((light.renderingLayers & hit.renderingLayers) == 0) continue;
            // light_access.glsl's localLightIrradiance, in double.
            glm::dvec3 toLight = glm::dvec3(light.position) - hit.position;
            const double distanceSq = glm::dot(toLight, toLight);
            const double distance = std::sqrt(distanceSq);
            if (!(distance > 0.0)) continue;
            toLight /= distance;
            const double cosine = glm::dot(hit.normal, toLight);
            if (cosine <= 0.0 || glm::dot(hit.geometricNormal, toLight) <= 0.0) continue;
            const double ratioSq = distanceSq * light.invRangeSq;
            const double window = std::clamp(1.0 - ratioSq * ratioSq, 0.0, 1.0);
            double attenuation = window * window / std::max(distanceSq, 1e-4);
            const double cone = std::clamp(glm::dot(glm::dvec3(light.direction), -toLight) * light.spotScale + light.spotOffset, 0.0, 1.0);
            attenuation *= cone * cone;
            if (attenuation <= 0.0) continue;
            if (!occluded(origin, toLight, distance * (1.0 - 1e-6))) sum += glm::dvec3(light.radiance) * attenuation * cosine;
        }
        return sum;
    }

    // Radiance arriving along a ray; `bounces` as GiReferenceSettings::bounces.
    glm::dvec3 trace(glm::dvec3 origin, glm::dvec3 direction, uint32_t bounces, Random& random) const {
        glm::dvec3 sum(0.0), throughput(1.0);
        const uint32_t maxBounces = bounces == 0 ? kGiReferenceMaxBounces : bounces;
        for (uint32_t bounce = 1;; ++bounce) {
            const std::optional<Hit> hit = intersect(origin, direction);
            if (!hit) {
                sum += throughput * skyRadiance(direction);
                break;
            }
            if (hit->geometricNormal == glm::dvec3(0.0)) break;   // a back face: sends nothing
            sum += throughput * (hit->emission + hit->albedo * (1.0 / kPi) * directIrradiance(*hit));
            if (bounce >= maxBounces) break;
            // albedo / pi x cosine / (cosine / pi): a cosine-distributed direction carries albedo.
            throughput *= hit->albedo;
            if (bounces == 0 && bounce >= kRouletteFrom) {
                const double keep = std::min(0.95, std::max({throughput.r, throughput.g, throughput.b}));
                if (!(random.uniform() < keep)) break;
                throughput /= keep;
            }
            if (std::max({throughput.r, throughput.g, throughput.b}) <= 0.0) break;
            origin = offsetFrom(*hit);
            direction = cosineDirection(hit->normal, random.uniform(), random.uniform());
            // A shading normal bent far from the geometric one can point a direction into the surface.
            if (glm::dot(direction, hit->geometricNormal) <= 0.0) break;
        }
        return sum;
    }
};

namespace {

void checkBounces(uint32_t bounces) {
    if (bounces > kGiReferenceMaxBounces)
        throw RendererError(fmt::format("GI reference: {} bounces; at most {} (0 = converged)", bounces, kGiReferenceMaxBounces));
}

}  // namespace

GiReference::GiReference(const Scene& scene) : m_impl(std::make_unique<Impl>()) {
    Impl& impl = *m_impl;
    impl.device = rtcNewDevice(nullptr);
    if (!impl.device) throw RendererError(fmt::format("GI reference: Embree device creation failed (error {})", int(rtcGetDeviceError(nullptr))));
    impl.scene = rtcNewScene(impl.device);
    rtcSetSceneBuildQuality(impl.scene, RTC_BUILD_QUALITY_HIGH);

    impl.materials = scene.materials;
    impl.textures.reserve(scene.textures.size());
    for (const TextureImage& image : scene.textures) impl.textures.emplace_back(image);

    glm::dvec3 lo(std::numeric_limits<double>::max()), hi(-std::numeric_limits<double>::max());
    // The shadow filters point into these: no reallocation once geometries are attached.
    impl.meshes.reserve(scene.instances.size());
    impl.meshPositions.reserve(scene.instances.size());
    for (const Instance& instance : scene.instances) {
        if (instance.mesh >= scene.meshes.size()) continue;
        const Mesh& mesh = scene.meshes[instance.mesh];
        if (mesh.material >= 0 && size_t(mesh.material) < scene.materials.size() &&
            scene.materials[size_t(mesh.material)].alphaMode == AlphaMode::Blend)
            continue;
        if (mesh.topology != MeshTopology::Triangles || mesh.indices.size() < 3 || mesh.vertices.empty()) continue;   // points and lines: no area
        TraceMesh trace;
        const glm::dmat4 world(instance.world);
        const glm::dmat3 normalMatrix = glm::transpose(glm::inverse(glm::dmat3(world)));
        trace.frontSign = glm::determinant(glm::dmat3(world)) < 0.0 ? -1.0 : 1.0;
        trace.renderingLayers = instance.renderingLayers;
        trace.material = mesh.material;
        std::vector<glm::dvec3> positions(mesh.vertices.size());
        trace.normals.resize(mesh.vertices.size());
        trace.uvs.resize(mesh.vertices.size());
        trace.uvs1.resize(mesh.vertices.size());
        trace.colors.resize(mesh.vertices.size());
        trace.unlit = mesh.unlit || (mesh.material >= 0 && size_t(mesh.material) < scene.materials.size() &&
                                     scene.materials[size_t(mesh.material)].unlit);
        for (size_t v = 0; v < mesh.vertices.size(); ++v) {
            positions[v] = glm::dvec3(world * glm::dvec4(glm::dvec3(mesh.vertices[v].position), 1.0));
            const glm::dvec3 n = normalMatrix * glm::dvec3(mesh.vertices[v].normal);
            const double length = glm::length(n);
            trace.normals[v] = length > 1e-30 && std::isfinite(length) ? n / length : glm::dvec3(0.0);
            trace.uvs[v] = glm::dvec2(mesh.vertices[v].uv);
            trace.uvs1[v] = glm::dvec2(mesh.vertices[v].uv1);
            trace.colors[v] = glm::dvec4(mesh.vertices[v].color);
            lo = glm::min(lo, positions[v]);
            hi = glm::max(hi, positions[v]);
        }
        const size_t triangles = mesh.indices.size() / 3;
        trace.indices.assign(mesh.indices.begin(), mesh.indices.begin() + triangles * 3);

        RTCGeometry geometry = rtcNewGeometry(impl.device, RTC_GEOMETRY_TYPE_TRIANGLE);
        auto* vertices = static_cast<float*>(
            rtcSetNewGeometryBuffer(geometry, RTC_BUFFER_TYPE_VERTEX, 0, RTC_FORMAT_FLOAT3, 3 * sizeof(float), positions.size()));
        auto* indices = static_cast<uint32_t*>(
            rtcSetNewGeometryBuffer(geometry, RTC_BUFFER_TYPE_INDEX, 0, RTC_FORMAT_UINT3, 3 * sizeof(uint32_t), triangles));
        if (!vertices || !indices) {
            rtcReleaseGeometry(geometry);
            throw RendererError(fmt::format("GI reference: Embree could not allocate mesh {} (error {})", instance.mesh,
                                            int(rtcGetDeviceError(impl.device))));
        }
        for (size_t v = 0; v < positions.size(); ++v)
            for (int c = 0; c < 3; ++c) vertices[v * 3 + c] = float(positions[v][c]);
        std::copy(trace.indices.begin(), trace.indices.end(), indices);
        const Material* material =
            mesh.material >= 0 && size_t(mesh.material) < impl.materials.size() ? &impl.materials[size_t(mesh.material)] : nullptr;
        const bool doubleSided = material && material->doubleSided;
        const bool masked = material && material->alphaMode == AlphaMode::Mask;
        impl.meshPositions.push_back(std::move(positions));
        // Pointers into impl's lists, which do not grow past their reserve (meshes) or at all
        // (materials, textures) from here on.
        impl.meshes.push_back(std::move(trace));
        if (!doubleSided || masked) {
            impl.filters.push_back(std::make_unique<GeometryFilterData>());
            GeometryFilterData& filter = *impl.filters.back();
            filter.positions = &impl.meshPositions.back();
            filter.mesh = &impl.meshes.back();
            filter.frontSign = impl.meshes.back().frontSign;
            filter.singleSided = !doubleSided;
            filter.masked = masked;
            filter.material = material;
            if (masked && material->baseColorTexture >= 0 && size_t(material->baseColorTexture) < impl.textures.size())
                filter.baseColorTexture = &impl.textures[size_t(material->baseColorTexture)];
            rtcSetGeometryUserData(geometry, &filter);
            rtcSetGeometryOccludedFilterFunction(geometry, passWhereLightMeetsABackFaceOrCutOut);
            if (masked) rtcSetGeometryIntersectFilterFunction(geometry, passWhereCutOut);
        }
        rtcCommitGeometry(geometry);
        const unsigned id = rtcAttachGeometry(impl.scene, geometry);
        rtcReleaseGeometry(geometry);
        if (id + 1 != impl.meshes.size()) throw RendererError("GI reference: Embree gave an unexpected geometry id");
    }
    rtcCommitScene(impl.scene);
    if (const RTCError error = rtcGetDeviceError(impl.device); error != RTC_ERROR_NONE)
        throw RendererError(fmt::format("GI reference: Embree failed to build the scene (error {})", int(error)));
    if (!impl.meshes.empty()) impl.epsilon = 1e-5 * std::max(1.0, glm::length(hi - lo));

    for (const Light& light : scene.lights) {
        if (light.type != LightType::Directional) continue;
        const double length = glm::length(glm::dvec3(light.direction));
        if (!(length > 0.0)) continue;
        impl.directional.push_back({-glm::dvec3(light.direction) / length, glm::dvec3(light.color) * double(light.intensity), light.renderingLayers});
    }
    // Cut-off 0: a light without a glTF range reaches everywhere (inverse square), as glTF says.
    impl.local = packLocalLights(scene, 0.0f).lights;

    const Environment& environment = scene.environment;
    if (!environment.map.empty()) impl.sky = readEnvironmentMap(environment.map);
    else if (environment.image) impl.sky = *environment.image;
    impl.skyIntensity = environment.intensity;
    impl.ambient = glm::dvec3(environment.ambientColor);
}

GiReference::~GiReference() = default;

glm::dvec3 GiReference::incidentRadiance(const glm::vec3& origin, const glm::vec3& direction, uint32_t bounces, uint64_t seed) const {
    checkBounces(bounces);
    Random random(seed, 0);
    return m_impl->trace(glm::dvec3(origin), glm::normalize(glm::dvec3(direction)), bounces, random);
}

std::vector<GiReferenceProbe> GiReference::probes(std::span<const glm::vec3> positions, const GiReferenceSettings& settings) const {
    checkBounces(settings.bounces);
    if (settings.directionsPerProbe == 0) throw RendererError("GI reference: 0 directions per probe");
    const std::vector<glm::vec3> directions = giSampleDirections(settings.directionsPerProbe);
    std::vector<std::array<double, 9>> basis(directions.size());
    for (size_t i = 0; i < directions.size(); ++i) basis[i] = shBasis(glm::dvec3(directions[i]));
    const double weight = 4.0 * kPi / double(directions.size());

    std::vector<GiReferenceProbe> result(positions.size());
    parallelFor(positions.size(), parallelThreads(settings.threads, positions.size()), [&](size_t p) {
        Random random(settings.seed, p + 1);
        ShRgb radiance{};
        for (size_t i = 0; i < directions.size(); ++i) {
            const glm::dvec3 l = m_impl->trace(glm::dvec3(positions[p]), glm::dvec3(directions[i]), settings.bounces, random);
            for (size_t k = 0; k < 9; ++k) radiance[k] += l * (basis[i][k] * weight);
        }
        const ShRgb irradiance = shConvolveIrradiance(radiance);
        result[p].position = positions[p];
        for (size_t k = 0; k < 9; ++k) {
            result[p].radianceSh[k] = radiance[k];
            result[p].irradianceSh[k] = irradiance[k];
        }
    });
    return result;
}

ImageRGBAF GiReference::indirectIrradiance(const Camera& camera, uint32_t width, uint32_t height, const GiReferenceSettings& settings) const {
    checkBounces(settings.bounces);
    if (width == 0 || height == 0) throw RendererError(fmt::format("GI reference: image size {}x{}", width, height));
    if (settings.samplesPerPixel == 0) throw RendererError("GI reference: 0 samples per pixel");
    const glm::dmat4 inverseViewProjection = glm::inverse(glm::dmat4(makeProjection(camera, width, height)) * glm::dmat4(makeView(camera)));
    ImageRGBAF image{width, height, std::vector<float>(size_t(width) * height * 4, 0.0f)};
    const double goldenRatio = 0.6180339887498949;
    parallelFor(height, parallelThreads(settings.threads, height), [&](size_t y) {
        for (uint32_t x = 0; x < width; ++x) {
            Random random(settings.seed, (uint64_t(y) * width + x) + (uint64_t(1) << 40));
            const std::optional<Hit> hit = m_impl->intersectPixel(inverseViewProjection, x, y, width, height);
            if (!hit || hit->geometricNormal == glm::dvec3(0.0)) continue;
            // Irradiance / pi = the mean of cosine-distributed radiance; a randomly shifted
            // Fibonacci lattice stratifies the samples over the hemisphere.
            const glm::dvec3 start = m_impl->offsetFrom(*hit);
            const double shift1 = random.uniform(), shift2 = random.uniform();
            glm::dvec3 sum(0.0);
            for (uint32_t s = 0; s < settings.samplesPerPixel; ++s) {
                const double u1 = std::fmod((s + shift1) / settings.samplesPerPixel, 1.0);
                const double u2 = std::fmod(s * goldenRatio + shift2, 1.0);
                const glm::dvec3 d = cosineDirection(hit->normal, u1, u2);
                if (glm::dot(d, hit->geometricNormal) <= 0.0) continue;
                sum += m_impl->trace(start, d, settings.bounces, random);
            }
            const glm::dvec3 value = sum / double(settings.samplesPerPixel);
            float* out = &image.pixels[(size_t(y) * width + x) * 4];
            out[0] = float(value.r), out[1] = float(value.g), out[2] = float(value.b), out[3] = 1.0f;
        }
    });
    return image;
}

ImageRGBAF GiReference::lightVisibility(const Camera& camera, uint32_t width, uint32_t height, const glm::vec3& lightDirection,
                                        uint32_t threads) const {
    if (width == 0 || height == 0) throw RendererError(fmt::format("shadow reference: image size {}x{}", width, height));
    const double length = glm::length(glm::dvec3(lightDirection));
    if (!(length > 0.0) || !std::isfinite(length))
        throw RendererError(fmt::format("shadow reference: the light direction ({}, {}, {}) is not a direction", lightDirection.x,
                                        lightDirection.y, lightDirection.z));
    const glm::dvec3 towardLight = -glm::dvec3(lightDirection) / length;
    const glm::dmat4 inverseViewProjection = glm::inverse(glm::dmat4(makeProjection(camera, width, height)) * glm::dmat4(makeView(camera)));
    ImageRGBAF image{width, height, std::vector<float>(size_t(width) * height * 4, 0.0f)};
    parallelFor(height, parallelThreads(threads, height), [&](size_t y) {
        for (uint32_t x = 0; x < width; ++x) {
            const std::optional<Hit> hit = m_impl->intersectPixel(inverseViewProjection, x, y, width, height);
            if (!hit || hit->geometricNormal == glm::dvec3(0.0) || glm::dot(hit->geometricNormal, towardLight) <= 0.0) continue;
            const bool lit = !m_impl->occluded(m_impl->offsetFrom(*hit), towardLight, std::numeric_limits<double>::infinity());
            float* out = &image.pixels[(size_t(y) * width + x) * 4];
            out[0] = out[1] = out[2] = lit ? 1.0f : 0.0f;
            out[3] = 1.0f;
        }
    });
    return image;
}

namespace {

struct ErrorAccumulator {
    double squared = 0.0, reference = 0.0, maxAbsolute = 0.0;
    double channelDifference = 0.0, channelReference = 0.0;
    uint64_t count = 0;
    void add(const glm::dvec3& value, const glm::dvec3& expected) {
        const double difference = glm::length(value - expected);
        squared += difference * difference;
        reference += glm::length(expected);
        channelDifference += (value.x - expected.x) + (value.y - expected.y) + (value.z - expected.z);
        channelReference += expected.x + expected.y + expected.z;
        maxAbsolute = std::max(maxAbsolute, difference);
        ++count;
    }
    GiError result() const {
        GiError error;
        error.compared = count;
        error.maxAbsolute = maxAbsolute;
        if (count > 0) {
            const double meanReference = reference / double(count);
            const double rms = std::sqrt(squared / double(count));
            error.relativeRmse = meanReference > 0.0 ? rms / meanReference : (rms > 0.0 ? std::numeric_limits<double>::infinity() : 0.0);
            error.relativeBias = channelReference > 0.0 ? channelDifference / channelReference
                                 : channelDifference == 0.0 ? 0.0
                                                            : std::copysign(std::numeric_limits<double>::infinity(), channelDifference);
        }
        return error;
    }
};

}  // namespace

GiError compareProbeIrradiance(std::span<const IrradianceProbe> probes, std::span<const GiReferenceProbe> reference, uint32_t normals) {
    if (probes.size() != reference.size())
        throw RendererError(fmt::format("GI reference: {} probes to compare with {} reference probes", probes.size(), reference.size()));
    const std::vector<glm::vec3> directions = giSampleDirections(std::max(1u, normals));
    ErrorAccumulator accumulator;
    for (size_t p = 0; p < probes.size(); ++p) {
        if (!probes[p].valid) continue;
        ShRgb rendered{}, expected{};
        for (size_t k = 0; k < 9; ++k) {
            rendered[k] = glm::dvec3(probes[p].sh[k]);
            expected[k] = reference[p].irradianceSh[k];
        }
        for (const glm::vec3& n : directions)
            accumulator.add(shEvaluateIrradiance(rendered, glm::dvec3(n)), shEvaluateIrradiance(expected, glm::dvec3(n)));
    }
    return accumulator.result();
}

GiError compareIndirectImage(const ImageRGBAF& rendered, const ImageRGBAF& reference) {
    if (rendered.width != reference.width || rendered.height != reference.height || rendered.pixels.size() != reference.pixels.size())
        throw RendererError(fmt::format("GI reference: a {}x{} image to compare with a {}x{} reference", rendered.width,
                                        rendered.height, reference.width, reference.height));
    ErrorAccumulator accumulator;
    for (size_t i = 0; i + 3 < reference.pixels.size(); i += 4) {
        if (reference.pixels[i + 3] < 0.5f) continue;
        accumulator.add(glm::dvec3(rendered.pixels[i], rendered.pixels[i + 1], rendered.pixels[i + 2]),
                        glm::dvec3(reference.pixels[i], reference.pixels[i + 1], reference.pixels[i + 2]));
    }
    return accumulator.result();
}

VisibilityError compareVisibility(const ImageRGBAF& rendered, const ImageRGBAF& reference) {
    if (rendered.width != reference.width || rendered.height != reference.height || rendered.pixels.size() != reference.pixels.size())
        throw RendererError(fmt::format("shadow reference: a {}x{} image to compare with a {}x{} reference", rendered.width,
                                        rendered.height, reference.width, reference.height));
    VisibilityError error;
    double absolute = 0.0, squared = 0.0;
    uint64_t leaks = 0, falseShadows = 0;
    for (size_t i = 0; i + 3 < reference.pixels.size(); i += 4) {
        if (reference.pixels[i + 3] < 0.5f) continue;
        const double expected = reference.pixels[i], value = rendered.pixels[i];
        const double difference = std::isfinite(value) ? std::abs(value - expected) : 1.0;
        absolute += difference;
        squared += difference * difference;
        if (expected < 0.5 && !(value <= 0.5)) ++leaks;
        if (expected >= 0.5 && !(value >= 0.5)) ++falseShadows;
        ++error.compared;
    }
    if (error.compared == 0) return error;
    const double n = double(error.compared);
    error.meanAbsolute = absolute / n;
    error.rmse = std::sqrt(squared / n);
    error.leakFraction = double(leaks) / n;
    error.falseShadowFraction = double(falseShadows) / n;
    error.wrongFraction = error.leakFraction + error.falseShadowFraction;
    return error;
}

}  // namespace janus::renderer
