#!/usr/bin/env python3
"""Log levels of a recorded conditions CSV (causal-recorder's conditions_<group>_<feature>.csv) for
causal-whatif --log-levels:  python3 tests/bench/ims2_log_features.py IN.csv OUT.csv"""
import csv
import math
import sys

rows = list(csv.DictReader(open(sys.argv[1])))
names = [c for c in rows[0] if c not in ("snapshot", "time_ns", "time_utc")]
with open(sys.argv[2], "w") as f:
    f.write("snapshot," + ",".join(names) + "\n")
    for r in rows:
        f.write(r["snapshot"] + "," + ",".join(str(math.log(float(r[n]))) for n in names) + "\n")
