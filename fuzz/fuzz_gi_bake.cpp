// GI bake files (docs/GI.md, "Bake files") through parseGiBakeFile, past the checks a random input
// never passes: the input's scene hash is taken as the scene's, its trailing checksum is made to
// hold, and the volume asked for is the one its header names. So every input reaches the counts,
// the records and the value checks. Any input parses or throws GiBakeFileError.
#include <cstdint>
#include <cstring>
#include <string>

#define XXH_INLINE_ALL
#include <xxhash.h>

#include "gi/gi_bake_file.h"
#include "janus/renderer/settings.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
    using namespace janus::renderer;
    std::string bytes(reinterpret_cast<const char*>(data), size);
    // Header: magic (8), version (4), scene hash (8), settings: bounds (24), probe counts (12),
    // surfels per probe (4), ...
    uint64_t hash = 0;
    IrradianceVolume volume;
    if (bytes.size() >= 20) std::memcpy(&hash, bytes.data() + 12, 8);
    if (bytes.size() >= 60) {
        std::memcpy(&volume.probeCounts, bytes.data() + 44, 12);
        std::memcpy(&volume.surfelsPerProbe, bytes.data() + 56, 4);
    }
    if (bytes.size() >= 16) {
        const uint64_t checksum = XXH3_64bits(bytes.data(), bytes.size() - 8);
        std::memcpy(bytes.data() + bytes.size() - 8, &checksum, 8);
    }
    try {
        parseGiBakeFile(bytes, "fuzz.bake", volume, hash);
    } catch (const GiBakeFileError&) {
    }
    return 0;
}
