#!/usr/bin/env python3
"""A fleet prior for the time to a level: the remaining times of a library of past runs to failure, conditioned on
the channel having lasted as long as it has (and, once it reached the warning level, on its own pace to it).

Usage: python3 tests/bench/prognosis_fleet_prior.py LIBRARY_TRACE TARGET_TRACE [--trace]
  LIBRARY_TRACE: causal-prognosis-eval --sim --seeds 20 --trace (seeds 1-20: the runs a plant would have on
  record); TARGET_TRACE: the same tool's --trace on held-out seeds (--first-seed 101) or on IMS (--ims ...).

A measurement, not shipped. From the trace lines (snapshot, level, actual remaining hours) only:
  per run and level, T = the hours from the first alarm to the crossing (the remaining time at the run's first
  decision point); the hours elapsed at a later decision point are T - actual (clock time: the truth cancels).
  survival: at elapsed e, the library runs with T > e give remaining times T - e; their 5 / 50 / 95 % points
    are the forecast (at least 8 such runs, else unknown: the channel has outlived most of the fleet);
    this is the conditional residual life of the fleet (a reliability engineer's answer with no condition data);
  paced: for critical and end of life once the channel reached the warning level at elapsed e_w, the library's
    ratios T / T_warning scale the channel's own e_w (the fleet's shape, the channel's own time scale),
    conditioned on the result exceeding e; before that, survival.
The library's time scale is the simulation's (40-120 h from the onset to the stop, run_to_failure_sim.cpp),
which this project chose with IMS test 2 (~73 h from its first alarm to the stop) known: on IMS this row is
only as independent as that choice. Also scored: "twin, else fleet" (the twin's answer, the fleet's where the twin says unknown) and "hull twin +
fleet" (where both answer, the hull of the two intervals around the twin's median), both defined before any run
was scored. Columns as causal-prognosis-eval's. --trace: instead of the table, the target's trace lines with the rows
fleet-surv and fleet-paced appended (for tests/bench/prognosis_trace_bounds.py)."""
import os
import statistics
import sys

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import prognosis_trace_bounds as bounds  # noqa: E402  (the trace format, one reader)


def runs(path):
    """[{level: [(snapshot, actual)]}] per run; a run starts where the snapshot index goes back or a level's
    remaining time grows (within a run it only shrinks)."""
    out, last = [], None
    with open(path) as f:
        lines = f.readlines()
    for line in lines:
        if not line.startswith("trace "):
            continue
        p = line.split()
        idx, level, actual = int(p[1]), p[2], float(p[3].split("=")[1])
        if last is None or idx < last or (level in out[-1] and actual >= out[-1][level][-1][1]):
            out.append({})
        last = idx
        out[-1].setdefault(level, []).append((idx, actual))
    return out


def quantiles(v):
    v = sorted(v)

    def q(p):
        k = p * (len(v) - 1)
        lo = int(k)
        return v[lo] + (v[min(lo + 1, len(v) - 1)] - v[lo]) * (k - lo)
    return q(0.05), q(0.5), q(0.95)


def forecast(lib, level, e, e_warn, paced):
    if paced and level != "warning" and e_warn is not None:
        rem = [r[level] / r["warning"] * e_warn - e for r in lib if r["warning"] > 0]
        rem = [x for x in rem if x > 0]
    else:
        rem = [r[level] - e for r in lib if r[level] > e]
    return quantiles(rem) if len(rem) >= 8 else None


def emit_trace(lib, path):
    """The target's trace lines, each with the two fleet rows appended (same format as the tool's)."""
    out = []
    with open(path) as f:
        lines = [x.rstrip("\n") for x in f if x.startswith("trace ")]
    k = 0
    for r in runs(path):
        w = r.get("warning", [])
        t_warn, last_w = (w[0][1], w[-1][0]) if w else (None, None)
        first = {lvl: pts[0][1] for lvl, pts in r.items()}
        for _ in range(sum(len(p) for p in r.values())):
            p = lines[k].split()
            idx, level, actual = int(p[1]), p[2], float(p[3].split("=")[1])
            e = first[level] - actual
            reached = t_warn is not None and idx > last_w
            extra = ""
            for name, paced in (("fleet-surv", False), ("fleet-paced", True)):
                q = forecast(lib, level, e, t_warn if reached else None, paced)
                extra += (" %s=%.2f [%.2f, %.2f]" % (name, q[1], q[0], q[2]) if q
                          else " %s=unknown 0 [0, 0]" % name)
            head, sep, why = lines[k].partition(" conformal=")
            tail = why.split("]", 1)
            out.append(head + sep + tail[0] + "]" + extra + tail[1])
            k += 1
    return out


def combined(preds):
    """The rows scored: the fleet alone (two ways), and the twin with the fleet where the twin says unknown
    (fill) or with the hull of both intervals around the twin's median where both answer (hull)."""
    t, f = preds.get("twin"), preds.get("fleet-paced")
    hull = (t[0], min(t[1], f[1]), max(t[2], f[2])) if t and f else (t or f)
    return {"fleet survival": preds.get("fleet-surv"), "fleet paced": f, "twin": t, "twin, else fleet": t or f,
            "hull twin + fleet": hull}


def main():
    args = [a for a in sys.argv[1:] if a != "--trace"]
    if len(args) != 2:
        sys.exit("usage: prognosis_fleet_prior.py LIBRARY_TRACE TARGET_TRACE [--trace]")
    lib = [{lvl: pts[0][1] for lvl, pts in r.items()} for r in runs(args[0])]
    lib = [r for r in lib if len(r) == 3]
    lines = emit_trace(lib, args[1])
    if "--trace" in sys.argv:
        print("\n".join(lines))
        return
    print("library: %d runs; targets: %d runs" % (len(lib), len(runs(args[1]))))
    print("| level | method | decisions | answered | coverage | med rel w | a-l 20% | a-l 30% | truth earlier |")
    print("|---|---|---|---|---|---|---|---|---|")
    for level, points in bounds.read(lines).items():
        per = {}
        for _, actual, preds in points:
            for name, q in combined(preds).items():
                per.setdefault(name, []).append((q, actual))
        for name, picked in per.items():
            n = len(picked)
            ans = [(q, a) for q, a in picked if q]
            widths = [(hi - lo) / a for (h, lo, hi), a in ans]
            k = max(len(ans), 1)
            print("| %s | %s | %d | %.2f | %.2f | %s | %.2f | %.2f | %.2f |" % (
                level, name, n, len(ans) / n, sum(lo <= a <= hi for (h, lo, hi), a in ans) / k,
                "%.2f" % statistics.median(widths) if widths else "-",
                sum(abs(h - a) <= 0.2 * a for (h, lo, hi), a in ans) / n,
                sum(abs(h - a) <= 0.3 * a for (h, lo, hi), a in ans) / n,
                sum(a < lo for (h, lo, hi), a in ans) / k))


if __name__ == "__main__":
    main()
