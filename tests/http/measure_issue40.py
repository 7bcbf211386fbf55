#!/usr/bin/env python3
"""Issue 40's attacks 1-3, measured: the server's peak and kept memory (VmRSS) and /api/health's
latency while each attack runs. Loopback only, every loop bounded in count and time.

    python3 tests/http/measure_issue40.py --binary build/dashbench --db data/demo.db [--seconds 15]

For each attack, starts `BINARY serve` on a free port with a copy of --db in a temporary folder, runs
the attack against it, and prints one line: RSS before, at peak, 3 s after (kept), /api/health p50
and p99 and /api/runs?limit=5 p99 (a probe of each every 50 ms), and the attack's answers by status. docs/http-api.md has the results.
"""
import argparse
import http.client
import json
import os
import shutil
import socket
import subprocess
import sys
import tempfile
import threading
import time


def rss_mb(pid):
    with open(f"/proc/{pid}/status") as f:
        for line in f:
            if line.startswith("VmRSS:"):
                return int(line.split()[1]) / 1024.0
    return 0.0


def request(port, method, path, body=None, timeout=120.0):
    conn = http.client.HTTPConnection("127.0.0.1", port, timeout=timeout)
    try:
        headers = {"Content-Type": "application/json"} if body is not None else {}
        conn.request(method, path, body=body, headers=headers)
        r = conn.getresponse()
        data = r.read()
        return r.status, len(data)
    except (OSError, http.client.HTTPException):
        return 0, 0
    finally:
        conn.close()


class Sampler:
    """VmRSS every 20 ms, and a /api/health and an /api/runs?limit=5 probe every 50 ms each, while running."""

    def __init__(self, pid, port):
        self.pid, self.port = pid, port
        self.peak = rss_mb(pid)
        self.latencies = {"/api/health": [], "/api/runs?limit=5": []}
        self.stop = threading.Event()
        self.threads = [threading.Thread(target=self._rss)] + [
            threading.Thread(target=self._probe, args=(path,)) for path in self.latencies]

    def _rss(self):
        while not self.stop.is_set():
            self.peak = max(self.peak, rss_mb(self.pid))
            time.sleep(0.02)

    def _probe(self, path):
        while not self.stop.is_set():
            started = time.monotonic()
            status, _ = request(self.port, "GET", path, timeout=30)
            self.latencies[path].append((time.monotonic() - started) * 1000 if status == 200 else float("inf"))
            time.sleep(0.05)

    def __enter__(self):
        for t in self.threads:
            t.start()
        return self

    def __exit__(self, *exc):
        self.stop.set()
        for t in self.threads:
            t.join()


def percentile(values, p):
    values = sorted(values)
    return values[min(len(values) - 1, int(p / 100.0 * len(values)))] if values else float("nan")


def run_clients(port, clients, seconds, method, path, body, max_requests):
    """`clients` threads sending the request until `seconds` pass or `max_requests` each."""
    statuses = {}
    lock = threading.Lock()
    deadline = time.monotonic() + seconds

    def client():
        for _ in range(max_requests):
            if time.monotonic() >= deadline:
                return
            status, _ = request(port, method, path, body)
            with lock:
                statuses[status] = statuses.get(status, 0) + 1

    threads = [threading.Thread(target=client) for _ in range(clients)]
    for t in threads:
        t.start()
    for t in threads:
        t.join()
    return statuses


def attacks(seconds):
    label_spec = json.dumps({"name": "mem", "scenarios": [{"family": "sorting", "params": {"robots": 2, "objects": 2}}],
                             "planners": [{"name": "lazy-dash", "label": "x" * 30000}],
                             "seeds": {"from": 1, "count": 5000}})
    grid_spec = json.dumps({"name": "cpu", "scenarios": [{"family": "sorting", "params": {
        "robots": list(range(2, 33)), "objects": list(range(1, 129))}}], "planners": [{"name": "lazy-dash"}],
        "seeds": [1]})
    columns = ", ".join(f"'c' || i AS c{k}" for k in range(200))
    wide = json.dumps({"sql": "WITH RECURSIVE c(i) AS (SELECT 1 UNION ALL SELECT i + 1 FROM c LIMIT 10000) "
                              f"SELECT {columns} FROM c", "max_rows": 10000})
    doubles = json.dumps({"sql": "WITH RECURSIVE c(i) AS (SELECT 1 UNION ALL SELECT i + 1 FROM c LIMIT 10000) "
                                 "SELECT " + ", ".join(f"0.1 + 0.2 AS c{k}" for k in range(200)) + " FROM c",
                          "max_rows": 10000})
    return [
        ("1: validate, 30 KB label x 5000 seeds, 1 client", 1, seconds, "/api/batches/validate", label_spec, 1),
        ("1: validate, 30 KB label x 5000 seeds, 2 clients at once", 2, seconds, "/api/batches/validate", label_spec, 1),
        (f"2: validate, 3,968-combination grid, 32 clients, {seconds:g} s", 32, seconds, "/api/batches/validate",
         grid_spec, 1000),
        (f"3: query, 200 columns x 10,000 rows, 4 clients, {seconds:g} s", 4, seconds, "/api/query", wide, 1000),
        (f"3: query, 200 columns of 0.1+0.2 x 10,000 rows, 4 clients, {seconds:g} s", 4, seconds, "/api/query",
         doubles, 1000),
    ]


def main():
    parser = argparse.ArgumentParser()
    parser.add_argument("--binary", required=True)
    parser.add_argument("--db", required=True)
    parser.add_argument("--seconds", type=float, default=15.0)
    args = parser.parse_args()
    if not 0 < args.seconds <= 120:
        sys.exit("--seconds: 0..120")
    print(f"{'attack':<62} {'RSS before':>10} {'peak':>8} {'kept':>8} {'health p50':>10} {'p99':>8} "
          f"{'runs p99':>9}  answers")
    for name, clients, seconds, path, body, count in attacks(args.seconds):
        # A fresh server for each attack: its memory before, at peak and 3 s after are this attack's.
        folder = tempfile.mkdtemp(prefix="issue40-")
        db = os.path.join(folder, "results.db")
        shutil.copy(args.db, db)
        with socket.socket() as s:
            s.bind(("127.0.0.1", 0))
            port = s.getsockname()[1]
        server = subprocess.Popen([args.binary, "serve", "--port", str(port), "--db", db, "--token-file",
                                   os.path.join(folder, "token")], stdout=subprocess.DEVNULL,
                                  stderr=subprocess.DEVNULL)
        try:
            for _ in range(100):
                if request(port, "GET", "/api/health", timeout=1)[0] == 200:
                    break
                time.sleep(0.1)
            request(port, "GET", "/api/runs?limit=5")
            before = rss_mb(server.pid)
            started = time.monotonic()
            with Sampler(server.pid, port) as sampler:
                statuses = run_clients(port, clients, seconds, "POST", path, body, count)
            took = time.monotonic() - started
            time.sleep(3)
            kept = rss_mb(server.pid)
            health, runs = sampler.latencies["/api/health"], sampler.latencies["/api/runs?limit=5"]
            print(f"{name:<62} {before:>7.0f} MB {sampler.peak:>5.0f} MB {kept:>5.0f} MB "
                  f"{percentile(health, 50):>7.1f} ms {percentile(health, 99):>5.0f} ms {percentile(runs, 99):>6.0f} ms"
                  f"  {statuses} in {took:.1f} s", flush=True)
        finally:
            server.terminate()
            server.wait(timeout=60)
            shutil.rmtree(folder, ignore_errors=True)


if __name__ == "__main__":
    main()
