#!/usr/bin/env bash
# Regenerates experiments/RESULTS.md, one section at a time or all of them. Each section is the output of
# one benchmark script, between markers <!-- section:NAME --> and <!-- end:NAME --> in RESULTS.md, with
# the command, the commit and the date above its tables; sections not named are left as they are.
#
#   experiments/results.sh [SECTION ...]        # default: every section (hours on 2 cores)
#   experiments/results.sh --list               # the sections and the commands behind them
#
# Sections:
#   small      experiments/lazy_dash/run.sh --seeds 5 --time-limit 300        (about 5 minutes)
#   large      experiments/lazy_dash/run.sh --large --seeds 5                 (1-3 hours)
#   task-layer experiments/task_layer/run.sh                                  (under a minute)
#   ablation   experiments/ablation/run.sh --workers 1 --seeds 1 --time-limit 60 (15-45 min; 1.5 h at most)
#   dispatch-load tests/dispatch/under_load.sh --runs 20 --sorting            (about 12 minutes)
#   validation experiments/validation/largest.sh                             (20-40 minutes)
#   scaling    experiments/scaling/run.sh                                     (1-3 hours: sorting 4..32 robots x
#              4 objects each, 3 seeds, 600 s per run; up to 3 hours when 32/128 times out; writes the plot
#              and raw data under experiments/scaling/results/)
#   paper-all  experiments/compare/paper_all.sh                              (7.6-35 hours: paper-all.json, 420
#              runs of 600 s on 2 workers, resumable; PAPER_ALL_BATCH=ID PAPER_ALL_DB=DB: the section of a
#              batch already run; writes the figures under experiments/compare/figures/)
#   paper-vs-paper  the same for paper-vs-paper.json (both planners --profile paper: the paper's claims);
#              PAPER_VS_PAPER_DB (default results-compare-paper-profile.db), PAPER_VS_PAPER_BATCH; figures
#              under experiments/compare/figures-paper/
#
# DASHBENCH names the dashbench to use (default: the repository's ./dashbench, which builds first).
# dispatch-load runs the dispatch tests DISPATCH_LOAD_RUNS times (default 20) while busy loops saturate
# every core; it uses build/'s test_dispatch, test_dispatch_sorting and dashbench (build them first).
# validation plans the largest instances first; VALIDATION_PLANS=DIR takes the plans from DIR instead
# (see experiments/validation/largest.sh).
set -euo pipefail

HERE="$(cd "$(dirname "${BASH_SOURCE[0]}")" && pwd)"
ROOT="$(cd "$HERE/.." && pwd)"
RESULTS="$HERE/RESULTS.md"

declare -A COMMANDS=(
  [small]="experiments/lazy_dash/run.sh --seeds 5 --time-limit 300"
  [large]="experiments/lazy_dash/run.sh --large --seeds 5"
  [task-layer]="experiments/task_layer/run.sh"
  [ablation]="experiments/ablation/run.sh --workers 1 --seeds 1 --time-limit 60"
  [dispatch-load]="tests/dispatch/under_load.sh --runs ${DISPATCH_LOAD_RUNS:-20} --sorting"
  [validation]="experiments/validation/largest.sh${VALIDATION_PLANS:+ --plans $VALIDATION_PLANS}"
  [scaling]="experiments/scaling/run.sh"
  [paper-all]="experiments/compare/paper_all.sh${PAPER_ALL_BATCH:+ --batch $PAPER_ALL_BATCH}${PAPER_ALL_DB:+ --db $PAPER_ALL_DB}"
  [paper-vs-paper]="experiments/compare/paper_all.sh --spec experiments/compare/paper-vs-paper.json --figures experiments/compare/figures-paper --db ${PAPER_VS_PAPER_DB:-results-compare-paper-profile.db}${PAPER_VS_PAPER_BATCH:+ --batch $PAPER_VS_PAPER_BATCH}"
)
ORDER=(small large task-layer ablation dispatch-load validation scaling paper-all paper-vs-paper)

if [ "${1:-}" = "--list" ]; then
  for s in "${ORDER[@]}"; do printf '%-13s %s\n' "$s" "${COMMANDS[$s]}"; done
  exit 0
fi
if [ "${1:-}" = "-h" ] || [ "${1:-}" = "--help" ]; then
  sed -n '2,30p' "${BASH_SOURCE[0]}" | sed 's/^# \{0,1\}//'
  exit 0
fi
SECTIONS=("$@")
[ ${#SECTIONS[@]} -eq 0 ] && SECTIONS=("${ORDER[@]}")
for s in "${SECTIONS[@]}"; do
  [ -n "${COMMANDS[$s]:-}" ] || { echo "results.sh: unknown section '$s' (see --list)" >&2; exit 2; }
done

commit="$(git -C "$ROOT" rev-parse --short HEAD 2>/dev/null || echo unknown)"
[ -n "$(git -C "$ROOT" status --porcelain --untracked-files=no 2>/dev/null)" ] && commit="$commit+changes"

# Replaces the text between the section's markers in RESULTS.md with the file $2 (appends the section if
# RESULTS.md lacks it).
replace_section() {
  local name="$1" body="$2"
  python3 - "$RESULTS" "$name" "$body" <<'EOF'
import sys
path, name, body_path = sys.argv[1], sys.argv[2], sys.argv[3]
body = open(body_path).read().rstrip("\n") + "\n"
begin, end = f"<!-- section:{name} -->\n", f"<!-- end:{name} -->"
try:
    text = open(path).read()
except FileNotFoundError:
    text = "# Measured results\n"
if begin in text and end in text:
    head, rest = text.split(begin, 1)
    _, tail = rest.split(end, 1)
    text = head + begin + body + end + tail
else:
    text = text.rstrip("\n") + "\n\n" + begin + body + end + "\n"
open(path, "w").write(text)
EOF
}

for s in "${SECTIONS[@]}"; do
  out="$(mktemp)"
  echo "results.sh: $s: ${COMMANDS[$s]}" >&2
  {
    printf 'Generated by `%s` at %s, %s, on %s (%s cores).\n\n' "${COMMANDS[$s]}" "$commit" "$(date -u +%Y-%m-%d)" \
      "$(uname -n)" "$(nproc)"
    (cd "$ROOT" && bash -c "${COMMANDS[$s]}")
  } >"$out"
  replace_section "$s" "$out"
  rm -f "$out"
done
