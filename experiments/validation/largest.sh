#!/usr/bin/env bash
# Validator time on the paper's largest instances: plans each of them with Lazy-DaSH (seed 1, 600 s),
# then prints experiments/validation/run.sh's table (sampled vs certified, one thread, median of 3) for
# every solved plan, and one line per scene that was not solved.
#
#   experiments/validation/largest.sh [--plans DIR]
#
# --plans DIR: take NAME-s1.scene.json / NAME-s1.plan.json from DIR instead of planning (plans made
# by the same commit's `dashbench plan --seed 1 --time-limit 600`; NAME as in the list below).
# DASHBENCH names the dashbench to use.
set -euo pipefail

HERE="$(cd "$(dirname "${BASH_SOURCE[0]}")" && pwd)"
DASHBENCH="${DASHBENCH:-$HERE/../../build/dashbench}"
export DASHBENCH
PLANS=""
if [ "${1:-}" = "--plans" ]; then PLANS="$2"; shift 2; fi
[ $# -eq 0 ] || { sed -n '2,10p' "${BASH_SOURCE[0]}" | sed 's/^# \{0,1\}//'; exit 2; }

SCENES=(
  "sorting16 sorting robots=16 objects=64"
  "wall8-6-40 wall robots=8 walls=6 objects=40"
  "shelfwall4-32 shelf-wall robots=4 objects=32"
  "stocking3-18 stocking layers=3 objects=18"
  "stocking2-28 stocking layers=2 objects=28"
  "lab8 lab containers=8"
)
if [ -z "$PLANS" ]; then
  PLANS="$(mktemp -d)"
  trap 'rm -rf "$PLANS"' EXIT
  for spec in "${SCENES[@]}"; do
    read -r name family params <<<"$spec"
    # shellcheck disable=SC2086
    "$DASHBENCH" scenario "$family" $params --seed 1 -o "$PLANS/$name-s1.scene.json" >/dev/null 2>&1
    "$DASHBENCH" plan --scene "$PLANS/$name-s1.scene.json" --seed 1 --time-limit 600 \
      --out "$PLANS/$name-s1.plan.json" >/dev/null 2>&1 || rm -f "$PLANS/$name-s1.plan.json"
  done
fi
pairs=()
unsolved=()
for spec in "${SCENES[@]}"; do
  read -r name _ <<<"$spec"
  if [ -s "$PLANS/$name-s1.plan.json" ]; then
    pairs+=("$PLANS/$name-s1.scene.json" "$PLANS/$name-s1.plan.json")
  else
    unsolved+=("$name")
  fi
done
[ ${#pairs[@]} -gt 0 ] && "$HERE/run.sh" "${pairs[@]}"
for name in "${unsolved[@]}"; do echo; echo "$name: no plan to validate (the planner did not solve it within 600 s)"; done
