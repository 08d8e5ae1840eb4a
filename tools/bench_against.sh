#!/usr/bin/env bash
# This tree's speed against another commit's, side by side on this machine, in one command: run it
# before stopping. Builds REV in a worktree under target/against/ (worktree and build kept between
# calls, so a second call against the same REV builds nothing), builds this tree, then runs
# `shadematrix bench MATRIX` with each binary in turn, A (REV) B (this tree) A B …, PAIRS times,
# printing each run's wall time and cells/s and each pair's ratio. Exit 1 when the median ratio
# (this tree's cells/s over REV's) is under 1 − BUDGET: a slowdown beyond the budget needs its
# reason stated (docs/performance.md).
#
#   tools/bench_against.sh REV [--matrix M] [--pairs N] [--budget B]
#
# Defaults: matrices/bench.toml, 2 pairs, a budget of 0.03 (3 %: two pairs on a quiet 2-core
# machine vary by about that much). AGAINST_TARGET_DIR: where REV is built (default
# target/against/target), e.g. a folder that already holds its build. Nothing else should run
# meanwhile: a build or a test run beside the bench moves its figures more than any change does.
set -euo pipefail
cd "$(dirname "$0")/.."

usage() { echo "usage: $0 REV [--matrix M] [--pairs N] [--budget B]" >&2; exit 2; }
[ $# -ge 1 ] || usage
rev="$1"; shift
matrix=matrices/bench.toml pairs=2 budget=0.03
while [ $# -gt 0 ]; do
  case "$1" in
    --matrix) matrix="$2"; shift 2 ;;
    --pairs) pairs="$2"; shift 2 ;;
    --budget) budget="$2"; shift 2 ;;
    *) usage ;;
  esac
done
commit=$(git rev-parse --verify --quiet "$rev^{commit}") || { echo "$0: $rev names no commit" >&2; exit 2; }
[ -f "$matrix" ] || { echo "$0: --matrix $matrix: no such file" >&2; exit 2; }

root=$(pwd)
work="$root/target/against"
tree="$work/tree"
mkdir -p "$work/runs"
# The worktree stays between calls: checked out anew, its files would be newer than REV's build
# and cargo would compile it again.
if [ "$(git -C "$tree" rev-parse HEAD 2>/dev/null)" != "$commit" ]; then
  git worktree remove --force "$tree" >/dev/null 2>&1 || rm -rf "$tree"
  git worktree prune
  git worktree add --detach --force "$tree" "$commit" >/dev/null
fi

echo "building $rev ($commit) and this tree (release)…"
built="${AGAINST_TARGET_DIR:-$work/target}"
(cd "$tree" && CARGO_TARGET_DIR="$built" cargo build --release --quiet)
cargo build --release --quiet
old="$built/release/shadematrix"
new="$root/target/release/shadematrix"

export XDG_RUNTIME_DIR="${XDG_RUNTIME_DIR:-$(mktemp -d)}"
run() {  # binary, out folder → "wall cells/s"
  rm -rf "$2"
  "$1" bench "$matrix" --out "$2" >"$2.log" 2>&1 || { cat "$2.log" >&2; exit 1; }
  python3 -c 'import json,sys; b=json.load(open(sys.argv[1])); print(b["wall_seconds"], b["cells_per_second"])' \
    "$2/tables/bench.json"
}

ratios=()
printf '%-5s %-12s %10s %10s\n' pair binary "wall s" "cells/s"
for i in $(seq 1 "$pairs"); do
  read -r wa ca < <(run "$old" "$work/runs/old-$i")
  printf '%-5s %-12s %10.1f %10.2f\n' "$i" "$rev" "$wa" "$ca"
  read -r wb cb < <(run "$new" "$work/runs/new-$i")
  printf '%-5s %-12s %10.1f %10.2f\n' "$i" "this tree" "$wb" "$cb"
  ratios+=("$(python3 -c "print($cb / $ca)")")
done
python3 - "$budget" "${ratios[@]}" <<'EOF'
import statistics, sys
budget, ratios = float(sys.argv[1]), [float(r) for r in sys.argv[2:]]
median = statistics.median(ratios)
print("ratio per pair (this tree / REV, cells/s):", ", ".join(f"{r:.3f}" for r in ratios))
print(f"median {median:.3f}; budget: at least {1 - budget:.3f}")
sys.exit(0 if median >= 1 - budget else 1)
EOF
