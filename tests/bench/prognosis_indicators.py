#!/usr/bin/env python3
"""Do the IMS test-2 per-file statistics carry information about the remaining time that the level lacks?

Usage: python3 tests/bench/prognosis_indicators.py [STATS_CSV] [LEVEL_CSV]
  defaults: deploy/data/ims2-features/derived_per_file_stats_all984.csv (kurtosis, rms, peak per bearing) and
  deploy/data/ims2-features/merged_dataset_BearingTest_2.csv (the level the twin and causal-prognosis-eval use).
  --first-alarm 541 --baseline 0.060826 --stop 981: what causal-prognosis-eval prints for bearing 1.

A measurement, not a forecaster: nothing here is shipped, and part C fits on IMS itself (an optimistic bound).
At every decision point t of causal-prognosis-eval (first alarm .. the level's crossing - 1), from data up to t:
  level   log(5-snapshot median of bearing 1's level / baseline)      } the level history the twin has
  slope6  Theil-Sen slope of bearing 1's log level over the last 6 h  }
  kurt    5-snapshot median of bearing 1's kurtosis
  crest   5-snapshot median of bearing 1's peak / rms
  shape   5-snapshot median of bearing 1's rms / mean abs
  others  mean over bearings 2-4 of log(5-snapshot median / own median of the first 500 snapshots)
  oth_sl6 Theil-Sen slope of that mean over the last 6 h
A: Spearman rank correlation of each signal with log(actual remaining hours), per level.
B: partial rank correlation given level and slope6 (ranks, linear residuals): what a signal adds to the level.
C: leave-one-block-out (6 h blocks) linear fit of log(remaining) on [1, level, slope6] with and without one
   signal; alpha-lambda (+-30 %) of exp(fit) and the share of points whose truth lies inside the fit's own
   residual 5-95 % band with width <= 1.5x: fitted on this run, so an upper bound on what the signal can give.
D: jump onsets per signal: snapshots where the 5-snapshot median leaves the preceding 6 h (36 snapshots,
   ending 1 h before) by more than 4 robust sds (1.4826 MAD), first of each run of such snapshots, from 500 on:
   does any signal jump before the level does?"""
import csv
import math
import statistics
import sys

ARGS = {"--first-alarm": 541, "--baseline": 0.060826, "--stop": 981}


def parse(argv):
    files, i = [], 1
    while i < len(argv):
        if argv[i] in ARGS:
            ARGS[argv[i]] = type(ARGS[argv[i]])(argv[i + 1])
            i += 2
        else:
            files.append(argv[i])
            i += 1
    stats = files[0] if files else "deploy/data/ims2-features/derived_per_file_stats_all984.csv"
    level = files[1] if len(files) > 1 else "deploy/data/ims2-features/merged_dataset_BearingTest_2.csv"
    return stats, level


def med5(v, t):
    return statistics.median(v[max(0, t - 4):t + 1])


def theil_sen(v, t, n=36):
    pts = [(j / 6.0, v[j]) for j in range(max(0, t - n + 1), t + 1)]
    s = [(b[1] - a[1]) / (b[0] - a[0]) for k, a in enumerate(pts) for b in pts[k + 1:]]
    return statistics.median(s) if s else 0.0


def ranks(x):
    order = sorted(range(len(x)), key=lambda i: x[i])
    r = [0.0] * len(x)
    i = 0
    while i < len(order):
        j = i
        while j + 1 < len(order) and x[order[j + 1]] == x[order[i]]:
            j += 1
        for k in range(i, j + 1):
            r[order[k]] = (i + j) / 2.0
        i = j + 1
    return r


def corr(a, b):
    ma, mb = sum(a) / len(a), sum(b) / len(b)
    sab = sum((x - ma) * (y - mb) for x, y in zip(a, b))
    sa = math.sqrt(sum((x - ma) ** 2 for x in a))
    sb = math.sqrt(sum((y - mb) ** 2 for y in b))
    return sab / (sa * sb) if sa > 0 and sb > 0 else 0.0


def lstsq(X, y):
    """Normal equations solved by Gaussian elimination with partial pivoting (a few columns)."""
    p = len(X[0])
    A = [[sum(r[i] * r[j] for r in X) for j in range(p)] + [sum(r[i] * v for r, v in zip(X, y))] for i in range(p)]
    for c in range(p):
        piv = max(range(c, p), key=lambda r: abs(A[r][c]))
        A[c], A[piv] = A[piv], A[c]
        if abs(A[c][c]) < 1e-12:
            A[c][c] = 1e-12
        for r in range(p):
            if r != c:
                f = A[r][c] / A[c][c]
                A[r] = [x - f * z for x, z in zip(A[r], A[c])]
    return [A[i][p] / A[i][i] for i in range(p)]


def residuals(X, y):
    beta = lstsq(X, y)
    return [v - sum(b * x for b, x in zip(beta, r)) for r, v in zip(X, y)]


def quantile(v, q):
    v = sorted(v)
    k = q * (len(v) - 1)
    lo = int(math.floor(k))
    return v[lo] + (v[min(lo + 1, len(v) - 1)] - v[lo]) * (k - lo)


def block_cv(X, y, t, block=36):
    """Leave-one-block-out: alpha-lambda (+-30 %) and 'covered with width <= 1.5x' shares."""
    within = narrow_covered = 0
    for b0 in range(min(t), max(t) + 1, block):
        test = [i for i in range(len(y)) if b0 <= t[i] < b0 + block]
        train = [i for i in range(len(y)) if not (b0 <= t[i] < b0 + block)]
        if not test or len(train) < 3 * len(X[0]):
            continue
        beta = lstsq([X[i] for i in train], [y[i] for i in train])
        res = [y[i] - sum(b * x for b, x in zip(beta, X[i])) for i in train]
        lo_r, hi_r = quantile(res, 0.05), quantile(res, 0.95)
        for i in test:
            f = sum(b * x for b, x in zip(beta, X[i]))
            actual, median = math.exp(y[i]), math.exp(f)
            within += abs(median - actual) <= 0.3 * actual
            lo, hi = math.exp(f + lo_r), math.exp(f + hi_r)
            narrow_covered += lo <= actual <= hi and (hi - lo) <= 1.5 * actual
    return within / len(y), narrow_covered / len(y)


def jump_onsets(v, start=500, window=36, lag=6, z=4.0):
    out, prev = [], False
    for t in range(max(start, window + lag), len(v)):
        ref = v[t - lag - window:t - lag]
        m = statistics.median(ref)
        mad = 1.4826 * statistics.median(abs(x - m) for x in ref)
        up = mad > 0 and (med5(v, t) - m) / mad > z
        if up and not prev:
            out.append(t)
        prev = up
    return out


def load(stats_file, level_file):
    rows = list(csv.DictReader(open(stats_file)))
    with open(level_file) as f:
        level = [float(r[1]) for r in csv.reader(f) if r and r[0] and r[0][0].isdigit()]
    s = {k: [] for k in ("kurt", "crest", "shape")}
    others = [[] for _ in range(3)]
    for r in rows:
        rms, ma = float(r["bearing1_rms"]), float(r["bearing1_meanabs"])
        s["kurt"].append(float(r["bearing1_kurtosis"]))
        s["crest"].append(float(r["bearing1_peakabs"]) / rms if rms > 0 else 0.0)
        s["shape"].append(rms / ma if ma > 0 else 0.0)
        for b in range(3):
            others[b].append(math.log(max(float(r["bearing%d_meanabs" % (b + 2)]), 1e-9)))
    healthy = [statistics.median(o[:500]) for o in others]
    s["others_raw"] = [sum(o[t] - h for o, h in zip(others, healthy)) / 3.0 for t in range(len(rows))]
    s["loglevel"] = [math.log(max(x, 1e-9)) for x in level]
    return s


def main():
    stats_file, level_file = parse(sys.argv)
    s = load(stats_file, level_file)
    first, base, stop = ARGS["--first-alarm"], ARGS["--baseline"], ARGS["--stop"]
    lv = s["loglevel"]
    truth = {}
    for name, ratio in (("warning", 2.0), ("critical", 4.0), ("end_of_life", 6.0)):
        hit = [t for t in range(first, stop + 1) if med5(lv, t) >= math.log(ratio * base)]
        truth[name] = hit[0] if hit else stop
    print("truth (trailing 5-snapshot median): %s" % truth)
    signals = ("kurt", "crest", "shape", "others", "oth_sl6")
    feats = {}
    for t in range(first, stop + 1):
        feats[t] = {"level": med5(lv, t) - math.log(base), "slope6": theil_sen(lv, t),
                    "kurt": med5(s["kurt"], t), "crest": med5(s["crest"], t), "shape": med5(s["shape"], t),
                    "others": med5(s["others_raw"], t), "oth_sl6": theil_sen(s["others_raw"], t)}
    print("| level | signal | rank corr with log remaining | partial given level, slope6 | CV a-l 30% level only | "
          "CV a-l 30% + signal | CV covered & width<=1.5 level only | + signal |")
    print("|---|---|---|---|---|---|---|---|")
    for name, end in truth.items():
        ts = list(range(first, end))
        y = [math.log((end - t) / 6.0) for t in ts]
        base_X = [[1.0, feats[t]["level"], feats[t]["slope6"]] for t in ts]
        ry = ranks(y)
        rl, rs = ranks([feats[t]["level"] for t in ts]), ranks([feats[t]["slope6"] for t in ts])
        ctrl = [[1.0, a, b] for a, b in zip(rl, rs)]
        res_y = residuals(ctrl, ry)
        a0, c0 = block_cv(base_X, y, ts)
        for sig in ("level", "slope6") + signals:
            x = [feats[t][sig] for t in ts]
            rho = corr(ranks(x), ry)
            if sig in ("level", "slope6"):
                print("| %s | %s | %.2f | - | %.2f | - | %.2f | - |" % (name, sig, rho, a0, c0))
                continue
            partial = corr(residuals(ctrl, ranks(x)), res_y)
            a1, c1 = block_cv([r + [v] for r, v in zip(base_X, x)], y, ts)
            print("| %s | %s | %.2f | %.2f | %.2f | %.2f | %.2f | %.2f |" % (name, sig, rho, partial, a0, a1, c0, c1))
    print("jump onsets (snapshot; 5-median > 4 robust sd above the 6 h ending 1 h before), from 500:")
    print("  level (bearing 1): %s" % jump_onsets(lv))
    for sig in ("kurt", "crest", "shape", "others_raw"):
        print("  %s: %s" % (sig, jump_onsets(s[sig])))


if __name__ == "__main__":
    main()
