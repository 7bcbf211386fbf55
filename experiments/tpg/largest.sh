#!/usr/bin/env bash
# Issue 39: the temporal plan graph of the plans of the paper's largest instances, and its replay check.
# Per instance: the scene (scenario seed 1), its Lazy-DaSH plan (default profile, seed 1), then
# `dashbench tpg --check DRAWS` (build the graph, replay DRAWS random delay draws that respect it
# through the certified validator). Prints one Markdown row per instance and keeps every log in $OUT.
#   experiments/tpg/largest.sh [DRAWS] [FAMILY K=V ...]...   (environment: DASHBENCH_BIN, OUT)
#   e.g. experiments/tpg/largest.sh 100 "lab containers=8"
set -euo pipefail
ROOT="$(cd "$(dirname "${BASH_SOURCE[0]}")/../.." && pwd)"
BIN="${DASHBENCH_BIN:-$ROOT/build/dashbench}"
OUT="${OUT:-$(mktemp -d /tmp/tpg-largest.XXXXXX)}"
DRAWS="${1:-100}"
shift || true
SCENES=("$@")
if [ ${#SCENES[@]} -eq 0 ]; then
  SCENES=("sorting robots=16 objects=64" "wall robots=8 walls=6 objects=40" "shelf-wall robots=4 objects=32"
          "stocking layers=3 objects=18" "stocking layers=2 objects=28" "lab containers=8")
fi
mkdir -p "$OUT"
echo "| instance | plan makespan (s) | graph build (s) | nodes / edges (handover, object, swept) | delay draws passed |"
echo "|---|---|---|---|---|"
for spec in "${SCENES[@]}"; do
  read -r family params <<< "$spec"
  name="$(echo "$spec" | tr ' =' '_-')"
  "$BIN" scenario "$family" --seed 1 -o "$OUT/$name.scene.json" $params > /dev/null 2>&1
  if ! "$BIN" plan --scene "$OUT/$name.scene.json" --seed 1 --profile default --time-limit 600 --threads 1 \
       --out "$OUT/$name.plan.json" --quiet > "$OUT/$name.plan.log" 2>&1; then
    echo "| $spec | not solved ($OUT/$name.plan.log) | - | - | - |"
    continue
  fi
  "$BIN" tpg --scene "$OUT/$name.scene.json" --plan "$OUT/$name.plan.json" --check "$DRAWS" --threads 1 \
    --out "$OUT/$name.tpg.json" > "$OUT/$name.tpg.log" 2>&1 || true
  python3 - "$spec" "$OUT/$name.tpg.log" <<'PY'
import re, sys
spec, log = sys.argv[1], open(sys.argv[2]).read()
graph = re.search(r"(\d+) nodes, (\d+) edges \(handover (\d+), object (\d+), swept (\d+)\)", log)
built = re.search(r"built in ([\d.]+) s", log)
rep = re.search(r"replays: (\d+) draws, (\d+) failed; makespan planned ([\d.]+) s", log)
if not (graph and built and rep):
    print(f"| {spec} | see {sys.argv[2]} | - | - | - |")
    sys.exit(0)
n, e, h, o, s = graph.groups()
draws, failed, planned = rep.groups()
print(f"| {spec} | {planned} | {built.group(1)} | {n} / {e} ({h}, {o}, {s}) | {int(draws) - int(failed)} of {draws} |")
PY
done
echo "logs in $OUT"
