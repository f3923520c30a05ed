#!/usr/bin/env python3
"""An episodic (renewal) time-to-level forecaster learned from the channel's own past episodes, scored on IMS test 2.

Usage: python3 tests/bench/prognosis_episodes.py [LEVEL_CSV] [--first-alarm 541] [--baseline 0.060826] [--stop 981]
       python3 tests/bench/prognosis_episodes.py --sim-trace FILE
  default LEVEL_CSV deploy/data/ims2-features/merged_dataset_BearingTest_2.csv (bearing 1's mean abs, the level
  causal-prognosis-eval scores; first alarm, baseline and stop as it prints them; 10-minute snapshots).
  --sim-trace: the output of causal-prognosis-eval --sim ... --trace (its "run" and "series" lines: each run's
  level, times, first alarm and baseline; the stop is the run's last row), every run scored and pooled.

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


def forecast(v, t, target, onsets, seed, hours=None, draws=2000, horizon=2000.0):
    """hours[i]: the time of snapshot i in hours (default i / 6: 10-minute snapshots)."""
    h = hours if hours is not None else [k / 6.0 for k in range(len(v))]
    if len(onsets) < 3:
        return None, "fewer than 2 completed episodes"
    holds = [h[b] - h[a] for a, b in zip(onsets, onsets[1:])]
    steps = []
    for a, b in zip(onsets, onsets[1:]):
        before = statistics.median(v[max(0, a - 36):a])
        end = statistics.median(v[max(a, b - 6):b])
        steps.append(end - before)
    if max(steps) <= 0:
        return None, "no past episode rose"
    elapsed = h[t] - h[onsets[-1]]
    longer = [x - elapsed for x in holds if x > elapsed]
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


LEVELS = (("warning", 2.0), ("critical", 4.0), ("end_of_life", 6.0))


def score_run(v, hours, first, base, stop, tally):
    """Adds one run's decision points (first alarm .. each level's crossing - 1) to tally[level]."""
    all_onsets = jump_onsets(v[:stop + 1])
    for name, ratio in LEVELS:
        hit = [t for t in range(first, stop + 1) if med5(v, t) >= base + math.log(ratio)]
        end = hit[0] if hit else stop
        c = tally.setdefault(name, {"n": 0, "ans": 0, "cov": 0, "a20": 0, "a30": 0, "early": 0, "rising": 0,
                                    "widths": [], "why": {}})
        for t in range(first, end):
            onsets = [o for o in all_onsets if o <= t]  # detection at o uses data up to o only
            actual = hours[end] - hours[t]
            c["n"] += 1
            c["rising"] += bool(onsets) and hours[t] - hours[onsets[-1]] <= 2.0
            q, why = forecast(v, t, base + math.log(ratio), onsets, seed=t, hours=hours)
            if q is None:
                c["why"][why] = c["why"].get(why, 0) + 1
                continue
            c["ans"] += 1
            c["cov"] += q[0] <= actual <= q[2]
            c["early"] += actual < q[0]
            c["a20"] += abs(q[1] - actual) <= 0.2 * actual
            c["a30"] += abs(q[1] - actual) <= 0.3 * actual
            c["widths"].append((q[2] - q[0]) / actual)
    return all_onsets


def sim_runs(path):
    """(level log series, hours, first alarm, log baseline) per run of a causal-prognosis-eval --sim --trace."""
    runs = []
    with open(path) as f:
        for line in f:
            p = line.split()
            if p and p[0] == "run":
                runs.append(([], [], int(p[3]), math.log(float(p[4]))))
            elif p and p[0] == "series":
                runs[-1][0].append(math.log(max(float(p[3]), 1e-9)))
                runs[-1][1].append(int(p[2]) / 3.6e12)
    return [r for r in runs if r[2] >= 0]


def main():
    files, i, sim = [], 1, None
    while i < len(sys.argv):
        if sys.argv[i] in ARGS:
            ARGS[sys.argv[i]] = type(ARGS[sys.argv[i]])(sys.argv[i + 1])
            i += 2
        elif sys.argv[i] == "--sim-trace":
            sim = sys.argv[i + 1]
            i += 2
        else:
            files.append(sys.argv[i])
            i += 1
    tally = {}
    if sim:
        runs = sim_runs(sim)
        for v, hours, first, base in runs:
            score_run(v, hours, first, base, len(v) - 1, tally)
        print("%d simulated runs with a first alarm" % len(runs))
    else:
        path = files[0] if files else "deploy/data/ims2-features/merged_dataset_BearingTest_2.csv"
        with open(path) as f:
            v = [math.log(max(float(r[1]), 1e-9)) for r in csv.reader(f) if r and r[0] and r[0][0].isdigit()]
        onsets = score_run(v, [k / 6.0 for k in range(len(v))], ARGS["--first-alarm"],
                           math.log(ARGS["--baseline"]), ARGS["--stop"], tally)
        print("jump onsets up to the stop: %s" % onsets)
    print("| level | decisions | answered | coverage | med rel w | a-l 20% | a-l 30% | truth earlier | rising share |")
    print("|---|---|---|---|---|---|---|---|---|")
    for name, _ in LEVELS:
        c = tally[name]
        n, ans = c["n"], c["ans"]
        print("| %s | %d | %.2f | %.2f | %s | %.2f | %.2f | %.2f | %.2f |" % (
            name, n, ans / n, c["cov"] / ans if ans else 0.0,
            "%.2f" % statistics.median(c["widths"]) if c["widths"] else "-", c["a20"] / n, c["a30"] / n,
            c["early"] / ans if ans else 0.0, c["rising"] / n))
        print("|   unknown: %s |" % ", ".join("%s %d" % kv for kv in sorted(c["why"].items())))


if __name__ == "__main__":
    main()
