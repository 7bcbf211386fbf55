#!/usr/bin/env bash
# The Lazy-DaSH task layer alone (`plan --task-only`) on the largest scenes of the paper: prints a
# markdown table (scene, status, schedule steps, time per phase, H_T and H_TE sizes, constraints,
# task space expansions) for the README. CPU time is the process's user + system time: on a shared
# machine it says more than wall time. Medians over --seeds seeds (default 1: seed 1 only).
#
#   experiments/task_layer/run.sh [--seeds N] [--time-limit SEC]
#
# DASHBENCH names the dashbench to use (default: the repository's ./dashbench, which builds first).
set -euo pipefail

HERE="$(cd "$(dirname "${BASH_SOURCE[0]}")" && pwd)"
ROOT="$(cd "$HERE/../.." && pwd)"
DASHBENCH="${DASHBENCH:-$ROOT/dashbench}"
SEEDS=1
TIME_LIMIT=300
while [ $# -gt 0 ]; do
  case "$1" in
    --seeds) SEEDS="$2"; shift 2 ;;
    --time-limit) TIME_LIMIT="$2"; shift 2 ;;
    -h|--help) sed -n '2,8p' "${BASH_SOURCE[0]}" | sed 's/^# \{0,1\}//'; exit 0 ;;
    *) echo "run.sh: unknown option $1" >&2; exit 2 ;;
  esac
done

SCENES=(
  "sorting robots=16 objects=64"
  "wall robots=8 walls=6 objects=40"
  "shelf-wall robots=4 objects=32"
  "stocking layers=3 objects=18"
  "stocking layers=2 objects=28"
  "lab containers=8"
)
WORK="$(mktemp -d)"
trap 'rm -rf "$WORK"' EXIT

median() { sort -g | awk '{v[NR]=$1} END{if (NR==0) print "-"; else if (NR%2) print v[(NR+1)/2]; else print (v[NR/2]+v[NR/2+1])/2}'; }

echo "| scene | feasible | steps | wall time (s) | CPU time (s) | task construction / query / conflict detection (s) | H_T | H_TE | constraints | expansions |"
echo "|---|---|---|---|---|---|---|---|---|---|"
for spec in "${SCENES[@]}"; do
  read -r family params <<<"$spec"
  : >"$WORK/rows"
  ok=0
  for seed in $(seq 1 "$SEEDS"); do
    scene="$WORK/scene.json"
    # shellcheck disable=SC2086
    "$DASHBENCH" scenario "$family" $params --seed "$seed" -o "$scene" >/dev/null 2>&1
    start=$(date +%s.%N)
    set +e
    /usr/bin/time -f '%U %S' -o "$WORK/cpu" \
      "$DASHBENCH" plan --scene "$scene" --seed "$seed" --task-only --time-limit "$TIME_LIMIT" >"$WORK/out" 2>"$WORK/err"
    rc=$?
    cpu=$(awk '{print $1 + $2}' "$WORK/cpu")
    set -e
    wall=$(echo "$(date +%s.%N) - $start" | bc)
    [ "$rc" -eq 0 ] && ok=$((ok + 1))
    steps=$(grep -c '^ *[0-9]*\. ' "$WORK/out" || true)
    phase() { grep '^time:' "$WORK/err" | grep -o "$1 [0-9.]*" | awk '{print $2}' | head -1; }
    sizes=$(grep '^sizes:' "$WORK/err" | awk '{print $3, $5}' || true)
    cons=$(grep '^collision checks:' "$WORK/err" | grep -o 'constraints: [0-9]*' | awk '{print $2}' || true)
    exps=$(grep '^collision checks:' "$WORK/err" | grep -o 'expansions: [0-9]*' | awk '{print $2}' || true)
    echo "$rc $steps $wall $cpu $(phase task_construction) $(phase task_query) $(phase task_conflict_detection) $sizes $cons $exps" >>"$WORK/rows"
  done
  col() { awk -v c="$1" '$1 == 0 {print $c}' "$WORK/rows" | median; }
  last() { awk -v c="$1" '$1 == 0 {v=$c} END{print (v == "" ? "-" : v)}' "$WORK/rows"; }
  printf '| %s %s | %d/%d | %s | %.2f | %.2f | %s / %s / %s | %s | %s | %s | %s |\n' "$family" "$params" "$ok" "$SEEDS" \
    "$(col 2)" "$(col 3 | sed 's/^-$/0/')" "$(col 4 | sed 's/^-$/0/')" "$(col 5)" "$(col 6)" "$(col 7)" "$(last 8)" \
    "$(last 9)" "$(col 10)" "$(col 11)"
done
