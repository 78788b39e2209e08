#!/usr/bin/env python3
"""usage: check_dry_run_plan.py LISTING THREADS [USABLE_SECONDS]

The wall time of `jamsim run --dry-run` on a rate-ladder campaign tells the truth: from
the listing's own per-replica seconds (rows "id N phi rate seed samples cost est.s
sampling"), the
longest chain (the replicas of one N, phi and seed) is summed here, and the printed critical
path must be at least that sum divided by THREADS (a replica on T threads is at most T
times faster), and equal to the sum on one thread; the simulated wall time, and the wall
time of the shards run at once, must be at least the critical path. With USABLE_SECONDS
(time limit − warning lead − 60 s) the busiest task's requeues must cover its wall time.
"""
import math
import re
import sys
from collections import defaultdict


def fail(why):
    print("FAIL: " + why)
    sys.exit(1)


def main():
    text = open(sys.argv[1]).read()
    threads = int(sys.argv[2])
    chains = defaultdict(float)
    rows = 0
    for m in re.finditer(r"^ *(\d+) +(\d+) +(\S+) +(\S+) +(\d+) +\d+ +\S+ +(\S+) +\S+$", text, re.M):
        chains[(m[2], m[3], m[5])] += float(m[6])
        rows += 1
    replicas = int(re.search(r"^campaign \S+: (\d+) replicas", text, re.M)[1])
    if rows != replicas or not chains:
        fail(f"{rows} rows for {replicas} replicas")
    longest = max(chains.values())
    slack = 5e-6 * longest + 1  # the listing's 6 digits, the lines' whole seconds
    critical = float(re.search(r"^critical path: .*? \((\d+) s\) on (\d+) threads?", text, re.M)[1])
    wall = float(re.search(r"^wall time on \d+ ranks? x \d+ threads?: about .*? \((\d+) s;", text, re.M)[1])
    print(f"longest chain {longest:.0f} s on one thread, critical path {critical:.0f} s on {threads} threads, "
          f"wall time {wall:.0f} s")
    if critical < longest / threads - slack:
        fail(f"critical path {critical} s < the longest chain {longest} s / {threads} threads")
    if threads == 1 and abs(critical - longest) > slack:
        fail(f"critical path {critical} s on one thread is not the longest chain's {longest} s")
    if wall < critical - 1:
        fail(f"wall time {wall} s below the critical path {critical} s")
    shards = re.search(r"^wall time with every task running at once: about .*? \((\d+) s\)", text, re.M)
    if shards and float(shards[1]) < critical - 1:
        fail(f"the shards' wall time {shards[1]} s is below the critical path {critical} s")
    if len(sys.argv) > 3:
        usable = float(sys.argv[3])
        requeues = int(re.search(r"the busiest task needs about .*?, (\d+) requeues?", text)[1])
        needed = math.ceil(critical / usable) - 1
        if requeues < needed:
            fail(f"{requeues} requeues for a critical path of {critical} s at {usable} s per task: {needed} needed")
        print(f"{requeues} requeues (at least {needed} for the critical path)")
    print("ok")


if __name__ == "__main__":
    main()
