#!/usr/bin/env python3
"""Usage: [BASE="--lingam --self-lags --calibration 100"] python3 tests/bench/whatif_eval.py CAUSAL_WHATIF LOG_CSV [--log-levels]
Runs causal-whatif on the IMS test-2 log features at several model rows and channels; counts table
points outside their own intervals and answers shown beyond 1000 % (not 'effect unknown')."""
import math, re, subprocess, sys
exe, csvf = sys.argv[1], sys.argv[2]
import os
extra = sys.argv[3:]
base = os.environ.get("BASE", "--lingam --self-lags --calibration 100").split()
outside = beyond = unknown = answers = tables = 0
for at in (540, 700, 900, 983):
    for ch in (1, 2, 3, 4):
        cmd = [exe, "--csv", csvf] + base + ["--at", str(at),
               "--intervene", str(ch), "--delta", str(math.log(0.9))] + extra
        out = subprocess.run(cmd, capture_output=True, text=True).stdout
        lines = out.splitlines()
        for i, l in enumerate(lines):
            if l.startswith("channel"):
                for row in lines[i + 1:i + 5]:
                    v = row.split()[1:]
                    try:
                        x = [float(t) for t in v]
                    except ValueError:
                        continue
                    tables += 1
                    if not (x[1] <= x[0] <= x[2]) or not (x[4] <= x[3] <= x[5]):
                        outside += 1
        in_answer = False
        for l in lines:
            if l.startswith("answer ("):
                in_answer = True
                continue
            if in_answer and l.startswith("  "):
                answers += 1
                if "effect unknown" in l:
                    unknown += 1
                # percent numbers as the live twin prints them, or raw log effects turned into percent
                m = re.search(r": ([-+]?[\d.]+) % \[([-+]?[\d.]+), ([-+]?[\d.]+)\]", l)
                if m:  # the live twin's percent line
                    nums = [float(g) for g in m.groups()]
                else:  # raw log-level effects: what they mean in percent of the level
                    m = re.search(r": ([-+\d.e]+) \[([-+\d.e]+), ([-+\d.e]+)\]", l)
                    nums = [100 * math.expm1(float(g)) for g in m.groups()] if m and "effect unknown" not in l else []
                if any(abs(n) > 1000 for n in nums) or "> +1000" in l:
                    beyond += 1
print(f"table rows {tables}: {outside} points outside their own interval; answer lines {answers}: "
      f"{beyond} beyond 1000 %, {unknown} 'effect unknown'")
