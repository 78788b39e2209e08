#!/usr/bin/env python3
"""Print the thread-scaling table of tests/bench/scaling.sh from Google Benchmark JSON files.

usage: scaling_table.py RESULTS.json...

One row per (kernel, N, threads): particle-steps per second (millions), the speed-up against the
same kernel and N on 1 thread, the parallel efficiency, and the kernel's own counters: the
serial fraction of RD0 (Amdahl's S / (S + T R), from timed parallel regions), and for CD0 the
step in RD0 steps on the same threads and the share of the step in the CHOLMOD factor.
"""
import json
import re
import sys


def rows(paths):
    for path in paths:
        try:
            with open(path) as f:
                results = json.load(f)["benchmarks"]
        except (OSError, ValueError, KeyError) as e:  # a run cut short leaves a partial file
            print(f"skipped {path}: {e}", file=sys.stderr)
            continue
        for b in results:
            m = re.match(r"BM_(\w+?)Threads/N:(\d+)/threads:(\d+)", b["name"])
            if m and b.get("run_type", "iteration") == "iteration":
                yield m.group(1), int(m.group(2)), int(m.group(3)), b


def main(paths):
    table = sorted(rows(paths), key=lambda r: (r[0], r[1], r[2]))
    one = {(k, n): b["items_per_second"] for k, n, t, b in table if t == 1}
    print(f"{'kernel':6} {'N':>7} {'threads':>7} {'M steps/s':>10} {'speed-up':>9} {'efficiency':>10}  counters")
    for kernel, n, t, b in table:
        rate = b["items_per_second"]
        speedup = rate / one[(kernel, n)] if (kernel, n) in one else float("nan")
        extra = []
        if "serial_fraction" in b and t > 1:
            extra.append(f"serial fraction {100 * b['serial_fraction']:.2f}%")
        if "cd0_over_rd0" in b:
            extra.append(f"CD0 step = {b['cd0_over_rd0']:.1f} RD0 steps")
            extra.append(f"factor share {100 * b['factor_fraction']:.0f}%")
        print(f"{kernel:6} {n:7d} {t:7d} {rate / 1e6:10.1f} {speedup:9.2f} {speedup / t:10.2f}  {'; '.join(extra)}")


if __name__ == "__main__":
    if len(sys.argv) < 2:
        sys.exit("usage: scaling_table.py RESULTS.json...")
    main(sys.argv[1:])
