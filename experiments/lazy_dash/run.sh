#!/usr/bin/env bash
# Lazy-DaSH end to end (scene -> plan -> the project's validator) on the scenes of the Lazy-DaSH
# issues: prints a markdown table for the README with, per scene, runs solved and validated, median
# total time, the time per phase (task construction / query / conflict detection, motion construction
# / query, conflict resolution), representation sizes, makespan and collision checks, medians over
# the solved runs (failed runs show their status instead).
#
#   experiments/lazy_dash/run.sh [--large] [--scene "FAMILY K=V ..."]... [--seeds N] [--time-limit SEC]
#                                [--plan-args "--set NAME=VALUE --profile paper ..."]
#
# Default: the small cases (sorting 4x8, wall 8/2/16, shelf-wall 2/8, stocking 2/8, lab 2);
# --large: the paper's largest instances (600 s each by default); --scene (repeatable): these scenes
# instead (e.g. to run the large ones in two halves side by side). Seeds are 1..N. Plans are validated
# by `dashbench validate` again here, outside the planner. DASHBENCH names the dashbench to use;
# KEEP_PLANS=DIR keeps every scene and plan there (FAMILY-PARAMS-sSEED.scene.json / .plan.json), e.g.
# for experiments/validation/run.sh.
set -euo pipefail

HERE="$(cd "$(dirname "${BASH_SOURCE[0]}")" && pwd)"
ROOT="$(cd "$HERE/../.." && pwd)"
DASHBENCH="${DASHBENCH:-$ROOT/dashbench}"
SEEDS=1
TIME_LIMIT=600
PLAN_ARGS=""
SCENES=(
  "sorting robots=4 objects=8"
  "wall robots=8 walls=2 objects=16"
  "shelf-wall robots=2 objects=8"
  "stocking layers=2 objects=8"
  "lab containers=2"
)
LARGE=(
  "sorting robots=16 objects=64"
  "wall robots=8 walls=6 objects=40"
  "shelf-wall robots=4 objects=32"
  "stocking layers=3 objects=18"
  "stocking layers=2 objects=28"
  "lab containers=8"
)
CHOSEN=()
while [ $# -gt 0 ]; do
  case "$1" in
    --large) SCENES=("${LARGE[@]}"); shift ;;
    --scene) CHOSEN+=("$2"); shift 2 ;;
    --seeds) SEEDS="$2"; shift 2 ;;
    --time-limit) TIME_LIMIT="$2"; shift 2 ;;
    --plan-args) PLAN_ARGS="$2"; shift 2 ;;
    -h|--help) sed -n '2,16p' "${BASH_SOURCE[0]}" | sed 's/^# \{0,1\}//'; exit 0 ;;
    *) echo "run.sh: unknown option $1" >&2; exit 2 ;;
  esac
done
[ ${#CHOSEN[@]} -gt 0 ] && SCENES=("${CHOSEN[@]}")
WORK="$(mktemp -d)"
trap 'rm -rf "$WORK"' EXIT

median() { sort -g | awk '{v[NR]=$1} END{if (NR==0) print "-"; else if (NR%2) print v[(NR+1)/2]; else print (v[NR/2]+v[NR/2+1])/2}'; }

echo "| scene | solved | total (s) | per seed (s) | task constr. / query / conflict det. (s) | motion constr. / query (s) | conflict res. / validation (s) | H_T | H_TE | H_M | H_ME | makespan (s) | collision checks |"
echo "|---|---|---|---|---|---|---|---|---|---|---|---|---|"
for spec in "${SCENES[@]}"; do
  read -r family params <<<"$spec"
  : >"$WORK/rows"
  ok=0
  statuses=""
  per_seed=""
  for seed in $(seq 1 "$SEEDS"); do
    # shellcheck disable=SC2086
    "$DASHBENCH" scenario "$family" $params --seed "$seed" -o "$WORK/scene.json" >/dev/null 2>&1
    rm -f "$WORK/plan.json"
    set +e
    # shellcheck disable=SC2086
    "$DASHBENCH" plan --scene "$WORK/scene.json" --seed "$seed" --time-limit "$TIME_LIMIT" $PLAN_ARGS \
      --out "$WORK/plan.json" >"$WORK/out" 2>"$WORK/err"
    rc=$?
    set -e
    status=$(grep -o '^status: [a-z]*' "$WORK/out" | awk '{print $2}' || true)
    if [ "$rc" -eq 0 ] && "$DASHBENCH" validate --scene "$WORK/scene.json" --plan "$WORK/plan.json" >/dev/null 2>&1; then
      ok=$((ok + 1))
    elif [ "$rc" -eq 0 ]; then
      status="invalid-plan"
      rc=1
    fi
    statuses="$statuses ${status:-crashed}"
    if [ -n "${KEEP_PLANS:-}" ]; then
      mkdir -p "$KEEP_PLANS"
      name="$family-$(echo "$params" | tr ' =' '-')-s$seed"
      cp "$WORK/scene.json" "$KEEP_PLANS/$name.scene.json"
      [ -f "$WORK/plan.json" ] && cp "$WORK/plan.json" "$KEEP_PLANS/$name.plan.json"
      cp "$WORK/err" "$KEEP_PLANS/$name.log"
    fi
    [ "$rc" -eq 0 ] && per_seed="$per_seed, $(grep '^time:' "$WORK/err" | grep -o ' total [0-9.]*' | awk '{printf "%.0f", $2}')" \
      || per_seed="$per_seed, ${status:-crashed}"
    phase() { grep '^time:' "$WORK/err" | grep -o "$1 [0-9.]*" | awk '{print $2}' | head -1; }
    total=$(grep '^time:' "$WORK/err" | grep -o ' total [0-9.]*' | awk '{print $2}' || true)
    sizes=$(grep '^sizes:' "$WORK/err" | awk '{print $3, $5, $7, $9}' || true)
    checks=$(grep '^collision checks:' "$WORK/err" | awk '{print $3 + $5}' || true)
    makespan=$(grep -o 'makespan [0-9.]*' "$WORK/out" | awk '{print $2}' || true)
    echo "$rc ${total:-0} $(phase task_construction) $(phase task_query) $(phase task_conflict_detection)" \
      "$(phase motion_construction) $(phase motion_query) $(phase conflict_resolution) $(phase validation) $sizes ${makespan:-0} ${checks:-0}" \
      | awk '{for (i = 1; i <= NF; ++i) if ($i == "") $i = 0; print}' >>"$WORK/rows"
  done
  col() { awk -v c="$1" '$1 == 0 {print ($c == "" ? 0 : $c)}' "$WORK/rows" | median; }
  last() { awk -v c="$1" '$1 == 0 {v=$c} END{print (v == "" ? "-" : v)}' "$WORK/rows"; }
  if [ "$ok" -eq 0 ]; then
    printf '| %s %s | 0/%d (%s) | | %s | | | | | | | | | |\n' "$family" "$params" "$SEEDS" "$(echo $statuses | tr ' ' ',')" \
      "${per_seed#, }"
    continue
  fi
  printf '| %s %s | %d/%d | %s | %s | %s / %s / %s | %s / %s | %s / %s | %s | %s | %s | %s | %s | %s |\n' "$family" "$params" "$ok" \
    "$SEEDS" "$(col 2)" "${per_seed#, }" "$(col 3)" "$(col 4)" "$(col 5)" "$(col 6)" "$(col 7)" "$(col 8)" "$(col 9)" "$(last 10)" \
    "$(last 11)" "$(last 12)" "$(last 13)" "$(col 14)" "$(col 15)"
done
