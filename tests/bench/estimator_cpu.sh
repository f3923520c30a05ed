#!/usr/bin/env bash
# The estimator's CPU per frame on a fixed workload (docs/scale-and-benchmarks.md "Estimator CPU per frame"):
# deploy/bench_scale.sh's step (b) for one estimator, by hand, so two estimator binaries or QoS files can be
# compared in interleaved runs on a shared machine. causal_bench_factor_counter -> causal-estimator (under
# `perf stat -e task-clock,context-switches` when perf works, else /usr/bin/time) <- sensor-sim as fast as
# possible; prints one line per run with the estimator's user+system CPU per frame, its context switches and
# the counter's exact delivery check. Run it under tests/support/isolate.sh (its own /dev/shm and loopback).
#
#   tests/bench/estimator_cpu.sh [--build DIR] [--estimator BIN] [--qos FILE] [--groups N] [--frames-per-group N]
#                                [--runs N] [--domain N] [--keep DIR]
#
# --estimator: another causal-estimator binary (e.g. a copy of main's); the other processes come from --build.
# Exit code 1 when a run did not deliver every frame's factors exactly.
set -uo pipefail
here="$(cd "$(dirname "$0")/../.." && pwd)"
build="$here/build" est="" qos="$here/deploy/dds/qos.xml" groups=16 frames=500 runs=1 domain=209 keep=""
. "$here/deploy/bench_options.sh"
parse_options "$0" 2,13 --build=build --estimator=est --qos=qos --groups=groups --frames-per-group=frames --runs=runs \
  --domain=domain --keep=keep -- "$@"
est="${est:-$build/services/causal_estimator/causal-estimator}"
sim="$build/services/sensor_sim/sensor-sim" counter="$build/tests/bench/causal_bench_factor_counter"
. "$here/tests/bench/bench_setup.sh"
bench_start estimator_cpu.sh "$est" "$sim" "$counter"
measure=(/usr/bin/time -f "time user_s=%U sys_s=%S" -o)
perf stat -e task-clock true >/dev/null 2>&1 && measure=(perf stat -e task-clock,context-switches -o)
failed=0
for r in $(seq 1 "$runs"); do
  dir="$work/run$r"
  mkdir -p "$dir"
  "$counter" --domain "$domain" --groups "$groups" --frames-per-group "$frames" --frame-samples 1024 \
    --sample-rate 20480 --skip-frames 40 --timeout 120 --quiet-exit 5 "${dds[@]}" > "$dir/counter.out" 2>&1 &
  c=$!; pids+=($c)
  for _ in $(seq 1 100); do grep -q '^ready' "$dir/counter.out" 2>/dev/null && break; sleep 0.1; done
  "${measure[@]}" "$dir/measure.txt" "$est" --domain "$domain" "${dds[@]}" --params "$here/deploy/config/estimator.yaml" \
    --idle-exit 1 --wait-for bench-factor-counter --max-runtime 120 --log-level info > "$dir/est.log" 2>&1 &
  e=$!; pids+=($e)
  "$sim" --domain "$domain" "${dds[@]}" --groups "$groups" --channels 4 --frame-samples 1024 --sample-rate 20480 \
    --frames-per-group "$frames" --wall-clock-stamps --wait-subscribers 1 --max-runtime 120 --log-level warn \
    > "$dir/sim.out" 2>&1
  wait "$e"; est_rc=$?
  wait "$c"; counter_rc=$?
  cpu=$(grep -o 'summary cpu .*' "$dir/est.log" | tail -n1 | sed 's/^summary cpu //')
  switches=$(awk '/context-switches/ { print $1 }' "$dir/measure.txt")
  delivered=$(grep -o 'frames=[0-9]* expected=[0-9]*' "$dir/counter.out" | tail -n1)
  echo "run $r: ${cpu:-no summary cpu line} context_switches=${switches:-?} ${delivered:-no factor line} (estimator exit $est_rc, counter exit $counter_rc)"
  [ "$est_rc" = 0 ] && [ "$counter_rc" = 0 ] || failed=1
done
exit "$failed"
