#!/usr/bin/env bash
# The paper's comparison on all five families (paper-all.json: 420 runs, 3 seeds, 600 s per run, both
# planners, the axis stop rule) and the RESULTS.md section that shows it: where each planner breaks,
# per family, the paper's figures (representation sizes, time breakdown, success rate) and the table of
# the paper's claims beside what the batch measured (verdict.py).
#
#   experiments/compare/paper_all.sh [--db DB] [--workers N]    # run the batch (or resume the last
#                                                               # unfinished one of DB), then the section
#   experiments/compare/paper_all.sh --batch ID [--db DB]       # the section of a batch already run
#   experiments/compare/paper_all.sh --spec experiments/compare/paper-vs-paper.json --db DB
#                                    # the same for paper profile against paper profile (issue 37)
#
# Options: --db DB (default results-compare-paper.db), --workers N (default 2), --figures DIR (default
# experiments/compare/figures: FAMILY-{sizes,time,success}.{svg,png} and report.txt, the full report).
# The section goes to stdout, with image links relative to experiments/RESULTS.md. On 2 cores the batch
# takes 7.6-35 hours (`./dashbench batch plan experiments/compare/paper-all.json --workers 2`); it can be
# interrupted at any time and this command run again resumes it.
# DASHBENCH names the dashbench to use (default: the repository's ./dashbench, which builds first).
set -euo pipefail

HERE="$(cd "$(dirname "${BASH_SOURCE[0]}")" && pwd)"
ROOT="$(cd "$HERE/../.." && pwd)"
DASHBENCH="${DASHBENCH:-$ROOT/dashbench}"
SPEC="$HERE/paper-all.json"
DB="results-compare-paper.db"
WORKERS=2
BATCH=""
FIGURES="$HERE/figures"

while [ $# -gt 0 ]; do
  case "$1" in
    --db) DB="$2"; shift 2 ;;
    --spec) SPEC="$2"; shift 2 ;;
    --workers) WORKERS="$2"; shift 2 ;;
    --batch) BATCH="$2"; shift 2 ;;
    --figures) FIGURES="$2"; shift 2 ;;
    -h|--help) sed -n '2,17p' "${BASH_SOURCE[0]}" | sed 's/^# \{0,1\}//'; exit 0 ;;
    *) echo "paper_all.sh: unknown argument $1 (see --help)" >&2; exit 2 ;;
  esac
done

spec_name="$(python3 -c 'import json, sys; print(json.load(open(sys.argv[1]))["name"])' "$SPEC")"

# The newest batch of this spec in DB whose runs are not all finished, if any.
unfinished_batch() {
  [ -f "$DB" ] || return 0
  "$DASHBENCH" batch status --db "$DB" | awk -v name="$spec_name" \
    'NR > 1 && $2 == name && ($11 > 0 || $12 > 0 || $3 != "finished") { id = $1 } END { if (id) print id }'
}

if [ -z "$BATCH" ]; then
  BATCH="$(unfinished_batch)"
  if [ -n "$BATCH" ]; then
    echo "paper_all.sh: resuming $BATCH in $DB" >&2
    "$DASHBENCH" batch resume --db "$DB" "$BATCH" --workers "$WORKERS" --quiet >&2
  else
    "$DASHBENCH" batch run "$SPEC" --db "$DB" --workers "$WORKERS" --quiet >&2
    BATCH="$("$DASHBENCH" batch status --db "$DB" | awk -v name="$spec_name" 'NR > 1 && $2 == name { id = $1 } END { print id }')"
  fi
fi

mkdir -p "$FIGURES"
"$DASHBENCH" report "$DB" --batch "$BATCH" --figures "$FIGURES" > "$FIGURES/report.txt"

# Image links are relative to experiments/RESULTS.md.
link_dir="$(python3 -c 'import os, sys; print(os.path.relpath(sys.argv[1], sys.argv[2]))' "$FIGURES" "$ROOT/experiments")"

status_line="$("$DASHBENCH" batch status --db "$DB" "$BATCH" | awk 'NR == 2')"
read -r _ _ state runs solved timeout infeasible crashed cancelled skipped running pending created <<< "$status_line"
echo "Batch \`$BATCH\` ($state, created $created): $runs runs: $solved solved, $timeout timeout,"
echo "$infeasible infeasible, $crashed crashed or out of memory, $skipped skipped by the axis stop rule, $((running + pending)) not run yet."
echo "The full report (sizes, times and success per size and planner): \`$link_dir/report.txt\`."
echo

python3 - "$FIGURES/report.txt" "$link_dir" <<'EOF'
import re, sys
report, link_dir = open(sys.argv[1]).read(), sys.argv[2]
# One block per family: "== FAMILY (N finished runs; ...) ==", then its tables.
for match in re.finditer(r"^== (\S+) \((.*?)\) ==\n(.*?)(?=^== |\Z)", report, re.S | re.M):
    family, heading, body = match.group(1), match.group(2), match.group(3)
    print(f"### {family.capitalize()} ({heading.split(';')[0]})\n")
    breaks = re.search(r"^Where each planner breaks.*?(?=\n\n|\Z)", body, re.S | re.M)
    if breaks:
        print("```\n" + breaks.group(0).rstrip() + "\n```\n")
    for kind, caption in (("sizes", "representation sizes"), ("time", "planning time by phase"),
                          ("success", "success rate")):
        print(f"![{family} {caption}]({link_dir}/{family}-{kind}.svg)")
    print()
EOF

echo
echo "**The paper's claims beside this batch**, by \`experiments/compare/verdict.py $(basename "$DB") $BATCH\` (its"
echo "header states each rule: sizes solved on every seed, ratios DaSH / Lazy-DaSH of the medians per size):"
echo
python3 "$HERE/verdict.py" "$DB" "$BATCH"
