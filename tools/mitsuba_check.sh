#!/usr/bin/env bash
# The cross-check of the physical truth against Mitsuba 3 (docs/references.md): renders
# tools/mitsuba_check.toml, whose cells export the scene as their truth traces it, then renders
# each in Mitsuba with the same BSDF and Z-tests the two (tools/mitsuba_check.py). Exit 1 when a
# case disagrees beyond noise. Needs python3 with venv; Mitsuba's LLVM variant needs libLLVM ≥ 16
# (Debian: libllvm19), found through DRJIT_LIBLLVM_PATH.
set -euo pipefail
cd "$(dirname "$0")/.."

venv="${MITSUBA_VENV:-target/mitsuba-venv}"
if ! "$venv/bin/python" -c "import mitsuba, numpy" 2>/dev/null; then
  python3 -m venv "$venv"
  "$venv/bin/pip" install --quiet --disable-pip-version-check "mitsuba==3.9.1" "numpy>=1.26,<3"
fi
if [ -z "${DRJIT_LIBLLVM_PATH:-}" ]; then
  for lib in /usr/lib/x86_64-linux-gnu/libLLVM.so.{22,21,20,19,18,17,16}*; do
    if [ -e "$lib" ]; then export DRJIT_LIBLLVM_PATH="$lib"; break; fi
  done
fi

# Release: the check prints the truth's paths per second beside Mitsuba's.
cargo build --release --quiet
out="${1:-target/mitsuba-check}"
rm -rf "$out"
./target/release/shadematrix run tools/mitsuba_check.toml --out "$out" --no-cache
"$venv/bin/python" tools/mitsuba_check.py "$out"
