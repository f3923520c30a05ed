#!/usr/bin/env python3
"""Advice evaluation of a recorded run (deploy/launch.sh ... --record DIR): does every degradation alarm
event (raise and escalation) carry an action, at its own index, and does any advice reduce a failing asset?

  python3 tests/bench/advice_eval.py DIR [--failing bearing1]

Prints one table of alarm events with their action and the summary numbers (docs/advice.md)."""
import csv
import sys


def rows(path):
    with open(path, newline="") as f:
        return list(csv.DictReader(f))


def main():
    args = sys.argv[1:]
    if not args:
        print(__doc__)
        return 2
    run = args[0]
    failing = args[args.index("--failing") + 1] if "--failing" in args else "bearing1"
    alarms = [a for a in rows(run + "/alarms.csv") if a.get("category", "degradation") == "degradation"]
    recs = rows(run + "/recommendations.csv")
    by_event = {}
    for r in recs:
        by_event.setdefault((r["alarm_id"], r["sample_index"]), []).append(r)
    events = [a for a in alarms if a["state"] in ("raised", "escalated")]
    print(f"{'index':>6} {'state':<9} {'severity':<8} {'channel':<9} {'root':<9} {'kind':<15} action")
    with_action = 0
    first = None
    for a in events:
        rs = sorted(by_event.get((a["alarm_id"], a["sample_index"]), []), key=lambda r: int(r["rank"]))
        top = rs[0] if rs else None
        if top and top["action"]:
            with_action += 1
            idx = int(a["sample_index"])
            first = idx if first is None else min(first, idx)
        print(f"{a['sample_index']:>6} {a['state']:<9} {a['severity']:<8} {a['channel_name']:<9} "
              f"{a['root_cause_name']:<9} {(top['action_kind'] if top else '-'):<15} "
              f"{(top['action'][:150] if top else 'NONE')}")
    reduce_failing = [r for r in recs if f"Reduce {failing}" in r["action"]]
    kinds = {}
    for r in recs:
        if r["rank"] == "1":
            kinds[r["action_kind"]] = kinds.get(r["action_kind"], 0) + 1
    unknown = sum(1 for r in recs if "effect unknown" in r["text"])
    beyond = sum(1 for r in recs
                 for c in ("effect_percent", "effect_percent_low", "effect_percent_high")
                 if r[c] not in ("", "nan") and abs(float(r[c])) > 1000 and "effect unknown" not in r["text"])
    print()
    print(f"degradation alarm events (raise + escalation): {len(events)}")
    print(f"events with an action at their own index: {with_action}")
    print(f"first actionable advice at snapshot: {first}")
    print(f"recommendations: {len(recs)}, rank-1 by kind: {kinds}")
    print(f"actions that reduce the failing {failing}: {len(reduce_failing)}")
    print(f"texts saying 'effect unknown': {unknown}; numbers beyond 1000 % shown as known: {beyond}")
    orders = sorted({(r['order_source'], r['order_confidence']) for r in recs})
    print(f"order source/confidence seen: {orders}")
    return 0 if with_action == len(events) and not reduce_failing else 1


if __name__ == "__main__":
    sys.exit(main())
