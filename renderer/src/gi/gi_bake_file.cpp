// GI bake files (gi_bake_file.h).
#include "gi/gi_bake_file.h"

#include <cmath>
#include <cstring>
#include <fstream>
#include <iterator>
#include <string>
#include <type_traits>

#include <fmt/format.h>
#define XXH_INLINE_ALL
#include <xxhash.h>

#include "janus/renderer/image.h"
#include "janus/renderer/settings.h"

namespace janus::renderer {

namespace {

constexpr char kMagic[8] = {'J', 'A', 'N', 'U', 'S', 'G', 'I', '\0'};

// Hashes values field by field (never struct bytes: padding would make equal scenes differ).
class Hasher {
public:
    Hasher() { XXH3_64bits_reset(&m_state); }
    template <class T>
    void add(const T& value) {
        static_assert(std::is_arithmetic_v<T>);
        XXH3_64bits_update(&m_state, &value, sizeof(T));
    }
    void add(const glm::vec2& v) { add(v.x), add(v.y); }
    void add(const glm::vec3& v) { add(v.x), add(v.y), add(v.z); }
    void add(const glm::vec4& v) { add(v.x), add(v.y), add(v.z), add(v.w); }
    void add(const glm::mat4& m) {
        for (int c = 0; c < 4; ++c) add(m[c]);
    }
    void bytes(const void* data, size_t size) {
        add(uint64_t(size));
        XXH3_64bits_update(&m_state, data, size);
    }
    uint64_t digest() const { return XXH3_64bits_digest(&m_state); }

private:
    XXH3_state_t m_state{};
};

void hashBakeSettings(Hasher& h, const IrradianceVolume& v) {
    h.add(v.bounds.min), h.add(v.bounds.max);
    h.add(v.probeCounts.x), h.add(v.probeCounts.y), h.add(v.probeCounts.z);
    h.add(v.surfelsPerProbe), h.add(v.brickSize), h.add(uint8_t(v.bricks)), h.add(v.nearPlane), h.add(v.farPlane);
    h.add(v.invalidBackFaceFraction), h.add(v.maxSurfelsPerBrick), h.add(uint8_t(v.relocateProbes));
}

class Writer {
public:
    template <class T>
    void add(const T& value) {
        static_assert(std::is_arithmetic_v<T>);
        const char* p = reinterpret_cast<const char*>(&value);
        m_bytes.append(p, sizeof(T));
    }
    void add(const glm::vec3& v) { add(v.x), add(v.y), add(v.z); }
    void addSettings(const IrradianceVolume& v) {
        add(v.bounds.min), add(v.bounds.max);
        add(v.probeCounts.x), add(v.probeCounts.y), add(v.probeCounts.z);
        add(v.surfelsPerProbe), add(v.brickSize), add(uint8_t(v.bricks)), add(v.nearPlane), add(v.farPlane);
        add(v.invalidBackFaceFraction), add(v.maxSurfelsPerBrick), add(uint8_t(v.relocateProbes));
    }
    std::string& bytes() { return m_bytes; }

private:
    std::string m_bytes;
};

class Reader {
public:
    Reader(const std::filesystem::path& path, const std::string& bytes, size_t end) : m_path(path), m_bytes(bytes), m_end(end) {}
    template <class T>
    T get() {
        static_assert(std::is_arithmetic_v<T>);
        if (m_offset + sizeof(T) > m_end) truncated();
        T value;
        std::memcpy(&value, m_bytes.data() + m_offset, sizeof(T));
        m_offset += sizeof(T);
        return value;
    }
    glm::vec3 vec3() {
        glm::vec3 v;
        v.x = get<float>(), v.y = get<float>(), v.z = get<float>();
        return v;
    }
    IrradianceVolume settings() {
        IrradianceVolume v;
        v.bounds.min = vec3(), v.bounds.max = vec3();
        v.probeCounts.x = get<uint32_t>(), v.probeCounts.y = get<uint32_t>(), v.probeCounts.z = get<uint32_t>();
        v.surfelsPerProbe = get<uint32_t>(), v.brickSize = get<float>(), v.bricks = get<uint8_t>() != 0;
        v.nearPlane = get<float>(), v.farPlane = get<float>(), v.invalidBackFaceFraction = get<float>();
        v.maxSurfelsPerBrick = get<uint32_t>();
        v.relocateProbes = get<uint8_t>() != 0;
        return v;
    }
    size_t offset() const { return m_offset; }
    [[noreturn]] void truncated() const {
        throw GiBakeFileError(fmt::format("GI bake file {}: truncated ({} bytes where its header needs more); bake it again with janus bake",
                                        m_path.string(), m_bytes.size()));
    }

private:
    const std::filesystem::path& m_path;
    const std::string& m_bytes;
    size_t m_end;
    size_t m_offset = 0;
};

constexpr size_t kProbeBytes = 12 + 4 + 1 + 4 + 4;
constexpr size_t kSurfelBytes = 5 * 12 + 4;
constexpr size_t kBrickBytes = 4 + 4 + 1 + 12;
constexpr size_t kTransferBytes = 4 + 9 * 4;

// Values as a bake makes them, so that the relight cannot turn them into NaN or Inf light (which
// it would spread over every probe that sees the brick): finite positions and weights, unit
// normals and sky directions, albedo and back-face fractions in [0, 1], emission >= 0. A
// checksum that holds proves only that the file is what its writer wrote.
void checkGiBakeValues(const GiBake& bake, const std::string& file) {
    auto refuse = [&](const char* item, size_t index, const char* what, const char* problem) {
        throw GiBakeFileError(fmt::format("GI bake file {}: {} {} has {} {}; bake it again with janus bake", file, item, index, what, problem));
    };
    auto finite = [](const glm::vec3& v) { return std::isfinite(v.x) && std::isfinite(v.y) && std::isfinite(v.z); };
    auto unit = [&](const glm::vec3& v) { return finite(v) && std::abs(glm::length(v) - 1.0f) <= 1e-3f; };
    auto inUnitInterval = [](float x) { return x >= 0.0f && x <= 1.0f; };   // false for NaN
    for (size_t p = 0; p < bake.probePositions.size(); ++p) {
        if (!finite(bake.probePositions[p])) refuse("probe", p, "a position", "that is not finite");
        if (!inUnitInterval(bake.backFaceFraction[p])) refuse("probe", p, "a back-face fraction", "outside [0, 1]");
    }
    for (size_t i = 0; i < bake.surfels.size(); ++i) {
        const GiSurfel& s = bake.surfels[i];
        if (!finite(s.position)) refuse("surfel", i, "a position", "that is not finite");
        if (!unit(s.normal)) refuse("surfel", i, "a normal", "that is not a unit vector");
        if (!unit(s.faceNormal)) refuse("surfel", i, "a face normal", "that is not a unit vector");
        if (!(inUnitInterval(s.albedo.r) && inUnitInterval(s.albedo.g) && inUnitInterval(s.albedo.b)))
            refuse("surfel", i, "an albedo", "outside [0, 1]");
        if (!finite(s.emission)) refuse("surfel", i, "an emission", "that is not finite");
        if (s.emission.r < 0.0f || s.emission.g < 0.0f || s.emission.b < 0.0f) refuse("surfel", i, "an emission", "that is negative");
    }
    for (size_t b = 0; b < bake.bricks.size(); ++b)
        if (bake.bricks[b].sky && !unit(bake.bricks[b].skyDirection)) refuse("brick", b, "a sky direction", "that is not a unit vector");
    for (size_t t = 0; t < bake.transfers.size(); ++t)
        for (float weight : bake.transfers[t].sh)
            if (!std::isfinite(weight)) refuse("transfer", t, "a weight", "that is not finite");
    // A mean distance and a mean square: both finite and >= 0, the square at least the mean's
    // square (a weighted mean of squares; float rounding allowed), or the visibility test's variance would be negative.
    for (size_t i = 0; i < bake.distanceMoments.size(); ++i) {
        const glm::vec2 m = bake.distanceMoments[i];
        if (!(std::isfinite(m.x) && std::isfinite(m.y) && m.x >= 0.0f && m.y >= 0.0f))
            refuse("visibility texel", i, "distance moments", "that are negative or not finite");
        if (m.y < m.x * m.x * (1.0f - 1e-4f)) refuse("visibility texel", i, "a mean square distance", "below its mean distance squared");
    }
}

}  // namespace

uint64_t giSceneHash(const Scene& scene) {
    Hasher h;
    h.add(uint64_t(scene.meshes.size()));
    for (const Mesh& mesh : scene.meshes) {
        h.add(mesh.material);
        h.add(uint64_t(mesh.vertices.size()));
        for (const Vertex& v : mesh.vertices) h.add(v.position), h.add(v.normal), h.add(v.uv), h.add(v.uv1);
        h.bytes(mesh.indices.data(), mesh.indices.size() * sizeof(uint32_t));
    }
    h.add(uint64_t(scene.instances.size()));
    for (const Instance& instance : scene.instances) h.add(instance.mesh), h.add(instance.world);
    h.add(uint64_t(scene.materials.size()));
    for (const Material& m : scene.materials) {
        h.add(m.baseColorFactor), h.add(m.metallicFactor), h.add(m.emissiveFactor);
        h.add(m.baseColorTexture), h.add(m.metallicRoughnessTexture), h.add(m.emissiveTexture);
        for (const TextureTransform* t : {&m.baseColorTransform, &m.metallicRoughnessTransform, &m.emissiveTransform})
            h.add(t->offset), h.add(t->rotation), h.add(t->scale), h.add(t->texCoord);
        h.add(uint8_t(m.doubleSided)), h.add(uint8_t(m.alphaMode)), h.add(m.alphaCutoff);
    }
    h.add(uint64_t(scene.textures.size()));
    for (const TextureImage& t : scene.textures) h.add(t.width), h.add(t.height), h.bytes(t.rgba.data(), t.rgba.size());
    if (scene.irradianceVolume) hashBakeSettings(h, *scene.irradianceVolume);
    return h.digest();
}

void writeGiBakeFile(const std::filesystem::path& path, const GiBake& bake, const IrradianceVolume& volume, uint64_t sceneHash) {
    const size_t mapTexels = size_t(kGiVisibilityResolution) * kGiVisibilityResolution;
    if (!bake.distanceMoments.empty() && bake.distanceMoments.size() != bake.probePositions.size() * mapTexels)
        throw RendererError(fmt::format("GI bake file {}: {} distance moments for {} probes of {} texels each", path.string(),
                                        bake.distanceMoments.size(), bake.probePositions.size(), mapTexels));
    Writer w;
    w.bytes().append(kMagic, sizeof(kMagic));
    w.add(kGiBakeFileVersion);
    w.add(sceneHash);
    w.addSettings(volume);
    w.add(uint32_t(bake.probePositions.size())), w.add(uint32_t(bake.surfels.size())), w.add(uint32_t(bake.bricks.size()));
    w.add(uint32_t(bake.transfers.size()));
    w.add(bake.samplesPerProbe);
    const uint32_t visibility = bake.distanceMoments.empty() ? 0 : kGiVisibilityResolution;
    w.add(visibility);
    for (size_t p = 0; p < bake.probePositions.size(); ++p) {
        w.add(bake.probePositions[p]);
        w.add(bake.backFaceFraction[p]);
        w.add(uint8_t(bake.valid[p]));
        w.add(bake.probeFirstTransfer[p]);
        w.add(bake.probeTransferCount[p]);
    }
    for (const GiSurfel& s : bake.surfels)
        w.add(s.position), w.add(s.normal), w.add(s.albedo), w.add(s.emission), w.add(s.faceNormal), w.add(s.renderingLayers);
    for (const GiBrick& b : bake.bricks) w.add(b.firstSurfel), w.add(b.surfelCount), w.add(uint8_t(b.sky)), w.add(b.skyDirection);
    for (const GiTransfer& t : bake.transfers) {
        w.add(t.brick);
        for (float f : t.sh) w.add(f);
    }
    for (const glm::vec2& m : bake.distanceMoments) w.add(m.x), w.add(m.y);
    w.add(uint64_t(XXH3_64bits(w.bytes().data(), w.bytes().size())));
    writeFileAtomically(path, w.bytes());
}

GiBake readGiBakeFile(const std::filesystem::path& path, const IrradianceVolume& volume, uint64_t sceneHash) {
    std::ifstream in(path, std::ios::binary);
    if (!in) throw GiBakeFileError(fmt::format("GI bake file {}: cannot open it (does it exist?); make one with janus bake", path.string()));
    const std::string bytes((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
    return parseGiBakeFile(bytes, path, volume, sceneHash);
}

GiBake parseGiBakeFile(const std::string& bytes, const std::filesystem::path& path, const IrradianceVolume& volume, uint64_t sceneHash) {
    const std::string file = path.string();
    if (bytes.size() < sizeof(kMagic) || std::memcmp(bytes.data(), kMagic, sizeof(kMagic)) != 0)
        throw GiBakeFileError(fmt::format("GI bake file {}: not a Janus GI bake (no JANUSGI header)", file));
    if (bytes.size() < sizeof(kMagic) + 8) throw GiBakeFileError(fmt::format("GI bake file {}: truncated after its header", file));
    Reader r(path, bytes, bytes.size() - 8);   // the checksum trails
    r.get<uint64_t>();                         // the magic, checked above
    const uint32_t version = r.get<uint32_t>();
    if (version != kGiBakeFileVersion)
        throw GiBakeFileError(fmt::format("GI bake file {}: format version {}; this janus reads version {}: bake it again with janus bake",
                                        file, version, kGiBakeFileVersion));
    const uint64_t fileSceneHash = r.get<uint64_t>();
    const IrradianceVolume settings = r.settings();
    const uint64_t probes = r.get<uint32_t>(), surfels = r.get<uint32_t>(), bricks = r.get<uint32_t>(), transfers = r.get<uint32_t>();
    const uint32_t samplesPerProbe = r.get<uint32_t>();
    const uint32_t visibility = r.get<uint32_t>();
    if (visibility != 0 && visibility != kGiVisibilityResolution)
        throw GiBakeFileError(fmt::format("GI bake file {}: visibility maps of {}^2 texels; this janus reads {}^2 (or none): bake it again "
                                        "with janus bake",
                                        file, visibility, kGiVisibilityResolution));
    const uint64_t momentsPerProbe = uint64_t(visibility) * visibility;
    const uint64_t expected = r.offset() + probes * kProbeBytes + surfels * kSurfelBytes + bricks * kBrickBytes +
                              transfers * kTransferBytes + probes * momentsPerProbe * 8 + 8;
    if (bytes.size() != expected)
        throw GiBakeFileError(fmt::format("GI bake file {}: {} bytes where its counts ({} probes, {} surfels, {} bricks, {} transfers) "
                                        "need {}: truncated or damaged; bake it again with janus bake",
                                        file, bytes.size(), probes, surfels, bricks, transfers, expected));
    uint64_t checksum;
    std::memcpy(&checksum, bytes.data() + bytes.size() - 8, 8);
    if (checksum != XXH3_64bits(bytes.data(), bytes.size() - 8))
        throw GiBakeFileError(fmt::format("GI bake file {}: checksum mismatch (the file is damaged); bake it again with janus bake", file));
    if (fileSceneHash != sceneHash)
        throw GiBakeFileError(fmt::format("GI bake file {}: baked from another scene (or the scene's geometry, materials or volume "
                                        "settings changed since); bake this scene with janus bake",
                                        file));
    const uint64_t gridProbes = uint64_t(volume.probeCounts.x) * volume.probeCounts.y * volume.probeCounts.z;
    if (settings.probeCounts != volume.probeCounts || probes != gridProbes || settings.surfelsPerProbe != volume.surfelsPerProbe)
        throw GiBakeFileError(fmt::format("GI bake file {}: baked with {}x{}x{} probes and {} surfels each; the scene asks for {}x{}x{} and {}",
                                        file, settings.probeCounts.x, settings.probeCounts.y, settings.probeCounts.z,
                                        settings.surfelsPerProbe, volume.probeCounts.x, volume.probeCounts.y, volume.probeCounts.z,
                                        volume.surfelsPerProbe));

    GiBake bake;
    bake.probeCounts = volume.probeCounts;
    bake.samplesPerProbe = samplesPerProbe;
    for (uint64_t p = 0; p < probes; ++p) {
        bake.probePositions.push_back(r.vec3());
        bake.backFaceFraction.push_back(r.get<float>());
        bake.valid.push_back(r.get<uint8_t>() != 0);
        bake.probeFirstTransfer.push_back(r.get<uint32_t>());
        bake.probeTransferCount.push_back(r.get<uint32_t>());
    }
    for (uint64_t i = 0; i < surfels; ++i) {
        GiSurfel s;
        s.position = r.vec3(), s.normal = r.vec3(), s.albedo = r.vec3(), s.emission = r.vec3(), s.faceNormal = r.vec3();
        s.renderingLayers = r.get<uint32_t>();
        bake.surfels.push_back(s);
    }
    for (uint64_t i = 0; i < bricks; ++i) {
        GiBrick b;
        b.firstSurfel = r.get<uint32_t>(), b.surfelCount = r.get<uint32_t>(), b.sky = r.get<uint8_t>() != 0, b.skyDirection = r.vec3();
        bake.bricks.push_back(b);
    }
    for (uint64_t i = 0; i < transfers; ++i) {
        GiTransfer t;
        t.brick = r.get<uint32_t>();
        for (float& f : t.sh) f = r.get<float>();
        bake.transfers.push_back(t);
    }
    bake.distanceMoments.resize(probes * momentsPerProbe);
    for (glm::vec2& m : bake.distanceMoments) m.x = r.get<float>(), m.y = r.get<float>();
    // Indices within range, so the relight cannot read past its data (a consistent checksum
    // does not prove a well-formed writer).
    for (uint64_t p = 0; p < probes; ++p)
        if (uint64_t(bake.probeFirstTransfer[p]) + bake.probeTransferCount[p] > transfers)
            throw GiBakeFileError(fmt::format("GI bake file {}: probe {} lists transfers past the end; bake it again", file, p));
    for (const GiBrick& b : bake.bricks)
        if (uint64_t(b.firstSurfel) + b.surfelCount > surfels)
            throw GiBakeFileError(fmt::format("GI bake file {}: a brick lists surfels past the end; bake it again", file));
    for (const GiTransfer& t : bake.transfers)
        if (t.brick >= bricks) throw GiBakeFileError(fmt::format("GI bake file {}: a transfer names brick {} of {}; bake it again", file, t.brick, bricks));
    checkGiBakeValues(bake, file);
    return bake;
}

}  // namespace janus::renderer
