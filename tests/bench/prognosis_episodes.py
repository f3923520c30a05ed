#!/usr/bin/env python3
"""An episodic (renewal) time-to-level forecaster learned from the channel's own past episodes, scored on IMS test 2.

Usage: python3 tests/bench/prognosis_episodes.py [LEVEL_CSV] [--first-alarm 541] [--baseline 0.060826] [--stop 981]
  default LEVEL_CSV deploy/data/ims2-features/merged_dataset_BearingTest_2.csv (bearing 1's mean abs, the level
  causal-prognosis-eval scores; first alarm, baseline and stop as it prints them).

A measurement, not shipped. The model (every constant fixed before it was run, none fitted on IMS):
  episodes: the level "jumps" where its 5-snapshot median leaves the preceding 6 h (36 snapshots ending 1 h
    before) by more than 4 robust sds (1.4826 MAD) - the first snapshot of each run of such snapshots, from
    snapshot 500 on (prognosis_indicators.jump_onsets; detection at t uses data up to t only);
  holds: the hours between consecutive jump onsets on record; steps: the net change of the log level over each
    completed episode (median of the last hour before the next onset minus median of the 6 h before the onset);
  forecast at t: the current hold lasts one of the past holds longer than the hold so far (renewal, resampled),
    then the level moves by a resampled step, then a resampled hold, ... until the log level reaches the level;
    2000 resampled futures (fixed seed per decision point), 5 / 50 / 95 % points;
  unknown: fewer than 2 completed episodes on record, the current hold longer than every past hold, no past
    step that rises, or the 95 % point beyond 2000 h.
Prints per level the same columns as causal-prognosis-eval (answered, coverage, med rel w, a-l 20 / 30 %), and
the share of decision points that fall in a 'rising' state (within 2 h after a jump onset): what a forecaster
that answers only while the channel rises could answer at most."""
import csv
import math
import os
import random
import statistics
import sys

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from prognosis_indicators import jump_onsets, med5  # noqa: E402  (the same jump detector, one copy)

ARGS = {"--first-alarm": 541, "--baseline": 0.060826, "--stop": 981}


def forecast(v, t, target, onsets, seed, draws=2000, horizon=2000.0):
    if len(onsets) < 3:
        return None, "fewer than 2 completed episodes"
    holds = [(b - a) / 6.0 for a, b in zip(onsets, onsets[1:])]
    steps = []
    for a, b in zip(onsets, onsets[1:]):
        before = statistics.median(v[max(0, a - 36):a])
        end = statistics.median(v[max(a, b - 6):b])
        steps.append(end - before)
    if max(steps) <= 0:
        return None, "no past episode rose"
    elapsed = (t - onsets[-1]) / 6.0
    longer = [h - elapsed for h in holds if h > elapsed]
    if not longer:
        return None, "the current hold is longer than every past one"
    rng = random.Random(seed)
    level0 = med5(v, t)
    times = []
    for _ in range(draws):
        level, time = level0, rng.choice(longer)
        while True:
            level += rng.choice(steps)
            if level >= target or time > horizon:
                break
            time += rng.choice(holds)
        times.append(time)
    times.sort()
    q = [times[int(p * (draws - 1))] for p in (0.05, 0.5, 0.95)]
    if q[2] > horizon:
        return None, "95 % point beyond the horizon"
    return q, ""


def main():
    files, i = [], 1
    while i < len(sys.argv):
        if sys.argv[i] in ARGS:
            ARGS[sys.argv[i]] = type(ARGS[sys.argv[i]])(sys.argv[i + 1])
            i += 2
        else:
            files.append(sys.argv[i])
            i += 1
    path = files[0] if files else "deploy/data/ims2-features/merged_dataset_BearingTest_2.csv"
    with open(path) as f:
        v = [math.log(max(float(r[1]), 1e-9)) for r in csv.reader(f) if r and r[0] and r[0][0].isdigit()]
    first, base, stop = ARGS["--first-alarm"], math.log(ARGS["--baseline"]), ARGS["--stop"]
    all_onsets = jump_onsets(v[:stop + 1])
    print("jump onsets up to the stop: %s" % all_onsets)
    print("| level | decisions | answered | coverage | med rel w | a-l 20% | a-l 30% | truth earlier | rising share |")
    print("|---|---|---|---|---|---|---|---|---|")
    for name, ratio in (("warning", 2.0), ("critical", 4.0), ("end_of_life", 6.0)):
        hit = [t for t in range(first, stop + 1) if med5(v, t) >= base + math.log(ratio)]
        end = hit[0] if hit else stop
        n = ans = cov = a20 = a30 = early = rising = 0
        widths, reasons = [], {}
        for t in range(first, end):
            onsets = [o for o in all_onsets if o <= t]  # detection at o uses data up to o only
            actual = (end - t) / 6.0
            n += 1
            rising += bool(onsets) and t - onsets[-1] <= 12
            q, why = forecast(v, t, base + math.log(ratio), onsets, seed=t)
            if q is None:
                reasons[why] = reasons.get(why, 0) + 1
                continue
            ans += 1
            cov += q[0] <= actual <= q[2]
            early += actual < q[0]
            a20 += abs(q[1] - actual) <= 0.2 * actual
            a30 += abs(q[1] - actual) <= 0.3 * actual
            widths.append((q[2] - q[0]) / actual)
        print("| %s | %d | %.2f | %.2f | %s | %.2f | %.2f | %.2f | %.2f |" % (
            name, n, ans / n, cov / ans if ans else 0.0, "%.2f" % statistics.median(widths) if widths else "-",
            a20 / n, a30 / n, early / ans if ans else 0.0, rising / n))
        print("|   unknown: %s |" % ", ".join("%s %d" % kv for kv in sorted(reasons.items())))


if __name__ == "__main__":
    main()
