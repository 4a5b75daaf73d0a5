#!/usr/bin/env python3
"""Do two report.json files have the same stages with the same values (wall times aside)?
Wall times (wall_seconds, phase_seconds) are left out at every depth: a pressure_steps stage
reports its levels as nested stage entries, each with its own wall_seconds.
Usage: same_report.py A/report.json B/report.json   (exit 0: same; an assertion otherwise)
"""
import json
import sys


def without_wall_times(v):
    if isinstance(v, dict):
        return {k: without_wall_times(x) for k, x in v.items() if k not in ("wall_seconds", "phase_seconds")}
    if isinstance(v, list):
        return [without_wall_times(x) for x in v]
    return v


a, b = (json.load(open(p))["stages"] for p in sys.argv[1:3])
assert [s["name"] for s in a] == [s["name"] for s in b], "stage names"
for x, y in zip(a, b):
    x, y = without_wall_times(x), without_wall_times(y)
    for k, v in x.items():
        assert y.get(k) == v, (x["name"], k, v, y.get(k))
