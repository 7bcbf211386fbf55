#!/usr/bin/env python3
"""The scaling benchmark's report (called by run.sh): reads one log per run from OUT/logs, writes
OUT/runs.tsv (one line per run), OUT/scaling.svg (log-log: total time against objects; OUT/scaling.png
too when rsvg-convert exists) and prints the markdown table. Python's standard library only."""

import argparse
import math
import os
import re
import shutil
import statistics
import subprocess
import sys
from xml.sax.saxutils import escape

PHASES = [
    ("task_construction", "task constr."),
    ("task_query", "task query"),
    ("task_conflict_detection", "task conflict det."),
    ("motion_construction", "motion constr."),
    ("motion_query", "motion query"),
    ("conflict_resolution", "conflict res."),
    ("validation", "validation"),
]
COLUMNS = (["robots", "objects", "seed", "status", "plan_exit", "validate_exit", "time_limit", "total", "wall"]
           + [p for p, _ in PHASES] + ["other", "peak_memory_mb", "collision_checks", "makespan"])


def parse(path, robots, objects, seed):
    """One run's log as a dict of COLUMNS (None where the log has no value)."""
    run = {c: None for c in COLUMNS}
    run.update(robots=robots, objects=objects, seed=seed)
    try:
        text = open(path).read()
    except FileNotFoundError:
        run["status"] = "missing"
        return run
    m = re.search(r"time-limit=([0-9.]+)", text)
    run["time_limit"] = float(m.group(1)) if m else None
    m = re.search(r"^plan exit: (\S+)", text, re.M)
    run["plan_exit"] = m.group(1) if m else None
    m = re.search(r"^validate exit: (\S+)", text, re.M)
    run["validate_exit"] = m.group(1) if m else None
    m = re.search(r"^status: (\S+)", text, re.M)
    planner_status = m.group(1) if m else None
    m = re.search(r"^time:(.*)$", text, re.M)
    if m:
        for name, value in re.findall(r"(\w+) ([0-9.]+) s", m.group(1)):
            if name in run and name not in ("robots", "objects", "seed"):
                run[name] = float(value)
        w = re.search(r"\(wall ([0-9.]+) s\)", m.group(1))
        run["wall"] = float(w.group(1)) if w else None
    m = re.search(r"^peak memory: ([0-9.]+) MB", text, re.M)
    run["peak_memory_mb"] = float(m.group(1)) if m else None
    m = re.search(r"^collision checks: (\d+) eager, (\d+) lazy", text, re.M)
    run["collision_checks"] = int(m.group(1)) + int(m.group(2)) if m else None
    m = re.search(r"makespan ([0-9.]+)", text)
    run["makespan"] = float(m.group(1)) if m else None

    pe, ve = run["plan_exit"], run["validate_exit"]
    if text.startswith("scenario failed"):
        run["status"] = "no-scene"             # the generator refused the parameters
    elif ve is None:
        run["status"] = "unfinished"           # killed while it ran: not in the table as a run
    elif pe == "0" and ve == "0":
        run["status"] = "solved"
    elif pe == "0":
        run["status"] = "invalid"              # solved by the planner, refused by the validator
    elif pe in ("124", "137"):
        run["status"] = "timeout"              # stopped by run.sh's hard limit
    elif pe == "3" and planner_status in ("timeout", "infeasible"):
        run["status"] = planner_status
    else:
        run["status"] = "crashed"
    return run


def median(values):
    values = [v for v in values if v is not None]
    return statistics.median(values) if values else None


def fmt_time(v):
    if v is None:
        return "-"
    return f"{v:.2f}" if v < 10 else f"{v:.1f}" if v < 1000 else f"{v:.0f}"


def fmt_mem(v):
    return "-" if v is None else f"{v:.1f}" if v < 100 else f"{v:.0f}"


def fmt_count(v):
    if v is None:
        return "-"
    if v >= 1e6:
        return f"{v / 1e6:.2f}M"
    if v >= 1e4:
        return f"{v / 1e3:.0f}k"
    return f"{v:.0f}"


def outcome(runs):
    """'2/3 (1 timeout)': solved / finished runs, with why the others were not solved."""
    done = [r for r in runs if r["status"] not in ("missing", "unfinished")]
    solved = sum(r["status"] == "solved" for r in done)
    why = []
    for status, word in (("timeout", "timeout"), ("infeasible", "infeasible"), ("invalid", "invalid plan"),
                         ("crashed", "crashed"), ("no-scene", "no scene")):
        n = sum(r["status"] == status for r in done)
        if n:
            why.append(f"{n} {word}")
    missing = len(runs) - len(done)
    if missing:
        why.append(f"{missing} not run")
    return f"{solved}/{len(done)}" + (f" ({'; '.join(why)})" if why else "")


# ---------------------------------------------------------------------------------------------- plot
W, H = 760, 500
LEFT, RIGHT, TOP, BOTTOM = 80, 30, 50, 70


def log_range(lo, hi):
    """A padded log range [lo, hi] that holds at least one power of ten."""
    lo, hi = math.log10(lo), math.log10(hi)
    if hi - lo < 0.3:
        mid = (lo + hi) / 2
        lo, hi = mid - 0.15, mid + 0.15
    pad = 0.06 * (hi - lo)
    lo, hi = lo - pad, hi + pad
    if math.floor(hi) < math.ceil(lo):        # no decade inside: reach down to the one below
        lo = math.floor(lo)
    return lo, hi


def ticks(lo, hi, marks=()):
    """(value, label or '', major) for log ticks in [10^lo, 10^hi]: every decade labelled and major, 2..9 x
    decade minor; minor ticks labelled too when the axis spans under one decade (2 and 5 under three), or
    only the values in marks when marks are given (the x axis: the sizes run)."""
    out = []
    span = hi - lo
    for d in range(math.floor(lo), math.ceil(hi) + 1):
        for k in range(1, 10):
            v = k * 10.0 ** d
            if lo - 1e-9 <= math.log10(v) <= hi + 1e-9:
                if k == 1:
                    show = True
                elif marks:
                    show = False
                else:
                    show = span < 1 or (span < 3 and k in (2, 5))
                out.append((v, label(v) if show else "", k == 1))
    for m in marks:
        if not any(abs(v - m) < 1e-9 * m for v, _, _ in out):
            out.append((float(m), label(m), False))
        else:
            out = [(v, label(v) if abs(v - m) < 1e-9 * m else t, major) for v, t, major in out]
    return out


def label(v):
    return f"{v:g}" if 1e-3 <= v < 1e5 else f"{v:.0e}".replace("e+0", "e").replace("e-0", "e-")


def plot(runs, sizes, time_limit, path, title):
    solved = [r for r in runs if r["status"] == "solved" and r["total"]]
    timeouts = [r for r in runs if r["status"] == "timeout"]
    points_y = [r["total"] for r in solved] + ([time_limit] if timeouts else [])
    if not points_y:
        points_y = [time_limit or 1.0]
    xs = [o for _, o in sizes]
    x_lo, x_hi = log_range(min(xs), max(xs))
    y_lo, y_hi = log_range(max(min(points_y), 1e-3), max(points_y))
    pw, ph = W - LEFT - RIGHT, H - TOP - BOTTOM

    def px(v):
        return LEFT + (math.log10(v) - x_lo) / (x_hi - x_lo) * pw

    def py(v):
        return TOP + ph - (math.log10(max(v, 10 ** y_lo)) - y_lo) / (y_hi - y_lo) * ph

    s = [f'<svg xmlns="http://www.w3.org/2000/svg" width="{W}" height="{H}" viewBox="0 0 {W} {H}" '
         'font-family="DejaVu Sans, Arial, sans-serif" font-size="12">',
         f'<rect width="{W}" height="{H}" fill="white"/>',
         f'<text x="{W / 2}" y="24" text-anchor="middle" font-size="15">{escape(title)}</text>']
    for v, text, major in ticks(x_lo, x_hi, xs):
        x = px(v)
        s.append(f'<line x1="{x:.1f}" y1="{TOP}" x2="{x:.1f}" y2="{TOP + ph}" stroke="{"#ccc" if major else "#eee"}"/>')
        s.append(f'<line x1="{x:.1f}" y1="{TOP + ph}" x2="{x:.1f}" y2="{TOP + ph + (7 if major else 4)}" stroke="black"/>')
        if text:
            s.append(f'<text x="{x:.1f}" y="{TOP + ph + 21}" text-anchor="middle">{text}</text>')
    for v, text, major in ticks(y_lo, y_hi):
        y = py(v)
        s.append(f'<line x1="{LEFT}" y1="{y:.1f}" x2="{LEFT + pw}" y2="{y:.1f}" stroke="{"#ccc" if major else "#eee"}"/>')
        s.append(f'<line x1="{LEFT - (7 if major else 4)}" y1="{y:.1f}" x2="{LEFT}" y2="{y:.1f}" stroke="black"/>')
        if text:
            s.append(f'<text x="{LEFT - 10}" y="{y + 4:.1f}" text-anchor="end">{text}</text>')
    s.append(f'<rect x="{LEFT}" y="{TOP}" width="{pw}" height="{ph}" fill="none" stroke="black"/>')
    s.append(f'<text x="{LEFT + pw / 2}" y="{H - 22}" text-anchor="middle" font-size="13">'
             'objects (4 per robot; log scale)</text>')
    s.append(f'<text transform="translate(22 {TOP + ph / 2}) rotate(-90)" text-anchor="middle" font-size="13">'
             'total planning time (s, log scale)</text>')
    if timeouts and time_limit:
        y = py(time_limit)
        s.append(f'<line x1="{LEFT}" y1="{y:.1f}" x2="{LEFT + pw}" y2="{y:.1f}" stroke="#d62728" '
                 'stroke-dasharray="6 4"/>')
        s.append(f'<text x="{LEFT + pw - 6}" y="{y + 18:.1f}" text-anchor="end" fill="#d62728">'
                 f'time limit {time_limit:g} s</text>')
    # The median over the solved runs per size.
    line = []
    for robots, objects in sizes:
        m = median([r["total"] for r in solved if r["robots"] == robots])
        if m is not None:
            line.append((px(objects), py(m)))
    if len(line) > 1:
        s.append('<polyline fill="none" stroke="#1f77b4" stroke-width="2" points="'
                 + " ".join(f"{x:.1f},{y:.1f}" for x, y in line) + '"/>')
    for x, y in line:
        s.append(f'<rect x="{x - 5:.1f}" y="{y - 5:.1f}" width="10" height="10" fill="none" stroke="#1f77b4" '
                 'stroke-width="2"/>')

    # One marker per run, spread sideways a little so that equal values stay visible.
    def jitter(r):
        n = sum(1 for q in runs if q["robots"] == r["robots"])
        i = sorted(q["seed"] for q in runs if q["robots"] == r["robots"]).index(r["seed"])
        return (i - (n - 1) / 2) * 5

    for r in solved:
        x, y = px(r["objects"]) + jitter(r), py(r["total"])
        s.append(f'<circle cx="{x:.1f}" cy="{y:.1f}" r="3.5" fill="#1f77b4" fill-opacity="0.7">'
                 f'<title>{r["robots"]} robots, {r["objects"]} objects, seed {r["seed"]}: '
                 f'{r["total"]:.2f} s</title></circle>')
    for r in timeouts:
        x, y = px(r["objects"]) + jitter(r), py(time_limit)
        s.append(f'<path d="M{x - 5:.1f},{y + 4:.1f} L{x + 5:.1f},{y + 4:.1f} L{x:.1f},{y - 5:.1f} Z" fill="none" '
                 f'stroke="#d62728" stroke-width="2"><title>{r["robots"]} robots, {r["objects"]} objects, '
                 f'seed {r["seed"]}: timeout</title></path>')
    # Legend, top left inside the axes.
    lx, ly = LEFT + 12, TOP + 14
    items = [("circle", "solved run (validated)"), ("square", "median of the solved runs")]
    if timeouts:
        items.append(("triangle", "timeout (drawn at the limit)"))
    s.append(f'<rect x="{lx - 6}" y="{ly - 10}" width="215" height="{len(items) * 18 + 4}" fill="white" '
             'fill-opacity="0.85" stroke="#999"/>')
    for i, (kind, text) in enumerate(items):
        y = ly + i * 18
        if kind == "circle":
            s.append(f'<circle cx="{lx + 8}" cy="{y}" r="3.5" fill="#1f77b4" fill-opacity="0.7"/>')
        elif kind == "square":
            s.append(f'<line x1="{lx}" y1="{y}" x2="{lx + 16}" y2="{y}" stroke="#1f77b4" stroke-width="2"/>')
            s.append(f'<rect x="{lx + 3}" y="{y - 5}" width="10" height="10" fill="white" stroke="#1f77b4" '
                     'stroke-width="2"/>')
        else:
            s.append(f'<path d="M{lx + 3},{y + 4} L{lx + 13},{y + 4} L{lx + 8},{y - 5} Z" fill="none" '
                     'stroke="#d62728" stroke-width="2"/>')
        s.append(f'<text x="{lx + 24}" y="{y + 4}">{escape(text)}</text>')
    s.append("</svg>")
    with open(path, "w") as f:
        f.write("\n".join(s) + "\n")


# ---------------------------------------------------------------------------------------------- main
def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--out", required=True)
    ap.add_argument("--robots", required=True)
    ap.add_argument("--objects-per-robot", type=int, required=True)
    ap.add_argument("--seeds", type=int, required=True)
    ap.add_argument("--experiments", required=True, help="the folder of RESULTS.md, for the plot's link")
    a = ap.parse_args()

    sizes = [(int(r), int(r) * a.objects_per_robot) for r in a.robots.split()]
    runs = [parse(os.path.join(a.out, "logs", f"sorting-r{r}-o{o}-s{s}.log"), r, o, s)
            for r, o in sizes for s in range(1, a.seeds + 1)]
    with open(os.path.join(a.out, "runs.tsv"), "w") as f:
        f.write("\t".join(COLUMNS) + "\n")
        for r in runs:
            f.write("\t".join("" if r[c] is None else str(r[c]) for c in COLUMNS) + "\n")
    limits = sorted({r["time_limit"] for r in runs if r["time_limit"] is not None})
    time_limit = limits[-1] if limits else None
    limit_text = "/".join(f"{t:g}" for t in limits) if limits else "?"

    svg = os.path.join(a.out, "scaling.svg")
    plot(runs, sizes, time_limit, svg,
         f"Lazy-DaSH on sorting: total time against objects ({a.seeds} seeds, {limit_text} s limit)")
    png = os.path.join(a.out, "scaling.png")
    if shutil.which("rsvg-convert"):
        subprocess.run(["rsvg-convert", "-o", png, svg], check=True)
    elif os.path.exists(png):
        os.remove(png)
    link = os.path.relpath(svg, os.path.realpath(a.experiments))

    print(f"Lazy-DaSH (`dashbench plan` defaults) on sorting with {a.objects_per_robot} objects per robot, "
          f"seeds 1..{a.seeds}, {limit_text} s per run, one run at a time. A run counts as solved only when "
          "`dashbench validate` (certified) accepts its plan. Times in seconds, medians over the solved "
          "runs; the phases are the planner's own timers (the total also holds a little 'other'); peak "
          "memory is the planner process's peak resident set; collision checks are eager + lazy.")
    print()
    head = (["robots", "objects", "solved", "total (s)", "per seed total (s)"] + [f"{n} (s)" for _, n in PHASES]
            + ["peak memory (MB)", "collision checks"])
    print("| " + " | ".join(head) + " |")
    print("|" + "---|" * len(head))
    fit, partial = [], []
    for robots, objects in sizes:
        mine = [r for r in runs if r["robots"] == robots]
        ok = [r for r in mine if r["status"] == "solved"]
        per_seed = ", ".join(fmt_time(r["total"]) if r["status"] == "solved" else r["status"] for r in mine)
        total = median([r["total"] for r in ok])
        if total and len(ok) == len(mine):
            fit.append((math.log(objects), math.log(total)))
        elif total:
            partial.append(str(objects))
        cells = ([str(robots), str(objects), outcome(mine), fmt_time(total), per_seed]
                 + [fmt_time(median([r[p] for r in ok])) for p, _ in PHASES]
                 + [fmt_mem(median([r["peak_memory_mb"] for r in ok])),
                    fmt_count(median([r["collision_checks"] for r in ok]))])
        print("| " + " | ".join(cells) + " |")
    print()
    if len(fit) >= 2:
        mx = sum(x for x, _ in fit) / len(fit)
        my = sum(y for _, y in fit) / len(fit)
        sxx = sum((x - mx) ** 2 for x, _ in fit)
        slope = sum((x - mx) * (y - my) for x, y in fit) / sxx if sxx else float("nan")
        left_out = (f"; {', '.join(partial)} objects left out: their medians are over the solved runs only"
                    if partial else "")
        print(f"Least-squares slope of log(median total time) against log(objects) over the sizes whose every run "
              f"was solved: {slope:.2f} (total time scales about as objects^{slope:.1f}{left_out}).")
        print()
    print(f"![Lazy-DaSH on sorting: total time against objects, log-log]({link})")
    print()
    print(f"Log-log plot: one dot per solved run, the median of the solved runs per size (squares, line), "
          f"timeouts as triangles at the time limit (runs that failed otherwise are in the table only). Raw data: `{os.path.relpath(os.path.join(a.out, 'runs.tsv'), os.path.dirname(os.path.realpath(a.experiments)))}` "
          "and one log per run beside it.")
    if any(r["status"] in ("missing", "unfinished") for r in runs):
        print(file=sys.stderr)
        print("report.py: some runs have no finished log (run.sh --resume makes them)", file=sys.stderr)


if __name__ == "__main__":
    main()
