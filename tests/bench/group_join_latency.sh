#!/usr/bin/env bash
# What a joining asset group costs the running ones (docs/scale-and-benchmarks.md, "round 2"): 8 groups live at the
# IMS rate (sensor-sim --group-prefix a-), 8 more (b-) join after 4 s; the estimator's --stage-trace gives each
# a-frame's received -> fed time. Prints its p99 and maximum in the steady state before the join (a-frames from
# sequence 40) and in the 2 s after it. Run it under tests/support/isolate.sh (its own /dev/shm and loopback).
#
#   tests/bench/group_join_latency.sh [--build DIR] [--estimator BIN] [--qos FILE] [--domain N] [--keep DIR]
#
# --estimator: another causal-estimator binary (e.g. a copy of main's); sensor-sim comes from --build.
set -uo pipefail
here="$(cd "$(dirname "$0")/../.." && pwd)"
build="$here/build" est="" qos="$here/deploy/dds/qos.xml" domain=201 keep=""
. "$here/deploy/bench_options.sh"
parse_options "$0" 2,9 --build=build --estimator=est --qos=qos --domain=domain --keep=keep -- "$@"
est="${est:-$build/services/causal_estimator/causal-estimator}"
sim="$build/services/sensor_sim/sensor-sim"
. "$here/tests/bench/bench_setup.sh"
bench_start group_join_latency.sh "$est" "$sim"
live=(--channels 4 --frame-samples 1024 --sample-rate 20480 --wall-clock-stamps --rate 20480 --stagger
      --wait-subscribers 1 --max-runtime 60 --log-level warn)
"$est" --domain "$domain" "${dds[@]}" --params "$here/deploy/config/estimator.yaml" --idle-exit 2 --max-runtime 60 \
  --stage-trace "$work/trace.csv" --log-level warn > "$work/est.log" 2>&1 &
e=$!; pids+=($e)
"$sim" --domain "$domain" "${dds[@]}" --groups 8 --group-prefix a- --frames-per-group 200 "${live[@]}" > "$work/a.out" 2>&1 &
a=$!; pids+=($a)
sleep 4
join_ns=$(date +%s%N)
"$sim" --domain "$domain" "${dds[@]}" --groups 8 --group-prefix b- --frames-per-group 60 "${live[@]}" > "$work/b.out" 2>&1
b_rc=$?
wait "$a"; a_rc=$?
wait "$e"; e_rc=$?
[ "$a_rc" = 0 ] && [ "$b_rc" = 0 ] && [ "$e_rc" = 0 ] || { echo "group_join_latency.sh: sensor-sim exit $a_rc/$b_rc, estimator exit $e_rc (logs in $work)"; keep=1; exit 1; }
awk -F, -v join="$join_ns" '
  NR == 1 { for (i = 1; i <= NF; ++i) col[$i] = i; next }
  $col["group"] ~ /^a-/ {
    r = $col["received_ns"]; l = ($col["fed_ns"] - r) / 1e6
    if (r < join && $col["sequence"] >= 40) before[nb++] = l
    else if (r >= join && r < join + 2e9) after[na++] = l
  }
  function pct(v, n, q,   i, j, t) {  # v sorted in place (insertion sort: a few hundred values)
    for (i = 1; i < n; ++i) { t = v[i]; for (j = i - 1; j >= 0 && v[j] > t; --j) v[j + 1] = v[j]; v[j + 1] = t }
    j = int(q * n); if (j >= n) j = n - 1; return v[j]
  }
  END {
    if (nb == 0 || na == 0) { print "group_join_latency.sh: no a-frames before or after the join"; exit 1 }
    p = pct(before, nb, 0.99); m = before[nb - 1]; q = pct(after, na, 0.99); x = after[na - 1]
    printf "a-groups received->fed ms: steady before join p99 %.2f max %.2f (n=%d); 2 s after the join p99 %.2f max %.2f (n=%d)\n", p, m, nb, q, x, na
  }' "$work/trace.csv"
