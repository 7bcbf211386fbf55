#!/usr/bin/env bash
# Lazy-DaSH vs DaSH on the same scenes and seeds: runs a batch spec (default compare.json: Sorting
# with 4 robots and 4-14 objects, Wall with 5 robots, 2 walls and 2-10 objects, 5 seeds) and prints markdown
# tables for the README: per scene, medians over the solved runs of each planner, the total time
# ratio DaSH / Lazy-DaSH, representation sizes and the time breakdown.
#
#   experiments/compare/run.sh [SPEC] [--db DB] [--workers N] [--time-limit SEC] [--seeds N]
#   experiments/compare/run.sh --quick [...]                   # compare-quick.json: 16 runs
#   experiments/compare/run.sh --table BATCH_ID [--db DB]      # tables of a batch already run
#
# DASHBENCH names the dashbench to use (default: the repository's ./dashbench, which builds first).
# The batch can be interrupted (Ctrl-C) and resumed: ./dashbench batch resume --db DB BATCH_ID.
set -euo pipefail

HERE="$(cd "$(dirname "${BASH_SOURCE[0]}")" && pwd)"
ROOT="$(cd "$HERE/../.." && pwd)"
DASHBENCH="${DASHBENCH:-$ROOT/dashbench}"
SPEC="$HERE/compare.json"
DB="results-compare.db"
WORKERS=""
TIME_LIMIT=""
SEEDS=""
TABLE_ONLY=""

while [ $# -gt 0 ]; do
  case "$1" in
    --db) DB="$2"; shift 2 ;;
    --workers) WORKERS="$2"; shift 2 ;;
    --time-limit) TIME_LIMIT="$2"; shift 2 ;;
    --seeds) SEEDS="$2"; shift 2 ;;
    --table) TABLE_ONLY="$2"; shift 2 ;;
    --quick) SPEC="$HERE/compare-quick.json"; shift ;;
    -h|--help) sed -n '2,13p' "${BASH_SOURCE[0]}" | sed 's/^# \{0,1\}//'; exit 0 ;;
    -*) echo "run.sh: unknown option $1" >&2; exit 2 ;;
    *) SPEC="$1"; shift ;;
  esac
done

if [ -z "$WORKERS" ]; then
  # One run per core but one, so that timings are not inflated by contention.
  WORKERS=$(( $(nproc) > 1 ? $(nproc) - 1 : 1 ))
fi

# Prints one CSV result (from `dashbench db query`) as a markdown table.
markdown() {
  awk -F, '
    { gsub(/"/, ""); printf "|"; for (i = 1; i <= NF; i++) printf " %s |", $i; print "" }
    NR == 1 { printf "|"; for (i = 1; i <= NF; i++) printf "---|"; print "" }'
}

query() { "$DASHBENCH" db query "$DB" "$1" --format csv --max-rows 100000; }

# SQL that formats numbers as printf() did: `db query` refuses printf() and format() (commit 329325f).
# int X: X as printf('%d') writes it: truncated to an integer, 0 for NULL.
int() { echo "CAST(IFNULL($1, 0) AS INTEGER)"; }
# fixed X N: X as printf('%.Nf') writes it (N >= 1 decimals), NULL for NULL.
fixed() {
  local scale=$((10 ** $2))
  local n="CAST(ROUND(ROUND(ABS($1), $2) * $scale) AS INTEGER)"
  echo "(CASE WHEN ($1) < 0 THEN '-' ELSE '' END || ($n / $scale) || '.' || SUBSTR('000000' || ($n % $scale), -$2))"
}

# The scene column of a batch's runs: "sorting r=4 o=8", "wall r=5 w=2 o=4".
scene_sql="CASE family WHEN 'wall' THEN 'wall r=' || $(int "json_extract(params, '\$.robots')")
                || ' w=' || $(int "json_extract(params, '\$.walls')") || ' o=' || $(int "json_extract(params, '\$.objects')")
             ELSE IFNULL(family, '') || ' r=' || $(int "json_extract(params, '\$.robots')")
                || ' o=' || $(int "json_extract(params, '\$.objects')")
           END AS scene,"

# CTEs "ranked" and "med": the median of each (scene, planner, m) of a long(scene, planner, m, v) table;
# $1 filters long's rows.
medians() {
  echo "ranked AS (SELECT scene, planner, m, v, ROW_NUMBER() OVER (PARTITION BY scene, planner, m ORDER BY v) AS i,
                    COUNT(*) OVER (PARTITION BY scene, planner, m) AS n FROM long $1),
  med AS (SELECT scene, planner, m, AVG(v) AS v FROM ranked WHERE i IN ((n + 1) / 2, (n + 2) / 2)
          GROUP BY scene, planner, m),"
}

tables() {
  local id="$1"
  # Runs of the batch, medians over the solved runs per (scene, planner), in long then wide form.
  local with
  with="WITH r AS (
    SELECT family, json_extract(params, '\$.objects') AS objects, planner, status,
           $scene_sql
           total_time, time_task_construction, time_task_query, time_task_conflict_detection,
           time_motion_construction, time_motion_query, time_conflict_resolution,
           task_vertices, task_hyperarcs, task_extended_vertices, task_extended_hyperarcs,
           motion_vertices, motion_hyperarcs, motion_extended_vertices, motion_extended_hyperarcs,
           collision_checks_eager, collision_checks_lazy, iterations, constraints_motion,
           roadmap_vertices, roadmap_edges
    FROM dash_runs WHERE batch_id = '$id' AND status NOT IN ('running', 'cancelled', 'pending')),
  long(scene, planner, m, v) AS (
              SELECT scene, planner, 'total', total_time FROM r WHERE status = 'solved'
    UNION ALL SELECT scene, planner, 'tc', time_task_construction FROM r WHERE status = 'solved'
    UNION ALL SELECT scene, planner, 'tq', time_task_query FROM r WHERE status = 'solved'
    UNION ALL SELECT scene, planner, 'td', time_task_conflict_detection FROM r WHERE status = 'solved'
    UNION ALL SELECT scene, planner, 'mc', time_motion_construction FROM r WHERE status = 'solved'
    UNION ALL SELECT scene, planner, 'mq', time_motion_query FROM r WHERE status = 'solved'
    UNION ALL SELECT scene, planner, 'cr', time_conflict_resolution FROM r WHERE status = 'solved'
    UNION ALL SELECT scene, planner, 'tv', task_vertices FROM r WHERE status = 'solved'
    UNION ALL SELECT scene, planner, 'ta', task_hyperarcs FROM r WHERE status = 'solved'
    UNION ALL SELECT scene, planner, 'tev', task_extended_vertices FROM r WHERE status = 'solved'
    UNION ALL SELECT scene, planner, 'tea', task_extended_hyperarcs FROM r WHERE status = 'solved'
    UNION ALL SELECT scene, planner, 'mv', motion_vertices FROM r WHERE status = 'solved'
    UNION ALL SELECT scene, planner, 'ma', motion_hyperarcs FROM r WHERE status = 'solved'
    UNION ALL SELECT scene, planner, 'mev', motion_extended_vertices FROM r WHERE status = 'solved'
    UNION ALL SELECT scene, planner, 'mea', motion_extended_hyperarcs FROM r WHERE status = 'solved'
    UNION ALL SELECT scene, planner, 'ce', collision_checks_eager FROM r WHERE status = 'solved'
    UNION ALL SELECT scene, planner, 'cl', collision_checks_lazy FROM r WHERE status = 'solved'
    UNION ALL SELECT scene, planner, 'rv', roadmap_vertices FROM r WHERE status = 'solved'
    UNION ALL SELECT scene, planner, 're', roadmap_edges FROM r WHERE status = 'solved'),
  $(medians "")
  w AS (SELECT scene, planner,
          MAX(CASE m WHEN 'total' THEN v END) AS total, MAX(CASE m WHEN 'tc' THEN v END) AS tc,
          MAX(CASE m WHEN 'tq' THEN v END) AS tq, MAX(CASE m WHEN 'td' THEN v END) AS td,
          MAX(CASE m WHEN 'mc' THEN v END) AS mc, MAX(CASE m WHEN 'mq' THEN v END) AS mq,
          MAX(CASE m WHEN 'cr' THEN v END) AS cr, MAX(CASE m WHEN 'tv' THEN v END) AS tv,
          MAX(CASE m WHEN 'ta' THEN v END) AS ta, MAX(CASE m WHEN 'tev' THEN v END) AS tev,
          MAX(CASE m WHEN 'tea' THEN v END) AS tea, MAX(CASE m WHEN 'mv' THEN v END) AS mv,
          MAX(CASE m WHEN 'ma' THEN v END) AS ma, MAX(CASE m WHEN 'mev' THEN v END) AS mev,
          MAX(CASE m WHEN 'mea' THEN v END) AS mea, MAX(CASE m WHEN 'ce' THEN v END) AS ce,
          MAX(CASE m WHEN 'cl' THEN v END) AS cl, MAX(CASE m WHEN 'rv' THEN v END) AS rv,
          MAX(CASE m WHEN 're' THEN v END) AS re
        FROM med GROUP BY scene, planner),
  c AS (SELECT scene, planner, MIN(family) AS family, MIN(objects) AS objects, COUNT(*) AS runs,
               SUM(status = 'solved') AS solved, SUM(status = 'timeout') AS timeouts,
               SUM(status = 'infeasible') AS infeasible,
               SUM(status NOT IN ('solved', 'timeout', 'infeasible')) AS crashed
        FROM r GROUP BY scene, planner),
  s AS (SELECT DISTINCT scene, family, objects FROM c),
  j AS (SELECT s.scene, s.family, s.objects,
               lc.runs AS l_runs, lc.solved AS l_solved, dc.runs AS d_runs, dc.solved AS d_solved,
               lc.timeouts AS l_timeouts, lc.infeasible AS l_infeasible, lc.crashed AS l_crashed,
               dc.timeouts AS d_timeouts, dc.infeasible AS d_infeasible, dc.crashed AS d_crashed,
               l.total AS l_total, d.total AS d_total, l.tv AS l_tv, l.ta AS l_ta, d.tv AS d_tv, d.ta AS d_ta,
               l.tev AS l_tev, l.tea AS l_tea, l.mv AS l_mv, l.ma AS l_ma, d.mv AS d_mv, d.ma AS d_ma,
               l.mev AS l_mev, l.mea AS l_mea, d.mev AS d_mev, d.mea AS d_mea,
               l.ce AS l_ce, l.cl AS l_cl, d.ce AS d_ce, d.cl AS d_cl,
               l.rv AS l_rv, l.re AS l_re, d.rv AS d_rv, d.re AS d_re
        FROM s LEFT JOIN c lc ON lc.scene = s.scene AND lc.planner = 'lazy-dash'
               LEFT JOIN c dc ON dc.scene = s.scene AND dc.planner = 'dash'
               LEFT JOIN w l ON l.scene = s.scene AND l.planner = 'lazy-dash'
               LEFT JOIN w d ON d.scene = s.scene AND d.planner = 'dash')"
  # A median with 2 decimals, '-' when there is none.
  num() { echo "CASE WHEN $1 IS NULL THEN '-' ELSE $(fixed "$1" 2) END"; }
  # "vertices/hyperarcs" (integers), '-' when there is no first one.
  pair() { echo "CASE WHEN $1 IS NULL THEN '-' ELSE $(int "$1") || '/' || $(int "$2") END"; }
  # solved/runs and why the others failed, e.g. "3/5 (1 timeout; 1 infeasible)" (no commas: CSV).
  outcome() {
    echo "$(int "${1}_solved") || '/' || $(int "${1}_runs") ||
      CASE WHEN IFNULL(${1}_runs, 0) > IFNULL(${1}_solved, 0) THEN ' (' || SUBSTR(
        CASE WHEN ${1}_timeouts > 0 THEN '; ' || $(int "${1}_timeouts") || ' timeout' ELSE '' END ||
        CASE WHEN ${1}_infeasible > 0 THEN '; ' || $(int "${1}_infeasible") || ' infeasible' ELSE '' END ||
        CASE WHEN ${1}_crashed > 0 THEN '; ' || $(int "${1}_crashed") || ' crashed' ELSE '' END, 3) || ')' ELSE '' END"
  }
  # $2 / $1 with one decimal and an x, '-' unless $1 > 0 and $2 is known.
  ratio() { echo "CASE WHEN $1 > 0 AND $2 IS NOT NULL THEN $(fixed "1.0 * $2 / $1" 1) || 'x' ELSE '-' END"; }

  echo "Batch $id (medians over the solved runs; x = DaSH / Lazy-DaSH)"
  echo
  echo "Total time and motion representation"
  echo
  query "$with SELECT scene AS Scene,
      $(outcome l) AS \"Lazy solved\", $(outcome d) AS \"DaSH solved\",
      $(num l_total) AS \"Lazy total (s)\", $(num d_total) AS \"DaSH total (s)\",
      $(ratio l_total d_total) AS \"total x\",
      $(pair l_mv l_ma) AS \"Lazy H_M V/A\", $(pair d_mv d_ma) AS \"DaSH H_M V/A\",
      $(ratio l_ma d_ma) AS \"H_M A x\", $(ratio l_mv d_mv) AS \"H_M V x\"
    FROM j ORDER BY family DESC, objects" | markdown
  echo
  echo "Representation sizes (V/A), the roadmaps under H_M (vertices/edges: Lazy-PRM's, unvalidated;"
  echo "DaSH's og::PRM, validated in every planning space) and collision checks (eager / lazy)"
  echo
  query "$with SELECT scene AS Scene,
      $(pair l_tv l_ta) AS \"Lazy H_T\", $(pair d_tv d_ta) AS \"DaSH H_T\", $(pair l_tev l_tea) AS \"Lazy H_TE\",
      $(pair l_mv l_ma) AS \"Lazy H_M\", $(pair d_mv d_ma) AS \"DaSH H_M\",
      $(pair l_mev l_mea) AS \"Lazy H_ME\", $(pair d_mev d_mea) AS \"DaSH H_ME\",
      $(pair l_rv l_re) AS \"Lazy roadmaps\", $(pair d_rv d_re) AS \"DaSH roadmaps\",
      $(pair l_ce l_cl) AS \"Lazy checks\", $(pair d_ce d_cl) AS \"DaSH checks\"
    FROM j ORDER BY family DESC, objects" | markdown
  echo
  echo "Time breakdown (s): task construction / task query / task conflict detection / motion construction /"
  echo "motion query (DaSH: the combined task-and-motion query) / conflict resolution / total"
  echo
  query "$with SELECT w.scene AS Scene, CASE w.planner WHEN 'dash' THEN 'DaSH' ELSE 'Lazy-DaSH' END AS Planner,
      $(num tc) AS \"task constr\", $(num tq) AS \"task query\", $(num td) AS \"task conflicts\",
      $(num mc) AS \"motion constr\", $(num mq) AS \"motion query\", $(num cr) AS \"conflict res\",
      $(num total) AS total
    FROM w JOIN s ON s.scene = w.scene ORDER BY s.family DESC, s.objects, w.planner DESC" | markdown
  echo
  echo "Unsolved runs (timeout: the limit was spent; medians over them): time per phase (s), constraint tree"
  echo "nodes or Lazy-DaSH iterations, motion constraints"
  echo
  query "WITH r AS (
    SELECT family, json_extract(params, '\$.objects') AS objects, planner, status,
           $scene_sql
           time_task_construction, time_task_query, time_task_conflict_detection, time_motion_construction,
           time_motion_query, time_conflict_resolution, total_time, iterations, constraints_motion
    FROM dash_runs WHERE batch_id = '$id' AND status NOT IN ('solved', 'running', 'cancelled', 'pending')),
  long(scene, planner, m, v) AS (
              SELECT scene, planner, 'tc', time_task_construction FROM r
    UNION ALL SELECT scene, planner, 'tq', time_task_query FROM r
    UNION ALL SELECT scene, planner, 'td', time_task_conflict_detection FROM r
    UNION ALL SELECT scene, planner, 'mc', time_motion_construction FROM r
    UNION ALL SELECT scene, planner, 'mq', time_motion_query FROM r
    UNION ALL SELECT scene, planner, 'cr', time_conflict_resolution FROM r
    UNION ALL SELECT scene, planner, 'total', total_time FROM r
    UNION ALL SELECT scene, planner, 'it', iterations FROM r
    UNION ALL SELECT scene, planner, 'mcn', constraints_motion FROM r),
  $(medians "WHERE v IS NOT NULL")
  w AS (SELECT scene, planner,
          MAX(CASE m WHEN 'tc' THEN v END) AS tc, MAX(CASE m WHEN 'tq' THEN v END) AS tq,
          MAX(CASE m WHEN 'td' THEN v END) AS td, MAX(CASE m WHEN 'mc' THEN v END) AS mc,
          MAX(CASE m WHEN 'mq' THEN v END) AS mq, MAX(CASE m WHEN 'cr' THEN v END) AS cr,
          MAX(CASE m WHEN 'total' THEN v END) AS total, MAX(CASE m WHEN 'it' THEN v END) AS it,
          MAX(CASE m WHEN 'mcn' THEN v END) AS mcn
        FROM med GROUP BY scene, planner),
  c AS (SELECT scene, planner, MIN(family) AS family, MIN(objects) AS objects,
               group_concat(status, ' ') AS statuses FROM r GROUP BY scene, planner)
  SELECT c.scene AS Scene, CASE c.planner WHEN 'dash' THEN 'DaSH' ELSE 'Lazy-DaSH' END AS Planner,
      (SELECT group_concat(k, '; ') FROM (SELECT COUNT(*) || ' ' || IFNULL(status, '') AS k FROM r
         WHERE r.scene = c.scene AND r.planner = c.planner GROUP BY status)) AS runs,
      $(num tc) AS \"task constr\", $(num tq) AS \"task query\", $(num td) AS \"task conflicts\",
      $(num mc) AS \"motion constr\", $(num mq) AS \"motion query\", $(num cr) AS \"conflict res\",
      $(num total) AS total, CASE WHEN it IS NULL THEN '-' ELSE $(int it) END AS \"nodes/iterations\",
      CASE WHEN mcn IS NULL THEN '-' ELSE $(int mcn) END AS \"motion constraints\"
    FROM c LEFT JOIN w ON w.scene = c.scene AND w.planner = c.planner
    ORDER BY c.family DESC, c.objects, c.planner DESC" | markdown
  echo
  # A ratio in the summary: one decimal and an x ('-' when unknown: a median of 0 or none).
  x1() { echo "IFNULL($(fixed "$1" 1) || 'x', '-')"; }
  query "$with, summary AS (SELECT COUNT(*) AS k, MIN(1.0 * d_total / l_total) AS t0, MAX(1.0 * d_total / l_total) AS t1,
               (SELECT AVG(x) FROM (SELECT 1.0 * d_total / l_total AS x, ROW_NUMBER() OVER (ORDER BY 1.0 * d_total / l_total) AS i,
                                           COUNT(*) OVER () AS n FROM j WHERE d_total > 0 AND l_total > 0)
                WHERE i IN ((n + 1) / 2, (n + 2) / 2)) AS tm,
               MIN(1.0 * d_ma / l_ma) AS a0, MAX(1.0 * d_ma / l_ma) AS a1, MIN(1.0 * d_mv / l_mv) AS v0, MAX(1.0 * d_mv / l_mv) AS v1
             FROM j WHERE d_total > 0 AND l_total > 0)
    SELECT CASE WHEN k = 0 THEN 'no scene solved by both planners' ELSE
        'Over the ' || k || ' scenes both planners solved: DaSH / Lazy-DaSH total time ' || $(x1 t0) || ' to ' || $(x1 t1)
        || ' (median ' || $(x1 tm) || '), motion hyperarcs ' || $(x1 a0) || ' to ' || $(x1 a1)
        || ', motion vertices ' || $(x1 v0) || ' to ' || $(x1 v1) || '.' END AS summary
    FROM summary" | tail -n +2 | sed 's/^"//; s/"$//'
}

if [ -n "$TABLE_ONLY" ]; then
  tables "$TABLE_ONLY"
  exit 0
fi

RUN_SPEC="$SPEC"
if [ -n "$TIME_LIMIT" ] || [ -n "$SEEDS" ]; then
  RUN_SPEC="$(mktemp --suffix=.json)"
  trap 'rm -f "$RUN_SPEC"' EXIT
  edits=()
  [ -n "$TIME_LIMIT" ] && edits+=(-e "s/\"time_limit\": *[0-9.]*/\"time_limit\": $TIME_LIMIT/")
  [ -n "$SEEDS" ] && edits+=(-e "s/\"seeds\": *.*\$/\"seeds\": {\"from\": 1, \"count\": $SEEDS}/")
  sed "${edits[@]}" "$SPEC" > "$RUN_SPEC"
fi
ID="$(basename "$SPEC" .json)-$(date +%Y%m%d-%H%M%S)"
echo "run.sh: batch $ID ($RUN_SPEC, $WORKERS workers) into $DB" >&2
"$DASHBENCH" batch run "$RUN_SPEC" --db "$DB" --workers "$WORKERS" --id "$ID" --quiet >&2
tables "$ID"
