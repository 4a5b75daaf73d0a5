#!/usr/bin/env python3
"""Do two report.json files have the same stages with the same values (wall times aside)?
Wall times (wall_seconds, phase_seconds, wall_split) are left out at every depth: a
pressure_steps stage reports its levels as nested stage entries, each with its own wall_seconds.
So is md_classes: its seconds are wall times, and its step counts are those of the leg that ran
(a run restarted inside a stage counts that stage's steps since the restart).
Usage: same_report.py A/report.json B/report.json   (exit 0: same; an assertion otherwise)
"""
import json
import sys


WALL_TIMES = ("wall_seconds", "phase_seconds", "wall_split", "md_classes")


def without_wall_times(v):
    if isinstance(v, dict):
        return {k: without_wall_times(x) for k, x in v.items() if k not in WALL_TIMES}
    if isinstance(v, list):
        return [without_wall_times(x) for x in v]
    return v


a, b = (json.load(open(p))["stages"] for p in sys.argv[1:3])
assert [s["name"] for s in a] == [s["name"] for s in b], "stage names"
for x, y in zip(a, b):
    x, y = without_wall_times(x), without_wall_times(y)
    for k, v in x.items():
        assert y.get(k) == v, (x["name"], k, v, y.get(k))
