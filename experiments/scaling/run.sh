#!/usr/bin/env bash
# The scaling benchmark: Lazy-DaSH on sorting with 4, 8, 16, 32 and 64 robots at 4 objects per robot,
# seeds 1..3, 600 s per run. Every run is scene -> `dashbench plan` -> `dashbench validate` (certified);
# a run counts as solved only when its plan validates. Prints a markdown table for RESULTS.md: per size,
# runs solved (with why the others were not: timeout, infeasible, invalid plan, crashed), medians over
# the solved runs of the total time, the time per phase, the peak memory and the collision checks; and
# writes a log-log plot of total time against the number of objects (scaling.svg, and .png when
# rsvg-convert exists) with the raw data beside it.
#
#   experiments/scaling/run.sh [--robots "4 8 16 32 64"] [--objects-per-robot K] [--seeds N]
#                              [--time-limit SEC] [--out DIR] [--resume] [--plan-args "--set NAME=VALUE ..."]
#   experiments/scaling/run.sh --table [--robots ...] [--seeds N] [--out DIR]   # report runs already made
#
# Defaults: --objects-per-robot 4, --seeds 3, --time-limit 600, --out experiments/scaling/results (one
# log per run in DIR/logs: the plan's summary, validator verdict and exit codes; DIR/runs.tsv, one
# line per run; DIR/scaling.svg and scaling.png). Runs one after another (timings without contention).
# --resume keeps the runs DIR/logs already holds and makes only the missing ones (after a kill).
# DASHBENCH names the dashbench to use (default: the repository's ./dashbench, which builds first).
set -euo pipefail

HERE="$(cd "$(dirname "${BASH_SOURCE[0]}")" && pwd)"
ROOT="$(cd "$HERE/../.." && pwd)"
DASHBENCH="${DASHBENCH:-$ROOT/dashbench}"
ROBOTS="4 8 16 32 64"
PER_ROBOT=4
SEEDS=3
TIME_LIMIT=600
OUT="$HERE/results"
RESUME=""
TABLE_ONLY=""
PLAN_ARGS=""

usage() { sed -n '2,18p' "${BASH_SOURCE[0]}" | sed 's/^# \{0,1\}//'; }
need() { [ $# -ge 2 ] || { echo "run.sh: $1 needs a value" >&2; exit 2; }; }

while [ $# -gt 0 ]; do
  case "$1" in
    --robots) need "$@"; ROBOTS="$2"; shift 2 ;;
    --objects-per-robot) need "$@"; PER_ROBOT="$2"; shift 2 ;;
    --seeds) need "$@"; SEEDS="$2"; shift 2 ;;
    --time-limit) need "$@"; TIME_LIMIT="$2"; shift 2 ;;
    --out) need "$@"; OUT="$2"; shift 2 ;;
    --plan-args) need "$@"; PLAN_ARGS="$2"; shift 2 ;;
    --resume) RESUME=1; shift ;;
    --table) TABLE_ONLY=1; shift ;;
    -h|--help) usage; exit 0 ;;
    *) echo "run.sh: unknown option $1 (see --help)" >&2; exit 2 ;;
  esac
done

read -r -a ROBOT_LIST <<<"$ROBOTS"
[ ${#ROBOT_LIST[@]} -gt 0 ] || { echo "run.sh: --robots is empty" >&2; exit 2; }
for r in "${ROBOT_LIST[@]}"; do
  [[ "$r" =~ ^[1-9][0-9]*$ ]] || { echo "run.sh: --robots expects positive integers, got '$r'" >&2; exit 2; }
done
[[ "$PER_ROBOT" =~ ^[1-9][0-9]*$ ]] || { echo "run.sh: --objects-per-robot expects a positive integer" >&2; exit 2; }
for r in "${ROBOT_LIST[@]}"; do
  # The sorting generator's ranges (dashbench scenario --list): robots 2..32, objects 1..128.
  if [ "$r" -lt 2 ] || [ "$r" -gt 32 ] || [ $((r * PER_ROBOT)) -gt 128 ]; then
    echo "run.sh: sorting takes 2..32 robots and at most 128 objects: $r robots x $PER_ROBOT objects" >&2
    exit 2
  fi
done
[[ "$SEEDS" =~ ^[1-9][0-9]*$ ]] || { echo "run.sh: --seeds expects a positive integer" >&2; exit 2; }
[[ "$TIME_LIMIT" =~ ^[0-9]+([.][0-9]+)?$ ]] || { echo "run.sh: --time-limit expects seconds" >&2; exit 2; }
if [ -n "$TABLE_ONLY" ] && [ ! -d "$OUT/logs" ]; then
  echo "run.sh: $OUT/logs does not exist: no runs to report" >&2
  exit 1
fi
mkdir -p "$OUT/logs"
OUT="$(cd "$OUT" && pwd)"

report() {
  python3 "$HERE/report.py" --out "$OUT" --robots "$ROBOTS" --objects-per-robot "$PER_ROBOT" --seeds "$SEEDS" \
    --experiments "$ROOT/experiments"
}

if [ -n "$TABLE_ONLY" ]; then
  report
  exit 0
fi

WORK="$(mktemp -d)"
trap 'rm -rf "$WORK"' EXIT
# The planner stops itself at the time limit; this only catches a run that does not.
HARD_LIMIT=$(awk -v t="$TIME_LIMIT" 'BEGIN { printf "%d", t * 1.5 + 120 }')

for r in "${ROBOT_LIST[@]}"; do
  objects=$((r * PER_ROBOT))
  for seed in $(seq 1 "$SEEDS"); do
    name="sorting-r$r-o$objects-s$seed"
    log="$OUT/logs/$name.log"
    if [ -n "$RESUME" ] && [ -f "$log" ] && grep -q '^validate exit:' "$log"; then
      echo "run.sh: $name: kept from $log" >&2
      continue
    fi
    rm -f "$log" "$WORK/plan.json"
    if ! "$DASHBENCH" scenario sorting robots="$r" objects="$objects" --seed "$seed" -o "$WORK/scene.json" \
        >"$WORK/scenario" 2>&1; then
      { echo "scenario failed: sorting robots=$r objects=$objects --seed $seed"; cat "$WORK/scenario"
        echo "plan exit: -"; echo "validate exit: -"; } >"$log"
      echo "run.sh: $name: scenario failed (see $log)" >&2
      continue
    fi
    echo "run.sh: $name: planning (limit $TIME_LIMIT s)" >&2
    set +e
    # shellcheck disable=SC2086
    timeout -k 30 "$HARD_LIMIT" "$DASHBENCH" plan --scene "$WORK/scene.json" --planner lazy-dash --seed "$seed" \
      --time-limit "$TIME_LIMIT" $PLAN_ARGS --out "$WORK/plan.json" >"$WORK/out" 2>"$WORK/err"
    rc=$?
    set -e
    vrc="-"
    : >"$WORK/validate"
    if [ "$rc" -eq 0 ] && [ -f "$WORK/plan.json" ]; then
      set +e
      "$DASHBENCH" validate --scene "$WORK/scene.json" --plan "$WORK/plan.json" >"$WORK/validate" 2>&1
      vrc=$?
      set -e
    fi
    {
      echo "run: sorting robots=$r objects=$objects seed=$seed planner=lazy-dash time-limit=$TIME_LIMIT${PLAN_ARGS:+ plan-args=$PLAN_ARGS}"
      cat "$WORK/out"
      # The summary and errors, without the progress lines ("[  12.34s] iter ...").
      grep -v '^\[ *[0-9.]*s\]' "$WORK/err" || true
      echo "plan exit: $rc"
      tail -n 20 "$WORK/validate"
      echo "validate exit: $vrc"
    } >"$log"
    echo "run.sh: $name: plan exit $rc, validate exit $vrc" >&2
  done
done
report
