#!/usr/bin/env python3
"""experiments/compare/verdict.py on a small results database written here: each verdict follows its
stated rule (sizes solved on every seed, skipped sizes as failed, ratios of the medians per size with
the time limit as a lower bound where DaSH solved no seed, incomplete families marked).

    python3 tests/batch/verdict_test.py
"""
import json
import os
import sqlite3
import subprocess
import sys
import tempfile
import unittest

HERE = os.path.dirname(os.path.abspath(__file__))
VERDICT = os.path.join(HERE, "..", "..", "experiments", "compare", "verdict.py")
BATCH = "b1"


def make_db(path, runs, skipped=(), pending=()):
    """runs: (family, params, seed, planner, status, total, query, tcd, hm_hyperarcs)."""
    db = sqlite3.connect(path)
    db.executescript(
        "CREATE TABLE dash_runs (uuid TEXT, batch_id TEXT, family TEXT, params TEXT, seed INTEGER, planner TEXT,"
        " status TEXT, total_time REAL, time_task_query REAL, time_motion_query REAL,"
        " time_task_conflict_detection REAL, motion_vertices INTEGER, motion_hyperarcs INTEGER, time_limit REAL);"
        "CREATE TABLE dash_batch_runs (batch_id TEXT, run_key TEXT, ordinal INTEGER, spec TEXT, run_uuid TEXT,"
        " attempts INTEGER);"
        "CREATE TABLE dash_batch_skipped (batch_id TEXT, run_key TEXT, reason TEXT);")
    for i, (family, params, seed, planner, status, total, query, tcd, ha) in enumerate(runs):
        uuid = f"u{i}"
        db.execute("INSERT INTO dash_runs VALUES (?,?,?,?,?,?,?,?,?,0,?,10,?,600)",
                   (uuid, BATCH, family, json.dumps(params), seed, planner, status, total, query, tcd, ha))
        spec = {"family": family, "params": list(params.items()), "planner": planner, "label": planner}
        db.execute("INSERT INTO dash_batch_runs VALUES (?,?,?,?,?,0)", (BATCH, f"k{i}", i, json.dumps(spec), uuid))
    for j, (family, params, planner) in enumerate(list(skipped) + list(pending)):
        key = f"s{j}"
        spec = {"family": family, "params": list(params.items()), "planner": planner, "label": planner}
        db.execute("INSERT INTO dash_batch_runs VALUES (?,?,?,?,NULL,0)", (BATCH, key, 1000 + j, json.dumps(spec)))
        if j < len(skipped):
            db.execute("INSERT INTO dash_batch_skipped VALUES (?,?,?)", (BATCH, key, "failed a smaller size"))
    db.commit()
    db.close()


def verdicts(runs, skipped=(), pending=()):
    """claim -> (measured, verdict) of verdict.py's table."""
    with tempfile.TemporaryDirectory() as tmp:
        path = os.path.join(tmp, "r.db")
        make_db(path, runs, skipped, pending)
        out = subprocess.run([sys.executable, VERDICT, path, BATCH], check=True, capture_output=True, text=True).stdout
    rows = {}
    for line in out.splitlines()[2:]:
        cells = [c.strip() for c in line.strip("|").split("|")]
        rows[cells[0]] = (cells[2], cells[3])
    return rows


def sorting(robots, objects, seed, planner, status="solved", total=1.0, query=0.1, tcd=0.002, ha=100):
    return ("sorting", {"objects": objects, "robots": robots}, seed, planner, status, total, query, tcd, ha)


class VerdictRules(unittest.TestCase):
    def test_a_dash_that_solves_past_the_papers_limit_on_every_seed_is_not_reproduced(self):
        runs = [sorting(8, 32, s, p) for s in (1, 2) for p in ("dash", "lazy-dash")]
        rows = verdicts(runs)
        self.assertEqual(rows["Sorting: DaSH solves"][1], "not reproduced: DaSH goes further here")

    def test_a_size_one_seed_missed_or_the_axis_stop_skipped_does_not_count_as_solved(self):
        runs = [sorting(16, 32, s, p) for s in (1, 2) for p in ("dash", "lazy-dash")]
        runs += [sorting(16, 64, 1, "lazy-dash"), sorting(16, 64, 2, "lazy-dash", "timeout", 600.0)]
        rows = verdicts(runs, skipped=[("sorting", {"objects": 64, "robots": 16}, "dash")])
        self.assertEqual(rows["Sorting: Lazy-DaSH solves"], ("robots=16: objects 32 (some seed 64)", "not reproduced"))
        self.assertEqual(rows["Sorting: DaSH solves"][0], "robots=16: objects 32")

    def test_time_ratios_use_the_limit_as_a_lower_bound_where_dash_solved_no_seed(self):
        runs = [sorting(4, 4, s, "lazy-dash", total=2.0, ha=10) for s in (1, 2)]
        runs += [sorting(4, 4, s, "dash", total=8.0, ha=2000) for s in (1, 2)]
        runs += [sorting(4, 8, s, "lazy-dash", total=30.0) for s in (1, 2)]
        runs += [sorting(4, 8, s, "dash", "timeout", 600.0) for s in (1, 2)]
        rows = verdicts(runs)
        self.assertEqual(rows["Total time, DaSH / Lazy-DaSH"],
                         ("sorting 4-4x (>= 20x where DaSH solved no seed)", "reproduced"))
        self.assertEqual(rows["Motion hypergraph H_M hyperarcs, DaSH / Lazy-DaSH"], ("sorting 200-200x", "reproduced"))

    def test_a_family_with_runs_left_to_run_has_no_verdict_yet(self):
        runs = [sorting(4, 4, s, p) for s in (1, 2) for p in ("dash", "lazy-dash")]
        rows = verdicts(runs, pending=[("sorting", {"objects": 8, "robots": 4}, "dash")])
        self.assertEqual(rows["Sorting: DaSH solves"][1], "incomplete: 1 runs of sorting not finished")

    def test_task_conflict_detection_in_milliseconds_is_reproduced_and_a_second_is_not(self):
        fast = [sorting(4, 4, s, p) for s in (1, 2) for p in ("dash", "lazy-dash")]
        self.assertEqual(verdicts(fast)["Lazy-DaSH's task conflict detection"][1], "reproduced")
        slow = [sorting(4, 4, s, p, tcd=1.5) for s in (1, 2) for p in ("dash", "lazy-dash")]
        self.assertTrue(verdicts(slow)["Lazy-DaSH's task conflict detection"][1].startswith("not reproduced"))


if __name__ == "__main__":
    unittest.main()
