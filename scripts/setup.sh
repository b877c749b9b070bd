#!/usr/bin/env bash
# Installs every Debian package Janus needs to build, render and test. Idempotent: packages
# already present are not touched, so a second run costs one dpkg query.
set -euo pipefail

packages=(
  build-essential cmake ninja-build pkg-config ccache
  # Vulkan: loader, lavapipe (software ICD), validation layers, tools for diagnostics
  libvulkan-dev mesa-vulkan-drivers vulkan-validationlayers vulkan-tools
  # OpenGL / OpenGL ES: EGL (surfaceless via Mesa), OSMesa, GLES headers, llvmpipe
  libegl-dev libegl-mesa0 libgles-dev libgl-dev libosmesa6-dev libgl1-mesa-dri mesa-utils
  # Shaders: GLSL -> SPIR-V (glslang), SPIR-V -> GLSL/ESSL (SPIRV-Cross), validator
  glslang-tools glslang-dev spirv-cross libspirv-cross-c-shared-dev spirv-tools
  # Libraries
  libglm-dev libtinygltf-dev libstb-dev nlohmann-json3-dev libtinyexr-dev
  libgtest-dev libgmock-dev libbenchmark-dev libfmt-dev
  # xxHash (header-only use, XXH_INLINE_ALL): scene content hashes and checksums of GI bake files
  libxxhash-dev
  # CLI: command-line parsing for apps/janus
  libcli11-dev
)

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
