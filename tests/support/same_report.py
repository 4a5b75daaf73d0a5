#!/usr/bin/env python3
"""Do two report.json files have the same stages with the same values (wall times aside)?
Usage: same_report.py A/report.json B/report.json   (exit 0: same; an assertion otherwise)
"""
import json
import sys

a, b = (json.load(open(p))["stages"] for p in sys.argv[1:3])
assert [s["name"] for s in a] == [s["name"] for s in b], "stage names"
for x, y in zip(a, b):
    for k, v in x.items():
        if k != "wall_seconds":
            assert y.get(k) == v, (x["name"], k, v, y.get(k))
