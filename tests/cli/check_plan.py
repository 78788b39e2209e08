#!/usr/bin/env python3
"""usage: check_plan.py PLAN_OUTPUT ROWS CORES_PER_NODE

The table of `jamsim plan`: ROWS rows, each with ranks x threads = nodes x CORES_PER_NODE,
a simulated makespan no shorter than its bound, a bound no shorter than the critical path,
and idle cores within the node's.
"""
import re
import sys


def seconds(text):
    value, unit = text.split()
    return float(value) * {"s": 1, "min": 60, "h": 3600}[unit]


def main():
    rows = re.findall(r"^\| (\d+) \| (\d+) × (\d+) \| ([^|]+) \| ([^|]+) \| ([^|]+) \| ([\d.]+) of (\d+) \|",
                      open(sys.argv[1]).read(), re.M)
    if len(rows) != int(sys.argv[2]):
        sys.exit(f"FAIL: {len(rows)} rows, expected {sys.argv[2]}")
    per_node = int(sys.argv[3])
    for nodes, ranks, threads, makespan, bound, critical, idle, cores in rows:
        m, b, c = seconds(makespan), seconds(bound), seconds(critical)
        if int(ranks) * int(threads) != int(nodes) * per_node or int(cores) != int(nodes) * per_node:
            sys.exit(f"FAIL: {ranks} x {threads} on {nodes} nodes of {per_node} cores")
        if m < b * (1 - 1e-3) or b < c * (1 - 1e-3) or not 0 <= float(idle) <= int(cores):
            sys.exit(f"FAIL: makespan {makespan}, bound {bound}, critical path {critical}, idle {idle} of {cores}")
    print(f"ok: {len(rows)} rows")


if __name__ == "__main__":
    main()
