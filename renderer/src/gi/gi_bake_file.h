// GI bake files (internal to the renderer; docs/GI.md, "Bake files"): what `janus bake` writes and
// `janus render --gi-bake` reads, so a renderer need not bake at start-up.
//
// Layout (little-endian, no padding between fields):
//   header   "JANUSGI\0", u32 format version, u64 scene content hash (giSceneHash), the bake
//            settings (bounds, probe counts, surfels per probe, brick size, bricks on/off, planes,
//            invalid back-face fraction, max surfels per brick), u32 counts of probes, surfels, bricks, transfers,
//            u32 samples per probe, u32 visibility map size N (kGiVisibilityResolution, or 0: none)
//   body     per probe: position, back-face fraction, valid, first transfer, transfer count;
//            surfels (position, normal, albedo, emission, face normal, u32 rendering layers); bricks (first surfel, count, sky, sky
//            direction); transfers (brick, 9 SH weights); per probe N^2 distance moments (mean, mean square)
//   trailer  u64 XXH3 checksum of everything before it
// Written atomically (writeFileAtomically). Reading checks, in order: the file opens; the magic;
// the version; the length against the counts; the checksum; the scene hash; the settings. Each
// failure is a RendererError naming the file and what to do.
#pragma once

#include <cstdint>
#include <filesystem>
#include <string>

#include "gi/gi_bake_data.h"
#include "janus/renderer/scene.h"

namespace janus::renderer {

// 2: max surfels per brick in the settings; 3: relocateProbes; 4: surfels' face normals, and their
// positions along their texels' rays (version 3's are off their surfaces at grazing angles);
// 5: surfels' rendering layers; 6: the probes' distance moments (visibility).
inline constexpr uint32_t kGiBakeFileVersion = 6;

// A hash of everything a bake depends on: the meshes, instances, materials and their textures,
// and the volume's bake settings (not its relight or shading settings).
uint64_t giSceneHash(const Scene& scene);

void writeGiBakeFile(const std::filesystem::path& path, const GiBake& bake, const IrradianceVolume& volume, uint64_t sceneHash);
GiBake readGiBakeFile(const std::filesystem::path& path, const IrradianceVolume& volume, uint64_t sceneHash);
// The same checks on a file's bytes (`path` names it in messages): what readGiBakeFile does once
// the file is read, and what fuzz/fuzz_gi_bake.cpp feeds.
GiBake parseGiBakeFile(const std::string& bytes, const std::filesystem::path& path, const IrradianceVolume& volume, uint64_t sceneHash);

}  // namespace janus::renderer
