#!/usr/bin/env bash
# Validator time, sampled (the older 1 cm check) against certified (conservative advancement), on plan
# files: prints a markdown table with one row per plan, median user CPU seconds of REPEAT runs each,
# one thread, and the certified check's smallest clearance.
#
#   experiments/validation/run.sh [--repeat N] SCENE.json PLAN.json [SCENE.json PLAN.json ...]
#
# Make the plans with `dashbench scenario ... -o SCENE.json` and `dashbench plan --scene SCENE.json
# --out PLAN.json` (experiments/lazy_dash/run.sh names the benchmark scenes). DASHBENCH names the
# dashbench to use.
set -euo pipefail

HERE="$(cd "$(dirname "${BASH_SOURCE[0]}")" && pwd)"
DASHBENCH="${DASHBENCH:-$HERE/../../build/dashbench}"
REPEAT=3
if [ "${1:-}" = "--repeat" ]; then REPEAT="$2"; shift 2; fi
if [ $# -lt 2 ] || [ $(($# % 2)) -ne 0 ]; then sed -n '2,10p' "${BASH_SOURCE[0]}" | sed 's/^# \{0,1\}//'; exit 2; fi

median() { sort -g | awk '{v[NR]=$1} END{if (NR%2) print v[(NR+1)/2]; else print (v[NR/2]+v[NR/2+1])/2}'; }
cpu() {  # user+sys seconds of one validate run
  /usr/bin/time -f "%U %S" "$DASHBENCH" validate --threads 1 "$@" 2>&1 >/dev/null | tail -1 | awk '{print $1 + $2}'
}

echo "| plan | makespan (s) | sampled (s) | certified (s) | ratio | smallest clearance |"
echo "|---|---|---|---|---|---|"
while [ $# -gt 0 ]; do
  scene="$1"; plan="$2"; shift 2
  sampled=$(for _ in $(seq "$REPEAT"); do cpu --scene "$scene" --plan "$plan" --sampled; done | median)
  certified=$(for _ in $(seq "$REPEAT"); do cpu --scene "$scene" --plan "$plan"; done | median)
  makespan=$(grep -o '"makespan": *[0-9.]*' "$plan" | head -1 | grep -o '[0-9.]*$' | awk '{printf "%.1f", $1}')
  closest=$("$DASHBENCH" validate --threads 1 --scene "$scene" --plan "$plan" | grep '^smallest clearance' | sed 's/^smallest clearance: //; s/ (required.*//')
  ratio=$(awk -v a="$certified" -v b="$sampled" 'BEGIN{ if (b > 0) printf "%.2f", a / b; else print "-" }')
  echo "| $(basename "$plan") | $makespan | $sampled | $certified | $ratio | $closest |"
done
