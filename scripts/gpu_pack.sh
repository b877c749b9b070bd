#!/usr/bin/env bash
# Packs a build for the GPU machine in the form scripts/gpu_check.sh takes there:
#   bash scripts/gpu_pack.sh [BUILD_DIR=build]
# then device `run` with carry [".gpu-pack"] and `bash scripts/gpu_check.sh --out "$OUT"`.
#
# ../shared/gpu/pack.sh makes .gpu (binaries, loaders, layer, scenes, run.sh last). It can stop
# early with status 141 (SIGPIPE: `ldconfig -p | awk '... exit'` under pipefail), leaving a .gpu
# without run.sh, which costs a device call to find out; so it is retried until run.sh is there.
# .gpu is over the device's 64 MiB, so it travels compressed as .gpu-pack/gpu.tar.gz, with the
# commit it was built at in .gpu-pack/commit ("+dirty" when the tree had changes).
set -euo pipefail

repo_root="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
cd "$repo_root"
build_dir="${1:-build}"
[[ -x "$build_dir/apps/janus/janus" ]] || { echo "gpu_pack.sh: no $build_dir/apps/janus/janus: build first (cmake --build $build_dir)" >&2; exit 2; }
[[ -f ../shared/gpu/pack.sh ]] || { echo "gpu_pack.sh: no ../shared/gpu/pack.sh on this machine" >&2; exit 2; }

for try in 1 2 3 4 5 6; do
  status=0
  bash ../shared/gpu/pack.sh "$build_dir" .gpu > /tmp/janus-gpu-pack.log 2>&1 || status=$?
  [[ $status == 0 && -f .gpu/run.sh ]] && break
  echo "gpu_pack.sh: pack.sh try $try ended with status $status$([[ -f .gpu/run.sh ]] || echo ', no .gpu/run.sh'); again" >&2
done
[[ -f .gpu/run.sh ]] || { echo "gpu_pack.sh: pack.sh never finished; its last log: /tmp/janus-gpu-pack.log" >&2; exit 1; }
# pack.sh takes janus and janus_* programs; the examples (examples/) run there too. They need no
# library janus does not (both link the same static libraries).
for example in hello_rhi render_scene; do
  [[ -x "$build_dir/examples/$example/$example" ]] && strip -o ".gpu/bin/$example" "$build_dir/examples/$example/$example"
done

rm -rf .gpu-pack
mkdir -p .gpu-pack
commit="$(git rev-parse --short HEAD)"
[[ -z "$(git status --porcelain --untracked-files=no)" ]] || commit+="+dirty"
echo "$commit" > .gpu-pack/commit
tar -czf .gpu-pack/gpu.tar.gz .gpu
echo "gpu_pack.sh: .gpu-pack holds the build of $commit ($(du -sh .gpu-pack | cut -f1)); carry [\".gpu-pack\"]"
