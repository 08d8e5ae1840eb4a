#!/usr/bin/env bash
# The GPU measurement in one command, for a machine with a GPU (docs/performance.md): the main job
# cold, then `bench` on bench.toml and on thesis.toml whole, each printing its cells/s, its stage
# table and the stage that bounds it. Results go to OUT (default target/gpu-measure): the run
# folders and summary.md, which gathers the figures.
#
#   tools/gpu_measure.sh [OUT]
#
# SHADEMATRIX=path runs a binary built elsewhere (the GPU machine may have no Rust toolchain);
# otherwise it is built here. Only a run on a GPU adapter counts: on a CPU adapter (lavapipe) the
# script stops with exit 2 unless ALLOW_CPU=1. THESIS=0 leaves thesis.toml out (65 988 rendered
# cells: minutes on a GPU, hours on a CPU).
set -euo pipefail
cd "$(dirname "$0")/.."

out="${1:-target/gpu-measure}"
bin="${SHADEMATRIX:-}"
if [ -z "$bin" ]; then
  cargo build --release --quiet
  bin=target/release/shadematrix
fi
if ! ldconfig -p 2>/dev/null | grep -q libvulkan; then
  echo "gpu_measure: no Vulkan loader (libvulkan1) on this machine: install it, or unpack its package" >&2
  exit 2
fi
# A container's NVIDIA driver ships its Vulkan ICD outside the loader's default search path.
for icd in /usr/local/nvidia/share/vulkan/icd.d/nvidia_icd.json /usr/share/vulkan/icd.d/nvidia_icd.json; do
  if [ -z "${VK_DRIVER_FILES:-}" ] && [ -e "$icd" ]; then export VK_DRIVER_FILES="$icd"; fi
done
export XDG_RUNTIME_DIR="${XDG_RUNTIME_DIR:-$(mktemp -d)}"

rm -rf "$out"
mkdir -p "$out"
summary="$out/summary.md"
{
  echo "# GPU measurement"
  echo
  echo "$(date -u +%Y-%m-%dT%H:%M:%SZ), $(git rev-parse --short HEAD 2>/dev/null || echo unknown), $(nproc) cores"
  echo
} >"$summary"

# The main job, both caches empty.
start=$(date +%s.%N)
"$bin" run --no-cache --out "$out/main-job" | tail -n 2
end=$(date +%s.%N)
record=$(tr -d '\n' <"$out/main-job/run.json" | grep -o '"adapter": *{[^}]*}' | head -n 1)
adapter=$(grep -o '"device_type": *"[A-Za-z]*"' <<<"$record" | cut -d'"' -f4)
name=$(grep -o '"name": *"[^"]*"' <<<"$record" | cut -d'"' -f4)
printf '## Main job (cold)\n\n%.1f s wall on %s (%s)\n\n' "$(echo "$end - $start" | bc)" "$name" "$adapter" >>"$summary"
if [ "$adapter" = Cpu ] && [ "${ALLOW_CPU:-0}" != 1 ]; then
  cat "$summary"
  echo "gpu_measure: the adapter is a CPU ($name): set ALLOW_CPU=1 to measure it anyway" >&2
  exit 2
fi

matrices=(matrices/bench.toml)
if [ "${THESIS:-1}" != 0 ]; then matrices+=(matrices/thesis.toml); fi
for m in "${matrices[@]}"; do
  name=$(basename "$m" .toml)
  "$bin" bench "$m" --out "$out/bench-$name" >/dev/null
  cat "$out/bench-$name/tables/bench.md" >>"$summary"
  echo >>"$summary"
done
cat "$summary"
