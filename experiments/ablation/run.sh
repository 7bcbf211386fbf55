#!/usr/bin/env bash
# The Lazy-DaSH ablation: runs a batch spec (default ablation.json: the small cases sorting 4x8, wall
# 8/2/16, shelf-wall 2/8, stocking 2/8 and lab 2, with Lazy-DaSH as it is, each extension beyond the
# paper off in turn, and all of them off; 3 seeds, 300 s per run) and prints markdown tables for
# RESULTS.md, grouped by the spec's configuration labels: per configuration and scene, runs solved and
# the median total time; per scene, medians over the solved runs of the representation sizes, roadmap,
# collision checks and constraints; and every unsolved run with its status and error.
#
#   experiments/ablation/run.sh [SPEC] [--db DB] [--workers N] [--seeds N] [--time-limit SEC]
#   experiments/ablation/run.sh --table BATCH_ID [--db DB]     # tables of a batch already run
#
# Defaults: --db results-ablation.db, --workers nproc-1 (at least 1), the spec's seeds and time limit
# (--seeds N: the spec's first N seeds; both options rewrite a temporary copy of the spec). DASHBENCH
# names the dashbench to use (default: the repository's ./dashbench, which builds first). The batch
# can be interrupted (Ctrl-C) and resumed: ./dashbench batch resume --db DB BATCH_ID, then --table.
set -euo pipefail

HERE="$(cd "$(dirname "${BASH_SOURCE[0]}")" && pwd)"
ROOT="$(cd "$HERE/../.." && pwd)"
DASHBENCH="${DASHBENCH:-$ROOT/dashbench}"
SPEC="$HERE/ablation.json"
DB="results-ablation.db"
WORKERS=""
TIME_LIMIT=""
SEEDS=""
TABLE_ONLY=""

usage() { sed -n '2,15p' "${BASH_SOURCE[0]}" | sed 's/^# \{0,1\}//'; }
need() { [ $# -ge 2 ] || { echo "run.sh: $1 needs a value" >&2; exit 2; }; }

while [ $# -gt 0 ]; do
  case "$1" in
    --db) need "$@"; DB="$2"; shift 2 ;;
    --workers) need "$@"; WORKERS="$2"; shift 2 ;;
    --time-limit) need "$@"; TIME_LIMIT="$2"; shift 2 ;;
    --seeds) need "$@"; SEEDS="$2"; shift 2 ;;
    --table) need "$@"; TABLE_ONLY="$2"; shift 2 ;;
    -h|--help) usage; exit 0 ;;
    -*) echo "run.sh: unknown option $1" >&2; exit 2 ;;
    *) SPEC="$1"; shift ;;
  esac
done

if [ -z "$WORKERS" ]; then
  # One run per core but one, so that timings are not inflated by contention.
  WORKERS=$(( $(nproc) > 1 ? $(nproc) - 1 : 1 ))
fi
[[ "$WORKERS" =~ ^[1-9][0-9]*$ ]] || { echo "run.sh: --workers expects a positive integer" >&2; exit 2; }
[ -z "$SEEDS" ] || [[ "$SEEDS" =~ ^[1-9][0-9]*$ ]] || { echo "run.sh: --seeds expects a positive integer" >&2; exit 2; }
[ -z "$TIME_LIMIT" ] || [[ "$TIME_LIMIT" =~ ^[0-9]+([.][0-9]+)?$ ]] ||
  { echo "run.sh: --time-limit expects seconds" >&2; exit 2; }

# Prints one CSV result (from `dashbench db query`) as a markdown table: quoted fields may hold commas
# and doubled quotes; '|' in a field is escaped.
markdown() {
  awk '
    function split_csv(line,   i, c, f, quoted, n) {
      n = 0; f = ""; quoted = 0
      for (i = 1; i <= length(line); i++) {
        c = substr(line, i, 1)
        if (quoted) {
          if (c == "\"") { if (substr(line, i + 1, 1) == "\"") { f = f "\""; i++ } else quoted = 0 }
          else f = f c
        } else if (c == "\"") quoted = 1
        else if (c == ",") { cell[++n] = f; f = "" }
        else f = f c
      }
      cell[++n] = f
      return n
    }
    { sub(/\r$/, ""); n = split_csv($0); printf "|"
      for (i = 1; i <= n; i++) { gsub(/\|/, "\\|", cell[i]); printf " %s |", cell[i] }
      print ""
      if (NR == 1) { printf "|"; for (i = 1; i <= n; i++) printf "---|"; print "" } }'
}

query() { "$DASHBENCH" db query "$DB" "$1" --format csv --max-rows 100000; }
# One query's rows without the header line, unquoted (for single-column results).
values() { query "$1" | tail -n +2 | sed 's/^"//; s/"$//; s/""/"/g'; }
# A text as an SQL string literal.
lit() { printf "'%s'" "${1//\'/\'\'}"; }

# Runs of batch $1 that ended, with their configuration label (dash_planner_configs.name: the spec's
# "label", or the planner plus its settings when it has none) and scene ("sorting r=4 o=8",
# "wall r=8 w=2 o=16", "stocking layers=2 o=8", "lab containers=2"), and the CTEs over them:
#   lord/sord  configurations and scenes in the spec's order (the runner starts runs in that order),
#   c          per (label, scene): runs, solved, timeouts, infeasible, crashed,
#   w          per (label, scene): medians over the solved runs,
#   cells      per (label, scene): cell "solved/runs median-total s (failures)", outcome without the time.
with_sql() {
  local id="$1"
  cat <<EOF
WITH r AS (
  SELECT r.id, c.name AS label, r.family,
         r.family || IFNULL((SELECT ' ' || group_concat(k || '=' || v, ' ') FROM (
           SELECT CASE key WHEN 'robots' THEN 'r' WHEN 'walls' THEN 'w' WHEN 'objects' THEN 'o' ELSE key END AS k,
                  value AS v FROM json_each(r.params)
           ORDER BY CASE key WHEN 'robots' THEN 0 WHEN 'walls' THEN 1 WHEN 'objects' THEN 3 ELSE 2 END, key)), '') AS scene,
         r.seed, r.status, r.error, r.total_time, r.task_vertices, r.motion_vertices, r.motion_extended_vertices,
         r.roadmap_vertices, r.collision_checks, r.iterations, r.constraints_motion,
         r.constraints_frontier + r.constraints_history + r.constraints_interaction AS constraints_task
  FROM dash_runs r JOIN dash_planner_configs c ON c.id = r.planner_config_id
  WHERE r.batch_id = $(lit "$id") AND r.status NOT IN ('running', 'cancelled', 'pending')),
lord AS (SELECT label, MIN(id) AS o FROM r GROUP BY label),
sord AS (SELECT scene, MIN(id) AS o FROM r GROUP BY scene),
long(label, scene, m, v) AS (
            SELECT label, scene, 'total', total_time FROM r WHERE status = 'solved'
  UNION ALL SELECT label, scene, 'tv', task_vertices FROM r WHERE status = 'solved'
  UNION ALL SELECT label, scene, 'mv', motion_vertices FROM r WHERE status = 'solved'
  UNION ALL SELECT label, scene, 'mev', motion_extended_vertices FROM r WHERE status = 'solved'
  UNION ALL SELECT label, scene, 'rv', roadmap_vertices FROM r WHERE status = 'solved'
  UNION ALL SELECT label, scene, 'cc', collision_checks FROM r WHERE status = 'solved'
  UNION ALL SELECT label, scene, 'tcn', constraints_task FROM r WHERE status = 'solved'
  UNION ALL SELECT label, scene, 'mcn', constraints_motion FROM r WHERE status = 'solved'
  UNION ALL SELECT label, scene, 'it', iterations FROM r WHERE status = 'solved'),
ranked AS (SELECT label, scene, m, v, ROW_NUMBER() OVER (PARTITION BY label, scene, m ORDER BY v) AS i,
                  COUNT(*) OVER (PARTITION BY label, scene, m) AS n FROM long WHERE v IS NOT NULL),
med AS (SELECT label, scene, m, AVG(v) AS v FROM ranked WHERE i IN ((n + 1) / 2, (n + 2) / 2) GROUP BY label, scene, m),
w AS (SELECT label, scene,
        MAX(CASE m WHEN 'total' THEN v END) AS total, MAX(CASE m WHEN 'tv' THEN v END) AS tv,
        MAX(CASE m WHEN 'mv' THEN v END) AS mv, MAX(CASE m WHEN 'mev' THEN v END) AS mev,
        MAX(CASE m WHEN 'rv' THEN v END) AS rv, MAX(CASE m WHEN 'cc' THEN v END) AS cc,
        MAX(CASE m WHEN 'tcn' THEN v END) AS tcn, MAX(CASE m WHEN 'mcn' THEN v END) AS mcn,
        MAX(CASE m WHEN 'it' THEN v END) AS it
      FROM med GROUP BY label, scene),
c AS (SELECT label, scene, COUNT(*) AS runs, SUM(status = 'solved') AS solved, SUM(status = 'timeout') AS timeouts,
             SUM(status = 'infeasible') AS infeasible, SUM(status NOT IN ('solved', 'timeout', 'infeasible')) AS crashed
      FROM r GROUP BY label, scene),
cells AS (SELECT c.label, c.scene, c.runs, c.solved, c.timeouts, c.infeasible, c.crashed, w.total,
            c.solved || '/' || c.runs ||
            CASE WHEN w.total IS NULL THEN '' ELSE ' ' || $(fixed w.total 2) || ' s' END || $(failures c) AS cell,
            c.solved || '/' || c.runs || $(failures c) AS outcome
          FROM c LEFT JOIN w ON w.label = c.label AND w.scene = c.scene)
EOF
}

# " (1 timeout; 2 crashed)" from the columns timeouts, infeasible, crashed of table $1; '' when none.
failures() {
  echo "CASE WHEN $1.timeouts + $1.infeasible + $1.crashed > 0 THEN ' (' || SUBSTR(
      CASE WHEN $1.timeouts > 0 THEN '; ' || $1.timeouts || ' timeout' ELSE '' END ||
      CASE WHEN $1.infeasible > 0 THEN '; ' || $1.infeasible || ' infeasible' ELSE '' END ||
      CASE WHEN $1.crashed > 0 THEN '; ' || $1.crashed || ' crashed' ELSE '' END, 3) || ')' ELSE '' END"
}
# A non-negative number $1 (SQL) as text with $2 decimals: `db query` refuses printf().
fixed() {
  local scale=$((10 ** $2)) n="CAST(ROUND(($1) * $((10 ** $2))) AS INTEGER)"
  echo "(($n / $scale) || '.' || SUBSTR('000000' || ($n % $scale), -$2))"
}
# A median as text: '-' when there is none, an integer when it is one, else one decimal.
num() { echo "CASE WHEN $1 IS NULL THEN '-' WHEN $1 = CAST($1 AS INTEGER) THEN CAST(CAST($1 AS INTEGER) AS TEXT) ELSE $(fixed "$1" 1) END"; }

tables() {
  local id="$1" with
  with="$(with_sql "$id")"
  local scenes=() labels=()
  mapfile -t scenes < <(values "$with SELECT scene FROM sord ORDER BY o")
  mapfile -t labels < <(values "$with SELECT label FROM lord ORDER BY o")
  if [ ${#scenes[@]} -eq 0 ]; then
    echo "run.sh: batch $id has no finished runs in $DB" >&2
    exit 1
  fi
  local first="${labels[0]}"
  local info
  info="$(values "SELECT (SELECT COUNT(DISTINCT planner_config_id) FROM dash_runs WHERE batch_id = $(lit "$id"))
      || ' configurations x ' || (SELECT COUNT(DISTINCT family || params) FROM dash_runs WHERE batch_id = $(lit "$id"))
      || ' scenes x ' || (SELECT COUNT(DISTINCT seed) || CASE COUNT(DISTINCT seed) WHEN 1 THEN ' seed, ' ELSE ' seeds, ' END
                          FROM dash_runs WHERE batch_id = $(lit "$id"))
      || IFNULL((SELECT CASE WHEN t = CAST(t AS INTEGER) THEN CAST(CAST(t AS INTEGER) AS TEXT) ELSE CAST(t AS TEXT) END
                 FROM (SELECT MAX(time_limit) AS t FROM dash_runs WHERE batch_id = $(lit "$id"))), '?') || ' s per run'
      || IFNULL((SELECT '; ' || COUNT(*) || ' runs did not finish (' || group_concat(DISTINCT status) || ')'
                 FROM dash_runs WHERE batch_id = $(lit "$id") AND status IN ('running', 'cancelled', 'pending')
                 HAVING COUNT(*) > 0), '') AS info")"

  echo "Batch $id: $info. Medians over the solved runs."
  echo
  echo "Runs solved / runs and median total time per configuration and scene, with why the others were"
  echo "not solved (timeout: the time limit was spent; infeasible: the planner gave up; crashed: the run's"
  echo "process failed). \"total / $first\": the median over the scenes both solved of the ratio of"
  echo "median total times (scenes where $first took at least 0.1 s)."
  echo
  local cols="" s
  for s in "${scenes[@]}"; do
    cols+="IFNULL((SELECT cell FROM cells WHERE cells.label = lord.label AND cells.scene = $(lit "$s")), '-') AS \"${s//\"/\"\"}\", "
  done
  query "$with,
  ratios AS (SELECT a.label, a.total / b.total AS x,
                    ROW_NUMBER() OVER (PARTITION BY a.label ORDER BY a.total / b.total) AS i,
                    COUNT(*) OVER (PARTITION BY a.label) AS n
             FROM w a JOIN w b ON b.scene = a.scene AND b.label = $(lit "$first")
             WHERE a.total IS NOT NULL AND b.total >= 0.1),
  ratio AS (SELECT label, AVG(x) AS x FROM ratios WHERE i IN ((n + 1) / 2, (n + 2) / 2) GROUP BY label),
  tot AS (SELECT label, SUM(runs) AS runs, SUM(solved) AS solved, SUM(timeouts) AS timeouts,
                 SUM(infeasible) AS infeasible, SUM(crashed) AS crashed FROM c GROUP BY label)
  SELECT lord.label AS Configuration, $cols
    tot.solved || '/' || tot.runs || $(failures tot) AS \"all scenes\",
    CASE WHEN ratio.x IS NULL THEN '-' ELSE $(fixed ratio.x 2) || 'x' END AS \"total / ${first//\"/\"\"}\"
  FROM lord JOIN tot ON tot.label = lord.label LEFT JOIN ratio ON ratio.label = lord.label
  ORDER BY lord.o" | markdown

  echo
  echo "Per scene, medians over the solved runs: total time, representation sizes (vertices of H_T, H_M,"
  echo "H_ME), the vertices of the roadmaps under H_M, collision checks, task constraints (frontier +"
  echo "history + interaction), motion constraints and iterations."
  for s in "${scenes[@]}"; do
    echo
    echo "**$s**"
    echo
    query "$with,
    base AS (SELECT total FROM w WHERE label = $(lit "$first") AND scene = $(lit "$s"))
    SELECT lord.label AS Configuration, IFNULL(cells.outcome, '-') AS solved,
      CASE WHEN w.total IS NULL THEN '-' ELSE $(fixed w.total 2) END AS \"total (s)\",
      CASE WHEN w.total IS NULL OR NOT (SELECT total FROM base) >= 0.1 THEN '-'
           ELSE $(fixed "w.total / (SELECT total FROM base)" 2) || 'x' END AS \"total / ${first//\"/\"\"}\",
      $(num w.tv) AS \"H_T V\", $(num w.mv) AS \"H_M V\", $(num w.mev) AS \"H_ME V\", $(num w.rv) AS \"roadmap V\",
      $(num w.cc) AS \"collision checks\", $(num w.tcn) AS \"task constraints\",
      $(num w.mcn) AS \"motion constraints\", $(num w.it) AS iterations
    FROM lord LEFT JOIN cells ON cells.label = lord.label AND cells.scene = $(lit "$s")
              LEFT JOIN w ON w.label = lord.label AND w.scene = $(lit "$s")
    ORDER BY lord.o" | markdown
  done

  echo
  local unsolved
  unsolved="$(values "$with SELECT COUNT(*) FROM r WHERE status <> 'solved'")"
  if [ "$unsolved" = "0" ]; then
    echo "Every run was solved."
  else
    echo "Unsolved runs"
    echo
    query "$with SELECT r.label AS Configuration, r.scene AS Scene, r.seed AS Seed, r.status AS Status,
        CASE WHEN r.total_time IS NULL THEN '-' ELSE $(fixed r.total_time 1) END AS \"time (s)\",
        IFNULL(SUBSTR(REPLACE(REPLACE(r.error, char(10), ' '), char(13), ' '), 1, 160), '') AS Error
      FROM r JOIN lord ON lord.label = r.label JOIN sord ON sord.scene = r.scene
      WHERE r.status <> 'solved' ORDER BY lord.o, sord.o, r.seed" | markdown
  fi
}

if [ -n "$TABLE_ONLY" ]; then
  tables "$TABLE_ONLY"
  exit 0
fi

RUN_SPEC="$SPEC"
if [ -n "$TIME_LIMIT" ] || [ -n "$SEEDS" ]; then
  RUN_SPEC="$(mktemp --suffix=.json)"
  trap 'rm -f "$RUN_SPEC"' EXIT
  # The spec's JSON, not its lines: "seeds" may span several lines.
  python3 - "$SPEC" "$RUN_SPEC" "$TIME_LIMIT" "$SEEDS" <<'PY'
import json, sys
src, dst, limit, seeds = sys.argv[1:]
with open(src) as f:
    spec = json.load(f)
if limit:
    spec["time_limit"] = float(limit) if "." in limit else int(limit)
if seeds:
    old = spec.get("seeds")
    start = old.get("from", 1) if isinstance(old, dict) else 1
    spec["seeds"] = {"from": start, "count": int(seeds)}
with open(dst, "w") as f:
    json.dump(spec, f, indent=2)
PY
fi
ID="$(basename "$SPEC" .json)-$(date +%Y%m%d-%H%M%S)"
echo "run.sh: batch $ID ($RUN_SPEC, $WORKERS workers) into $DB" >&2
"$DASHBENCH" batch run "$RUN_SPEC" --db "$DB" --workers "$WORKERS" --id "$ID" --quiet >&2
tables "$ID"
