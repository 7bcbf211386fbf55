#!/usr/bin/env bash
# The dispatch tests under full CPU load (issue 25): runs them N times while busy loops keep every core
# saturated, and prints, as Markdown, runs passed / tests passed / seconds per run, the tests that
# failed (if any) and the measurements the tests print ("[ measure  ]") in the last run.
#
#   tests/dispatch/under_load.sh [--runs N] [--busy N] [--sorting] [--build DIR]
#
#   --runs N    how many times to run the dispatch tests (default 20)
#   --busy N    busy loops beside them (default: one per core, `nproc`)
#   --sorting   also run the sorting dispatch test (it plans with Lazy-DaSH first) once under the load
#   --build DIR the build directory with test_dispatch and dashbench built (default: build/)
#
# The tests are those of tests/dispatch except SortingDispatch, one at a time (ctest). It does not
# build: `cmake --build build --target test_dispatch test_dispatch_sorting dashbench` first. Exits 0
# when it could run them, whatever they did (the counts say it); 2 on a usage or build problem.
set -euo pipefail

ROOT="$(cd "$(dirname "${BASH_SOURCE[0]}")/../.." && pwd)"
RUNS=20
BUSY="$(nproc)"
SORTING=0
BUILD="$ROOT/build"
while [ $# -gt 0 ]; do
  case "$1" in
    --runs) RUNS="$2"; shift 2 ;;
    --busy) BUSY="$2"; shift 2 ;;
    --sorting) SORTING=1; shift ;;
    --build) BUILD="$(cd "$2" && pwd)"; shift 2 ;;
    -h|--help) sed -n '2,15p' "${BASH_SOURCE[0]}" | sed 's/^# \{0,1\}//'; exit 0 ;;
    *) echo "under_load.sh: unknown option '$1' (see --help)" >&2; exit 2 ;;
  esac
done
[[ "$RUNS" =~ ^[1-9][0-9]*$ && "$BUSY" =~ ^[0-9]+$ ]] || { echo "under_load.sh: --runs and --busy take counts" >&2; exit 2; }
TESTS="$BUILD/tests/dispatch"
for f in "$TESTS/test_dispatch" "$BUILD/dashbench"; do
  [ -x "$f" ] || { echo "under_load.sh: $f is not built" >&2; exit 2; }
done
[ "$SORTING" = 0 ] || [ -x "$TESTS/test_dispatch_sorting" ] || { echo "under_load.sh: test_dispatch_sorting is not built" >&2; exit 2; }

LOGS="$(mktemp -d)"
BUSY_PIDS=()
cleanup() {
  for pid in "${BUSY_PIDS[@]}"; do kill "$pid" 2>/dev/null || true; done
  rm -rf "$LOGS"
}
trap cleanup EXIT
for _ in $(seq 1 "$BUSY"); do
  bash -c 'while :; do :; done' &
  BUSY_PIDS+=($!)
done

# One ctest run; its log in $LOGS/$1.log, its wall time in seconds on stdout.
run_ctest() {
  local name="$1"; shift
  local t0 ms
  t0="$(date +%s%N)"
  ctest --test-dir "$TESTS" -V "$@" >"$LOGS/$name.log" 2>&1 || true
  ms=$((($(date +%s%N) - t0) / 1000000))
  printf '%d.%03d\n' $((ms / 1000)) $((ms % 1000))
}

for i in $(seq 1 "$RUNS"); do
  run_ctest "run$i" -E SortingDispatch >"$LOGS/run$i.seconds"
  echo "under_load.sh: run $i/$RUNS: $(grep -E 'tests passed, [0-9]+ tests? failed' "$LOGS/run$i.log" || echo 'no summary') ($(cat "$LOGS/run$i.seconds") s)" >&2
done
[ "$SORTING" = 0 ] || run_ctest sorting -R SortingDispatch >"$LOGS/sorting.seconds"

python3 - "$LOGS" "$RUNS" "$BUSY" "$(nproc)" "$SORTING" <<'EOF'
import re, statistics, sys
logs, runs, busy, cores, sorting = sys.argv[1], int(sys.argv[2]), int(sys.argv[3]), sys.argv[4], sys.argv[5] == "1"
SUMMARY = re.compile(r"(\d+)% tests passed, (\d+) tests? failed out of (\d+)")

def read(name):
    text = open(f"{logs}/{name}.log", errors="replace").read()
    seconds = float(open(f"{logs}/{name}.seconds").read())
    m = SUMMARY.search(text)
    total, failed = (int(m.group(3)), int(m.group(2))) if m else (0, 0)
    names = dict(re.findall(r"^\s*Start\s+(\d+): (\S+)", text, re.M))
    failures = re.findall(r"^\s*\d+ - (\S+) \(", text.split("The following tests FAILED:")[-1], re.M) \
        if "The following tests FAILED:" in text else []
    measures = [(names.get(n, "test " + n), line.strip())
                for n, line in re.findall(r"^(\d+): \[ measure  \] (.*)$", text, re.M)]
    return {"ok": m is not None and failed == 0, "summary": m is not None, "total": total, "failed": failed,
            "seconds": seconds, "failures": failures, "measures": measures}

results = [read(f"run{i}") for i in range(1, runs + 1)]
tests = results[-1]["total"]
passed_runs = sum(r["ok"] for r in results)
passed_tests = sum(r["total"] - r["failed"] for r in results)
total_tests = sum(r["total"] for r in results)
seconds = [r["seconds"] for r in results]
print(f"The dispatch tests (`ctest --test-dir build/tests/dispatch -E SortingDispatch`, {tests} tests, one at a "
      f"time) run {runs} time{'s' if runs != 1 else ''} with {busy} busy loop{'s' if busy != 1 else ''} on {cores} "
      f"cores beside them.\n")
print("| runs passed | tests passed | seconds per run: median (min-max) |")
print("|---|---|---|")
print(f"| {passed_runs}/{runs} | {passed_tests}/{total_tests} | {statistics.median(seconds):.1f} "
      f"({min(seconds):.1f}-{max(seconds):.1f}) |")
failed_in = {}
for i, r in enumerate(results, 1):
    if not r["summary"]:
        failed_in.setdefault("(ctest gave no summary)", []).append(i)
    for name in r["failures"]:
        failed_in.setdefault(name, []).append(i)
if failed_in:
    print("\nFailed:")
    for name, where in sorted(failed_in.items()):
        print(f"- {name} in run{'s' if len(where) > 1 else ''} {', '.join(map(str, where))}")
if sorting:
    s = read("sorting")
    print(f"\nThe sorting dispatch test (it plans with Lazy-DaSH first), once under the same load: "
          f"{'passed' if s['ok'] else 'FAILED'} ({s['seconds']:.1f} s).")
    results[-1]["measures"] += s["measures"]
if results[-1]["measures"]:
    print("\nWhat the tests measured in the last run:\n")
    for name, line in results[-1]["measures"]:
        print(f"- {name}: {line}")
EOF
