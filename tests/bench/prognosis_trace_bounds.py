#!/usr/bin/env python3
"""What choosing or gating among causal-prognosis-eval's rows could reach, from its --trace lines.

Usage: causal-prognosis-eval ... --trace | python3 tests/bench/prognosis_trace_bounds.py [GATE_HOURS] [--announced-at N]

Per level it prints:
  hindsight: the share of decision points at which at least one row's 90 % interval holds the actual time
    (any width; width <= 1.5x and <= 3x the actual remaining time) and at least one row's median is within
    +-30 %. A choice among the rows, however made, cannot beat these shares. The targets (share answered
    >= 0.5, coverage >= 0.8, median relative width <= 1.5) need covered intervals of width <= 1.5 at
    >= 0.8 + 0.5 - 1 = 0.3 of the answered points, so at >= 0.15 of all decision points, and alpha-lambda
    (+-30 %) >= 0.2 needs a median within +-30 % at >= 0.2 of them.
  self-check gate (per row): the row answers only while none of its own answers of the last GATE_HOURS
    (default 24) is already known to be wrong, i.e. its whole interval has passed without the level being
    reached (a check on the channel's own history before the decision point; a miss with the truth before
    the interval is only known at the crossing, so it cannot gate).
  --announced-at N: the same hindsight shares when, in addition, a perfect forecast (covered, narrow and
    exact) were available at every decision point from snapshot N on: an information bound for a leading
    indicator that announces the end at N (tests/bench/prognosis_indicators.py prints candidate onsets).
  choice by own record: at each point the answering row with the fewest answers known wrong in the last
    GATE_HOURS (ties: the narrower interval relative to its own median).
Decision points are 10 minutes apart (snapshot index / 6 = hours), as in IMS test 2 and the simulations; run
it on one run's trace at a time (--ims)."""
import collections
import re
import statistics
import sys

PAT = re.compile(r"(\S+)=(unknown )?(\S+) \[(\S+), (\S+)\]")


def read(lines):
    rows = collections.defaultdict(list)
    for line in lines:
        if not line.startswith("trace "):
            continue
        p = line.split()
        preds = {}
        for m in PAT.finditer(line):
            name, unknown, h, lo, hi = m.groups()
            preds[name] = None if unknown else (float(h), float(lo), float(hi))
        rows[p[2]].append((int(p[1]) / 6.0, float(p[3].split("=")[1]), preds))
    return rows


def score(picked):
    n = len(picked)
    ans = [(f, a) for f, a in picked if f]
    cov = sum(lo <= a <= hi for (h, lo, hi), a in ans)
    widths = [(hi - lo) / a for (h, lo, hi), a in ans]
    a30 = sum(abs(h - a) <= 0.3 * a for (h, lo, hi), a in ans)
    return "answered %.2f coverage %.2f med rel w %s a-l 30%% %.2f" % (
        len(ans) / n, cov / len(ans) if ans else 0.0,
        "%.2f" % statistics.median(widths) if widths else "nan", a30 / n)


def known_wrong(past, now, gate):
    return sum(1 for s, hi in past if s + hi <= now and now - s <= gate)


def main():
    args = sys.argv[1:]
    announced = None
    if "--announced-at" in args:
        k = args.index("--announced-at")
        announced = int(args[k + 1])
        del args[k:k + 2]
    gate = float(args[0]) if args else 24.0
    for level, points in read(sys.stdin).items():
        n = len(points)
        methods = list(points[0][2].keys())
        hind = collections.Counter()
        for now, actual, preds in points:
            c = [(hi - lo) / actual for f in preds.values() if f for h, lo, hi in [f] if lo <= actual <= hi]
            hind["any"] += bool(c)
            hind["1.5"] += any(w <= 1.5 for w in c)
            hind["3"] += any(w <= 3 for w in c)
            hind["a30"] += any(abs(f[0] - actual) <= 0.3 * actual for f in preds.values() if f)
            early = announced is None or round(now * 6) < announced
            hind["1.5o"] += early and any(w <= 1.5 for w in c)
            hind["a30o"] += early and any(abs(f[0] - actual) <= 0.3 * actual for f in preds.values() if f)
        print("%s (%d decision points) hindsight: covered by some row %.2f (width <= 1.5x: %.2f, <= 3x: %.2f);"
              " some median within +-30 %%: %.2f" % (level, n, hind["any"] / n, hind["1.5"] / n, hind["3"] / n,
                                                    hind["a30"] / n))
        if announced is not None:
            late = sum(1 for now, actual, preds in points if round(now * 6) >= announced)
            print("  with a perfect forecast from snapshot %d on (%.2f of the points): width <= 1.5x %.2f,"
                  " median within +-30 %% %.2f" % (announced, late / n, (hind["1.5o"] + late) / n,
                                                   (hind["a30o"] + late) / n))
        past = {m: [] for m in methods}
        gated = {m: [] for m in methods}
        chosen = []
        for now, actual, preds in points:
            best = None
            for m in methods:
                f = preds.get(m)
                wrong = known_wrong(past[m], now, gate)
                gated[m].append((f if f and wrong == 0 else None, actual))
                if f and f[0] > 0:
                    key = (wrong, (f[2] - f[1]) / f[0])
                    if best is None or key < best[0]:
                        best = (key, f)
            chosen.append((best[1] if best else None, actual))
            for m in methods:
                if preds.get(m):
                    past[m].append((now, preds[m][2]))
        for m in methods:
            print("  self-check gate %-9s %s" % (m, score(gated[m])))
        print("  choice by own record  %s" % score(chosen))


if __name__ == "__main__":
    main()
