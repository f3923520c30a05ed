#!/usr/bin/env bash
# Factor-path throughput (README "Lean data path"): sensor-sim -> causal-estimator -> alarm-recommender over the
# loopback profile, as fast as the readers take the frames, a bounded number of frames per group. Prints the
# end-to-end rate and checks delivery exactly (every factor message the estimator sent was received by the
# recommender, nothing lost, dropped or refused). Run it twice with different binaries or QoS files to compare.
#
#   tests/bench/lean_path.sh [--build DIR | --bin DIR] [--qos FILE] [--domain N] [--groups N]
#                            [--frames-per-group N] [--params FILE] [--runs N]
#
# --build: a build tree (default ./build); --bin: a folder holding causal-estimator, alarm-recommender and
# sensor-sim (e.g. copies of an older build). Time: from the start of sensor-sim to the estimator's exit, minus its
# --idle-exit wait (1 s): the estimator drains its output and waits for the acknowledgements after that wait,
# so the interval covers every frame processed and every factor message delivered. CPU time per frame of the
# estimator and the recommender (user + system, /usr/bin/time) varies less than the rate on a shared machine.
set -euo pipefail
here="$(cd "$(dirname "$0")/../.." && pwd)"
build="$here/build" bin="" qos="$here/deploy/dds/qos.xml" domain=88 groups=16 frames=200 runs=1
params="$here/deploy/config/estimator.yaml"
. "$here/deploy/bench_options.sh"
parse_options "$0" 2,14 --build=build --bin=bin --qos=qos --domain=domain --groups=groups --frames-per-group=frames \
  --params=params --runs=runs -- "$@"
if [ -n "$bin" ]; then
  est="$bin/causal-estimator" rec="$bin/alarm-recommender" sim="$bin/sensor-sim"
else
  est="$build/services/causal_estimator/causal-estimator" rec="$build/services/alarm_recommender/alarm-recommender"
  sim="$build/services/sensor_sim/sensor-sim"
fi
common=(--domain "$domain" --qos "$qos" --transport "$here/deploy/dds/localhost.xml")
work="$(mktemp -d /tmp/lean_path.XXXXXX)"
pids=()
cleanup() { for p in "${pids[@]}"; do kill "$p" 2>/dev/null || true; done; }
trap cleanup EXIT
frame_samples=1024 idle=1
num() { grep -o "$1" "$2" | tail -n 1 | grep -o '[0-9]*$' || echo 0; }

for run in $(seq 1 "$runs"); do
  /usr/bin/time -f 'cpu_s=%U+%S' -o "$work/rec$run.cpu" "$rec" "${common[@]}" --params "$here/deploy/config/alarms.yaml" --idle-exit 3 --max-runtime 600 \
    > "$work/rec$run.log" 2>&1 & rec_pid=$!; pids+=("$rec_pid")
  /usr/bin/time -f 'cpu_s=%U+%S' -o "$work/est$run.cpu" "$est" "${common[@]}" --params "$params" --idle-exit "$idle" --max-runtime 600 --wait-for alarm-recommender \
    > "$work/est$run.log" 2>&1 & est_pid=$!; pids+=("$est_pid")
  t0=$(date +%s.%N)
  "$sim" --domain "$domain" --qos "$qos" --transport "$here/deploy/dds/localhost.xml" --groups "$groups" \
    --channels 4 --frame-samples "$frame_samples" --frames-per-group "$frames" --seed 7 --wait-subscribers 1 \
    --wait-timeout 60 --max-runtime 600 > "$work/sim$run.log" 2>&1 || { echo "lean_path: sensor-sim failed ($work)" >&2; exit 1; }
  est_rc=0; wait "$est_pid" || est_rc=$?
  t1=$(date +%s.%N)
  rec_rc=0; wait "$rec_pid" || rec_rc=$?
  sent_frames=$(num 'sent frames=[0-9]*' "$work/sim$run.log")
  factors_sent=$(num 'published factors=[0-9]*' "$work/est$run.log")
  factors_received=$(num 'topic=causal_twin/causal_factors received=[0-9]*' "$work/rec$run.log")
  seconds=$(echo "$t1 - $t0 - $idle" | bc -l)
  vectors=$(( sent_frames * frame_samples ))
  cpu() { echo "$(grep -o 'cpu_s=[0-9.+]*' "$1" | cut -d= -f2)" | bc -l; }
  est_cpu=$(cpu "$work/est$run.cpu") rec_cpu=$(cpu "$work/rec$run.cpu")
  exact=no
  [ "$est_rc" = 0 ] && [ "$rec_rc" = 0 ] && [ "$factors_sent" = "$factors_received" ] && [ "$factors_sent" -gt 0 ] && exact=yes
  printf 'lean_path: run=%d frames=%d groups=%d seconds=%.2f frames_per_s=%.0f sample_vectors_per_s=%.0f '\
'estimator_cpu_us_per_frame=%.0f recommender_cpu_us_per_frame=%.0f factors_sent=%d recommender_received=%d exact=%s\n' \
    "$run" "$sent_frames" "$groups" "$seconds" "$(echo "$sent_frames / $seconds" | bc -l)" \
    "$(echo "$vectors / $seconds" | bc -l)" "$(echo "$est_cpu * 1000000 / $sent_frames" | bc -l)" \
    "$(echo "$rec_cpu * 1000000 / $sent_frames" | bc -l)" "$factors_sent" "$factors_received" "$exact"
  if [ "$exact" != yes ]; then
    echo "lean_path: delivery not exact (estimator rc $est_rc, recommender rc $rec_rc); logs in $work" >&2
    exit 1
  fi
done
rm -rf "$work"
