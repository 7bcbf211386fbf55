#!/usr/bin/env python3
"""The paper's claims beside what one comparison batch measured (issue 37 item 3): a Markdown table,
one row per claim, with the paper's number, the batch's number and a verdict by a fixed rule.

    experiments/compare/verdict.py DB BATCH_ID

Reads the batch's runs from the results database (dash_runs, and the runs the axis stop rule skipped
from dash_batch_runs / dash_batch_skipped). Sizes count as solved by a planner when every seed of that
size solved; a skipped size counts as failed. Ratios are DaSH over Lazy-DaSH of the medians over
seeds, per size where both planners solved every seed; where DaSH solved no seed of a size that
Lazy-DaSH solved on every seed, the time ratio is at least the time limit over Lazy-DaSH's median
(written with ">="). The paper's numbers are those its results section reports, written in each row below.
"""
import json
import sqlite3
import statistics
import sys
from collections import defaultdict

# Per family: the growing axis (the spec's stop_axis) and the parameters that name a line.
AXES = {"sorting": "objects", "wall": "objects", "shelf-wall": "objects", "stocking": "objects", "lab": "containers"}
FAMILIES = ["sorting", "wall", "shelf-wall", "stocking", "lab"]


def planner_kind(planner):
    return "lazy" if planner == "lazy-dash" else "dash"


def load_runs(db, batch):
    """(family, line, size, kind) -> list of runs (dicts); skipped sizes as {'status': 'skipped'}."""
    cells = defaultdict(list)
    rows = db.execute(
        "SELECT family, params, planner, status, total_time, time_task_query, time_motion_query,"
        " time_task_conflict_detection, motion_vertices, motion_hyperarcs, time_limit FROM dash_runs"
        " WHERE batch_id = ? AND status NOT IN ('running', 'cancelled')", (batch,))
    for family, params, planner, status, total, tq, mq, tcd, hv, ha, limit in rows:
        p = json.loads(params)
        axis = AXES.get(family)
        if axis is None or axis not in p:
            continue
        line = " ".join(f"{k}={p[k]}" for k in sorted(p) if k != axis)
        cells[(family, line, p[axis], planner_kind(planner))].append({
            "status": status, "total": total, "query": (tq or 0.0) + (mq or 0.0), "tcd": tcd,
            "hm_vertices": hv, "hm_hyperarcs": ha, "limit": limit})
    for spec, in db.execute(
            "SELECT b.spec FROM dash_batch_skipped s JOIN dash_batch_runs b ON b.batch_id = s.batch_id"
            " AND b.run_key = s.run_key WHERE s.batch_id = ?", (batch,)):
        j = json.loads(spec)
        p = dict(j["params"])
        axis = AXES.get(j["family"])
        line = " ".join(f"{k}={p[k]}" for k in sorted(p) if k != axis)
        cells[(j["family"], line, p[axis], planner_kind(j["planner"]))].append({"status": "skipped"})
    return cells


def pending_families(db, batch):
    """family -> runs of the batch not finished yet (queued, running or cancelled)."""
    out = defaultdict(int)
    for spec, status in db.execute(
            "SELECT b.spec, r.status FROM dash_batch_runs b LEFT JOIN dash_runs r ON r.uuid = b.run_uuid"
            " WHERE b.batch_id = ? AND NOT EXISTS (SELECT 1 FROM dash_batch_skipped s WHERE"
            " s.batch_id = b.batch_id AND s.run_key = b.run_key)", (batch,)):
        if status is None or status in ("running", "cancelled", "queued"):
            out[json.loads(spec)["family"]] += 1
    return out


def all_solved(runs):
    return bool(runs) and all(r["status"] == "solved" for r in runs)


def none_solved(runs):
    return bool(runs) and all(r["status"] != "solved" for r in runs)


def median(runs, key):
    values = [r[key] for r in runs if r.get(key) is not None]
    return statistics.median(values) if values else None


def reach(cells, family, kind):
    """line -> (largest size every seed solved, largest size some seed solved), None where none."""
    out = {}
    lines = sorted({(line) for (f, line, _, k) in cells if f == family and k == kind}, key=line_key)
    for line in lines:
        sizes = sorted(s for (f, l, s, k) in cells if f == family and l == line and k == kind)
        every = [s for s in sizes if all_solved(cells[(family, line, s, kind)])]
        some = [s for s in sizes if any(r["status"] == "solved" for r in cells[(family, line, s, kind)])]
        out[line] = (max(every) if every else None, max(some) if some else None)
    return out


def line_key(line):
    return [int(part.split("=")[1]) if part.split("=")[1].isdigit() else part for part in line.split()] if line else []


def reach_text(family, per_line):
    axis = AXES[family]
    parts = []
    for line, (every, some) in per_line.items():
        where = f"{line}: " if line else ""
        if every is None and some is None:
            parts.append(f"{where}none")
        elif every == some:
            parts.append(f"{where}{axis} {every}")
        else:
            parts.append(f"{where}{axis} {every if every is not None else '-'} (some seed {some})")
    return "; ".join(parts) if parts else "no runs"


def line_robots(line):
    for part in line.split():
        if part.startswith("robots="):
            return int(part.split("=")[1])
    return None


def lazy_reaches(per_line, lines, at_least):
    """Every line named in `lines` (a predicate) solved on every seed up to at least `at_least`."""
    chosen = [(l, r) for l, r in per_line.items() if lines(l)]
    return bool(chosen) and all(every is not None and every >= at_least for _, (every, _) in chosen)


def dash_beyond(per_line, robots, objects):
    """DaSH solved, on every seed, a size past the paper's limit of `robots` robots / `objects` objects."""
    for line, (every, _) in per_line.items():
        r = line_robots(line)
        if r is None or every is None:
            continue
        if (r >= robots and every > objects) or (r > robots and every >= objects):
            return True
    return False


def solves_nothing(per_line):
    return bool(per_line) and all(some is None for _, (_, some) in per_line.items())


def fmt(x):
    return f"{x:.2g}" if x < 10 else f"{x:.0f}"


def scale_rows(cells):
    """(claim, paper, measured, verdict) per family and planner."""
    rows = []
    reach_of = {(f, k): reach(cells, f, k) for f in FAMILIES for k in ("lazy", "dash")}

    def row(family, kind, paper, ok, fail_text):
        per_line = reach_of[(family, kind)]
        if not per_line:
            return
        name = "Lazy-DaSH" if kind == "lazy" else "DaSH"
        verdict = "reproduced" if ok(per_line) else fail_text
        rows.append((f"{family.capitalize()}: {name} solves", paper, reach_text(family, per_line), verdict))

    row("sorting", "lazy", "16 robots, more than 60 objects",
        lambda p: lazy_reaches(p, lambda l: line_robots(l) == 16, 61), "not reproduced")
    row("sorting", "dash", "4 robots, 14 objects", lambda p: not dash_beyond(p, 4, 14),
        "not reproduced: DaSH goes further here")
    row("wall", "lazy", "8 robots, more than 40 objects",
        lambda p: lazy_reaches(p, lambda l: line_robots(l) == 8, 41), "not reproduced")
    row("wall", "dash", "5 robots, 10 objects", lambda p: not dash_beyond(p, 5, 10),
        "not reproduced: DaSH goes further here")
    row("shelf-wall", "lazy", "4 robots, 32 objects",
        lambda p: lazy_reaches(p, lambda l: line_robots(l) == 4, 32), "not reproduced")
    row("shelf-wall", "dash", "none in the time limit, even with 2 robots", solves_nothing,
        "not reproduced: DaSH solves some")
    row("stocking", "lazy", "18 objects with 3 layers, 28 with 2",
        lambda p: lazy_reaches(p, lambda l: l == "layers=3", 18) and lazy_reaches(p, lambda l: l == "layers=2", 28),
        "not reproduced")
    row("stocking", "dash", "fails", solves_nothing, "not reproduced: DaSH solves some")
    lab = (reach_of[("lab", "lazy")].get(""), reach_of[("lab", "dash")].get(""))
    if lab[0] and lab[1]:
        lazy_every, dash_every = lab[0][0] or 0, lab[1][0] or 0
        largest = max(s for (f, _, s, _) in cells if f == "lab")
        if dash_every == 0 and lazy_every > 0:
            verdict = "reproduced (DaSH solves no size on every seed)"
        elif lazy_every > 2 * dash_every:
            verdict = "reproduced"
        elif lazy_every == dash_every == largest:
            verdict = f"not separated: both solve every size up to {largest}"
        else:
            verdict = "not reproduced"
        rows.append(("Lab: Lazy-DaSH handles more than twice DaSH's objects", "more than twice DaSH's containers",
                     f"Lazy-DaSH containers {lazy_every or '-'}, DaSH {dash_every or '-'} (every seed)", verdict))
    return rows


def ratios(cells, key, timeout_bound=False):
    """family -> list of (ratio, is_lower_bound) per size both solved (or DaSH none, with timeout_bound)."""
    out = defaultdict(list)
    for (family, line, size, kind), lazy in cells.items():
        if kind != "lazy" or not all_solved(lazy):
            continue
        dash = cells.get((family, line, size, "dash"), [])
        mine = median(lazy, key)
        if not dash or mine is None or mine <= 0:
            continue
        if all_solved(dash) and median(dash, key) is not None:
            out[family].append((median(dash, key) / mine, False))
        elif timeout_bound and none_solved(dash):
            limits = [r["limit"] for r in dash if r.get("limit")]
            if limits:
                out[family].append((min(limits) / mine, True))
    return out


def ratio_text(per_family):
    parts = []
    for family in FAMILIES:
        values = per_family.get(family)
        if not values:
            continue
        exact = [v for v, bound in values if not bound]
        bounds = [v for v, bound in values if bound]
        text = f"{family} {fmt(min(exact))}-{fmt(max(exact))}x" if exact else f"{family}"
        if bounds:
            text += f" (>= {fmt(max(bounds))}x where DaSH solved no seed)"
        parts.append(text)
    return "; ".join(parts) if parts else "no size both solved"


def ratio_row(claim, paper, per_family, orders):
    """Verdict: the largest ratio reaches 10^orders (reproduced), 10^(orders-1) (partly), or less."""
    values = [v for vs in per_family.values() for v, _ in vs]
    if not values:
        return (claim, paper, "no size both solved", "not testable here")
    top = max(values)
    if top >= 10 ** orders:
        verdict = "reproduced"
    elif orders > 1 and top >= 10 ** (orders - 1):
        verdict = f"partly: up to {fmt(top)}x"
    else:
        verdict = f"not reproduced: at most {fmt(top)}x"
    return (claim, paper, ratio_text(per_family), verdict)


def claim_rows(cells):
    rows = scale_rows(cells)
    rows.append(ratio_row("Total time, DaSH / Lazy-DaSH", "up to an order of magnitude",
                          ratios(cells, "total", timeout_bound=True), 1))
    rows.append(ratio_row("Query time (task + motion query), DaSH / Lazy-DaSH", "up to three orders of magnitude",
                          ratios(cells, "query"), 3))
    rows.append(ratio_row("Motion hypergraph H_M hyperarcs, DaSH / Lazy-DaSH", "up to two orders of magnitude smaller",
                          ratios(cells, "hm_hyperarcs"), 2))
    tcd = [(median(runs, "tcd"), f, l, s) for (f, l, s, k), runs in cells.items() if k == "lazy" and all_solved(runs)]
    tcd = sorted(t for t in tcd if t[0] is not None)
    if tcd:
        top, family, line, size = tcd[-1]
        where = f"{family} {line} {AXES[family]}={size}".replace("  ", " ")
        rows.append(("Lazy-DaSH's task conflict detection", "milliseconds",
                     f"median per size {fmt(tcd[0][0] * 1e3)}-{fmt(top * 1e3)} ms (largest: {where})",
                     "reproduced" if top < 0.1 else "not reproduced: up to a second or more"))
    return rows


def mark_incomplete(rows, pending):
    """A row of a family with runs still to run says so instead of a verdict."""
    out = []
    for claim, paper, measured, verdict in rows:
        family = claim.split(":")[0].lower()
        if family in pending:
            verdict = f"incomplete: {pending[family]} runs of {family} not finished"
        elif not claim.split(":")[0].lower() in FAMILIES and pending:
            verdict = f"{verdict} (so far: {sum(pending.values())} runs not finished)"
        out.append((claim, paper, measured, verdict))
    return out


def main():
    if len(sys.argv) != 3:
        sys.exit("usage: verdict.py DB BATCH_ID")
    db = sqlite3.connect(f"file:{sys.argv[1]}?mode=ro", uri=True)
    cells = load_runs(db, sys.argv[2])
    print("| Paper's claim | Paper | Measured here | Verdict |")
    print("|---|---|---|---|")
    for claim, paper, measured, verdict in mark_incomplete(claim_rows(cells), pending_families(db, sys.argv[2])):
        print(f"| {claim} | {paper} | {measured} | {verdict} |")


if __name__ == "__main__":
    main()
