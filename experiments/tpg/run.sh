#!/usr/bin/env bash
# Issue 39: executed against planned makespan, timed against tpg (execution by dependencies), with
# simulated arms that behave and that misbehave. One sorting plan with handovers (2 robots, 2 objects,
# Lazy-DaSH seed 1), a server on loopback and two `dashbench controller --driver sim` agents per
# setting; every dispatch at time_scale 0.8. Prints one line per (setting, execution) and appends it
# to $OUT/results.csv (setting, execution, repeat, state, planned s, executed s, reason).
#   experiments/tpg/run.sh [REPEATS]      (environment: DASHBENCH_BIN, OUT, PORT)
set -euo pipefail
ROOT="$(cd "$(dirname "${BASH_SOURCE[0]}")/../.." && pwd)"
BIN="${DASHBENCH_BIN:-$ROOT/build/dashbench}"
OUT="${OUT:-$(mktemp -d /tmp/tpg-exp.XXXXXX)}"
PORT="${PORT:-18639}"
REPEATS="${1:-1}"
URL="http://127.0.0.1:$PORT"
mkdir -p "$OUT"
echo "tpg-experiment-token" > "$OUT/token"
"$BIN" scenario sorting --seed 1 --out "$OUT/scene.json" robots=2 objects=2
"$BIN" plan --scene "$OUT/scene.json" --seed 1 --out "$OUT/plan.json" --quiet
"$BIN" serve --port "$PORT" --db "$OUT/results.db" --token-file "$OUT/token" > "$OUT/serve.log" 2>&1 &
SERVER=$!
AGENTS=()
cleanup() {
  for pid in "${AGENTS[@]}" "$SERVER"; do kill "$pid" 2>/dev/null || true; done
  wait 2>/dev/null || true
}
trap cleanup EXIT
python3 - "$OUT" <<'PY'
import json, sys
out = sys.argv[1]
plan = json.load(open(out + "/plan.json")); scene = json.load(open(out + "/scene.json"))
for mode in ("timed", "tpg"):
    body = {"plan": plan, "scene": scene, "options": {"time_scale": 0.8, "execution": mode}, "user": "experiments/tpg"}
    json.dump(body, open(f"{out}/body-{mode}.json", "w"))
homes = {r["id"]: ",".join(repr(x) for x in plan["robots"][r["id"]]["points"][0]["q"]) for r in scene["robots"]}
open(out + "/homes", "w").write("\n".join(f"{k} {v}" for k, v in homes.items()) + "\n")
PY
for _ in $(seq 50); do curl -s "$URL/api/controllers" -H "Authorization: Bearer $(cat "$OUT/token")" > /dev/null && break; sleep 0.2; done

start_agents() {  # $1: extra options of ur5e_0, $2: of ur5e_1
  AGENTS=()
  while read -r robot home; do
    local extra="$1"; [ "$robot" = ur5e_1 ] && extra="$2"
    # shellcheck disable=SC2086
    "$BIN" controller --server "$URL" --robot "$robot" --token-file "$OUT/token" --driver sim --sim-start "$home" \
      $extra > "$OUT/agent-$robot.log" 2>&1 &
    AGENTS+=($!)
  done < "$OUT/homes"
  sleep 3
}
stop_agents() { for pid in "${AGENTS[@]}"; do kill "$pid" 2>/dev/null || true; done; wait "${AGENTS[@]}" 2>/dev/null || true; }

dispatch() {  # $1: setting name, $2: execution, $3: repeat
  local reply
  reply=$(curl -s -X POST "$URL/api/dispatch" -H "Authorization: Bearer $(cat "$OUT/token")" \
    -H 'Content-Type: application/json' --data-binary "@$OUT/body-$2.json")
  if ! grep -q '"dispatch_id"' <<< "$reply"; then
    echo "$1 $2 refused: ${reply:0:300}"
    echo "$1,$2,$3,refused,,,see the output" >> "$OUT/results.csv"
    return
  fi
  for _ in $(seq 600); do
    sleep 0.5
    status=$(curl -s "$URL/api/dispatch" -H "Authorization: Bearer $(cat "$OUT/token")")
    if python3 -c 'import json,sys; sys.exit(0 if json.loads(sys.argv[1]).get("final") else 1)' "$status"; then break; fi
  done
  python3 - "$1" "$2" "$status" "$3" "$OUT/results.csv" <<'PY'
import csv, json, sys
setting, mode, text, repeat, path = sys.argv[1:6]
s = json.loads(text)
ratio = s["elapsed"] / s["duration"] if s["duration"] > 0 else 0.0
print(f"{setting:10s} {mode:6s} state={s['state']:9s} planned={s['duration']:7.2f} s executed={s['elapsed']:7.2f} s "
      f"ratio={ratio:5.2f} {s['reason'][:90]}")
with open(path, "a", newline="") as f:
    csv.writer(f).writerow([setting, mode, repeat, s["state"], f"{s['duration']:.3f}", f"{s['elapsed']:.3f}", s["reason"]])
PY
}

echo "setting,execution,repeat,state,planned_s,executed_s,reason" > "$OUT/results.csv"
# Fresh agents for every dispatch: an aborted one leaves its arms where they stopped.
for r in $(seq "$REPEATS"); do
  for mode in timed tpg; do
    start_agents "" ""
    dispatch nominal "$mode" "$r"
    stop_agents
    start_agents "--sim-speed 0.7 --sim-gripper-time 1 --sim-gripper-jitter 0.2 --sim-seed $r" \
                 "--sim-gripper-time 1 --sim-gripper-jitter 0.2 --sim-pause-rate 0.2 --sim-pause-max 1 --sim-seed $((r + 100))"
    dispatch perturbed "$mode" "$r"
    stop_agents
  done
done
