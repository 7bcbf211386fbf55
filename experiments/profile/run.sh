#!/usr/bin/env bash
# Where the time of one Lazy-DaSH run goes, per function (issue 23): `perf record` samples the planner
# (199 Hz, user and kernel) and `perf report` lists the functions holding the most samples, by themselves
# (not counting their callees) and by library. Prints markdown; keeps perf.data and the planner's log
# under --out.
#
#   experiments/profile/run.sh [--scene "FAMILY K=V ..."] [--seed N] [--time-limit SEC] [--top N] [--out DIR]
#
# Default: sorting robots=16 objects=64, seed 1, 600 s, top 25, out experiments/profile/results.
# Needs perf (Debian: linux-perf); as root, or with kernel.perf_event_paranoid <= 1.
# DASHBENCH names the dashbench to use (default: the repository's ./dashbench, which builds first).
set -euo pipefail
HERE="$(cd "$(dirname "${BASH_SOURCE[0]}")" && pwd)"
ROOT="$(cd "$HERE/../.." && pwd)"
DASHBENCH="${DASHBENCH:-$ROOT/dashbench}"
SCENE="sorting robots=16 objects=64"
SEED=1
TIME_LIMIT=600
TOP=25
OUT="$HERE/results"
while [ $# -gt 0 ]; do
  case "$1" in
    --scene) SCENE="$2"; shift 2 ;;
    --seed) SEED="$2"; shift 2 ;;
    --time-limit) TIME_LIMIT="$2"; shift 2 ;;
    --top) TOP="$2"; shift 2 ;;
    --out) OUT="$2"; shift 2 ;;
    -h|--help) sed -n '2,12p' "$0"; exit 0 ;;
    *) echo "profile/run.sh: unknown argument '$1' (see --help)" >&2; exit 2 ;;
  esac
done
command -v perf >/dev/null || { echo "profile/run.sh: perf is not installed (apt-get install linux-perf)" >&2; exit 2; }
mkdir -p "$OUT"
name="$(echo "$SCENE" | tr ' =' '--')-s$SEED"
family="${SCENE%% *}"
params="${SCENE#"$family"}"
# shellcheck disable=SC2086  # params are separate K=V words
"$DASHBENCH" scenario "$family" $params --seed "$SEED" -o "$OUT/$name.scene.json" >/dev/null
perf record -F 199 -o "$OUT/$name.perf.data" -- \
  "$DASHBENCH" plan --scene "$OUT/$name.scene.json" --seed "$SEED" --time-limit "$TIME_LIMIT" \
  --out "$OUT/$name.plan.json" >"$OUT/$name.log" 2>&1 || true
report() { perf report -i "$OUT/$name.perf.data" --no-children --percent-limit 0.3 --stdio "$@" 2>/dev/null; }

echo "### $SCENE, seed $SEED"
echo
echo "\`experiments/profile/run.sh --scene \"$SCENE\" --seed $SEED --time-limit $TIME_LIMIT\`"
echo
echo '```'
grep -E '^(time|sizes|collision checks|peak memory|status):' "$OUT/$name.log" | cut -c1-400
echo '```'
echo
echo "| share of samples | function (self) |"
echo "|---|---|"
report --sort symbol | grep -E '^ +[0-9]' | head -n "$TOP" |
  sed -E 's/^ +([0-9.]+%) +\[\.\] +/\1\t/; s/^ +([0-9.]+%) +\[k\] +/\1\t[kernel] /' |
  awk -F'\t' '{ gsub(/\|/, "\\|", $2); name = $2; sub(/[ -]+$/, "", name); if (length(name) > 110) name = substr(name, 1, 107) "..."; printf "| %s | `%s` |\n", $1, name }'
echo
echo "| share of samples | library |"
echo "|---|---|"
report --sort dso | grep -E '^ +[0-9]' | head -n 8 | awk '{ printf "| %s | %s |\n", $1, $2 }'
