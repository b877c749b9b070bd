#!/usr/bin/env bash
# Installs every Debian package Janus needs to build, render and test. Idempotent: packages
# already present are not touched, so a second run costs one dpkg query.
#
#   scripts/setup.sh          what build, test and CI need
#   scripts/setup.sh --fuzz   also clang and libFuzzer (scripts/fuzz.sh). Only fuzzing needs them, so
#                             CI's setup does not install them. scripts/sanitize.sh needs nothing
#                             extra: it builds with gcc, whose ASan/UBSan runtimes come with gcc.
set -euo pipefail

fuzz=0
for arg in "$@"; do
  case $arg in
    --fuzz) fuzz=1 ;;
    *) echo "usage: scripts/setup.sh [--fuzz]" >&2; exit 2 ;;
  esac
done

packages=(
  build-essential cmake ninja-build pkg-config ccache
  # Vulkan: loader, lavapipe (software ICD), validation layers, tools for diagnostics
  libvulkan-dev mesa-vulkan-drivers vulkan-validationlayers vulkan-tools
  # OpenGL / OpenGL ES: EGL (surfaceless via Mesa), GLES headers, llvmpipe. OSMesa only at run time
  # (the GL backend loads it with dlopen; the gl_osmesa tests and --gl-platform osmesa need it)
  libegl-dev libegl-mesa0 libgles-dev libgl-dev libosmesa6 libgl1-mesa-dri mesa-utils
  # Shaders: GLSL -> SPIR-V (glslang), SPIR-V -> GLSL/ESSL (SPIRV-Cross), validator
  glslang-tools glslang-dev spirv-cross libspirv-cross-c-shared-dev spirv-tools
  # Libraries
  libglm-dev libtinygltf-dev libstb-dev nlohmann-json3-dev libtinyexr-dev
  # JPEG textures: libjpeg-turbo's TurboJPEG API (stb_image decodes PNG and Radiance HDR)
  libturbojpeg0-dev
  libgtest-dev libgmock-dev libbenchmark-dev libfmt-dev
  # xxHash (header-only use, XXH_INLINE_ALL): scene content hashes and checksums of GI bake files
  libxxhash-dev
  # Embree 3: the CPU ray tracer of the GI reference path tracer (renderer/src/gi/gi_reference.*)
  libembree-dev
  # CLI: command-line parsing for apps/janus
  libcli11-dev
)
if ((fuzz)); then
  # clang with libFuzzer and the ASan/UBSan runtimes (libclang-rt-dev), llvm-symbolizer (llvm) for
  # readable reports, zlib for the EXR decoder the fuzz build compiles from source (fuzz/CMakeLists.txt).
  packages+=(clang libclang-rt-dev llvm zlib1g-dev)
fi

missing=()
for p in "${packages[@]}"; do
  dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed" || missing+=("$p")
done

if ((${#missing[@]} == 0)); then
  echo "setup: all ${#packages[@]} packages present"
  exit 0
fi

echo "setup: installing ${missing[*]}"
SUDO=""
if [[ $(id -u) -ne 0 ]]; then
  command -v sudo >/dev/null || { echo "setup: need root (or sudo) to install: ${missing[*]}" >&2; exit 1; }
  SUDO="sudo"
fi
export DEBIAN_FRONTEND=noninteractive
$SUDO apt-get update -qq
$SUDO apt-get install -y -qq --no-install-recommends "${missing[@]}"
echo "setup: done"
