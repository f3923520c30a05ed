#!/usr/bin/env bash
# A slow link between two hosts (network namespaces this test creates and removes, joined by a veth pair whose
# host-B side is limited with tc tbf; there is no netem here). Host A runs sensor-replay and causal-recorder,
# host B causal-estimator and alarm-recommender: frames cross A -> B, condition vectors, factors and alarms
# cross B -> A through the slow link. The estimator's outbound queue is made small (--outbound-queue 64) so the
# link is the bottleneck. Stated policy (README "Delivery contract"): condition vectors, condition-level factors
# and alarms arrive complete; sample-level factor messages may be dropped at the estimator's queue, and every
# one dropped is counted: queued = sent + dropped, and the recorder receives exactly what was sent.
# Exit 77 = skipped (no permission).
#   netns_slow_link.sh <build/services dir> <deploy dir>
set -uo pipefail
bin="$1"; deploy="$2"
tag=$$; net=232
source "$(dirname "$0")/../support/netns_hosts.sh"
command -v tc >/dev/null || { echo "SKIP: tc (iproute2) not installed"; exit 77; }
# B -> A at 4 Mbit/s: the sample-level stream (about 2 MB here) takes seconds to cross.
ip netns exec "$ns_b" tc qdisc add dev "$veth_b" root tbf rate 4mbit burst 32kb latency 400ms \
  || { echo "SKIP: tc tbf is not available in this kernel"; exit 77; }

domain=214  # a fixed id per fault test (tests/fault/CMakeLists.txt)
# Sample-level factors every 128 samples instead of the shipped 1024: 8 batches per frame and estimator (1920 in
# all, about 2 MB; the shipped cadence made 960 messages while every outcome was its own message). With batches
# at the shipped cadence (240) the stream fitted into the outbound queue and the sample writer's ring, nothing
# overflowed even at 1 Mbit/s, and the test exists to see the overflow policy at work.
sed 's/^  publish_every: 1024 .*/  publish_every: 128/' "$deploy/config/estimator.yaml" > "$work/estimator.yaml"
grep -q '^  publish_every: 128$' "$work/estimator.yaml" || { echo "FAIL: cannot set publish_every"; exit 1; }
common_a=(--domain "$domain" --transport "$work/host_a.xml")
common_b=(--domain "$domain" --transport "$work/host_b.xml")
ip netns exec "$ns_a" "$bin/causal_recorder/causal-recorder" "${common_a[@]}" --out "$work/rec" --sample-level \
  --idle-exit 5 --max-runtime 150 > "$work/recorder.log" 2>&1 & pids+=($!)
ip netns exec "$ns_b" "$bin/alarm_recommender/alarm-recommender" "${common_b[@]}" --idle-exit 5 --max-runtime 150 \
  > "$work/alarm.log" 2>&1 & pids+=($!)
ip netns exec "$ns_b" "$bin/causal_estimator/causal-estimator" "${common_b[@]}" --idle-exit 3 --max-runtime 150 \
  --params "$work/estimator.yaml" --outbound-queue 64 --wait-for alarm-recommender --wait-for causal-recorder --wait-timeout 60 \
  > "$work/estimator.log" 2>&1 & pids+=($!)
started=$(date +%s)
ip netns exec "$ns_a" "$bin/sensor_replay/sensor-replay" "${common_a[@]}" --ims-dir "$deploy/data/ims2-slice" \
  --wait-for causal-estimator --wait-timeout 60 > "$work/replay.log" 2>&1
replay_rc=$?
rcs=()
for p in "${pids[@]}"; do wait "$p"; rcs+=($?); done
pids=()
echo "run took $(( $(date +%s) - started )) s; exit codes recorder/recommender/estimator: ${rcs[*]}, replay: $replay_rc"
grep -h "summary topic" "$work"/*.log | sed 's/^.*\[\(.*\)\] [a-z]* /\1: /'
fail() { echo "FAIL: $1"; exit 1; }
[ $replay_rc -eq 0 ] || fail "sensor-replay exited $replay_rc"
num() { grep -o "$1" "$2" | tail -n 1 | grep -o '[0-9]*$'; }
est="$work/estimator.log"
cv_sent=$(num 'topic=causal_twin/condition_vector sent=[0-9]*' "$est")
cv_dropped=$(num 'topic=causal_twin/condition_vector sent=[0-9]* dropped=[0-9]*' "$est")
cf_dropped=$(num 'topic=causal_twin/causal_factors/condition sent=[0-9]* dropped=[0-9]*' "$est")
cf_sent=$(num 'topic=causal_twin/causal_factors/condition sent=[0-9]*' "$est")
sf_sent=$(num 'topic=causal_twin/causal_factors/sample sent=[0-9]*' "$est")
sf_dropped=$(num 'topic=causal_twin/causal_factors/sample sent=[0-9]* dropped=[0-9]*' "$est")
sf_failed=$(num 'topic=causal_twin/causal_factors/sample sent=[0-9]* dropped=[0-9]* failed=[0-9]*' "$est")
# What the estimator produced at sample level: "asset '...': N frames (...), ..., S sample-level and C condition-level".
sf_made=$(grep -o "[0-9]* sample-level and" "$est" | head -n 1 | grep -o '^[0-9]*')
echo "sample-level factor messages: produced $sf_made, sent $sf_sent, dropped $sf_dropped, failed $sf_failed"
[ "$cv_sent" = 6 ] && [ "$cv_dropped" = 0 ] || fail "condition vectors: sent $cv_sent dropped $cv_dropped (want 6, 0)"
[ "$cf_dropped" = 0 ] && [ "$cf_sent" = 12 ] || fail "condition-level factor batches: sent $cf_sent dropped $cf_dropped (want 12 = 6 snapshots x 2 estimators, 0)"
[ $(( sf_sent + sf_dropped + sf_failed )) -eq "$sf_made" ] || fail "sample level: sent + dropped + failed != produced"
[ "$sf_dropped" -gt 0 ] || fail "the slow link did not make the queue overflow: the test no longer tests the policy"
rec="$work/recorder.log"
rec_cv=$(num 'topic=causal_twin/condition_vector file=[^ ]* written=[0-9]*' "$rec")
[ "$rec_cv" = 6 ] || fail "the recorder wrote $rec_cv condition vectors (want 6)"
# Every sample-level message the estimator sent crossed the slow link (reliable): received by the recorder.
rec_sf=0
for f in sample_filter sample_fixed-lag; do
  n=$(grep -o "causal factors factors_[^ ]*_${f}.csv: received [0-9]*" "$rec" | grep -o '[0-9]*$')
  rec_sf=$(( rec_sf + ${n:-0} ))
done
[ "$rec_sf" -eq "$sf_sent" ] || fail "the recorder received $rec_sf sample-level messages, the estimator sent $sf_sent"
alarms_sent=$(num 'topic=causal_twin/alarm sent=[0-9]*' "$work/alarm.log")
alarms_rec=$(grep -o "alarms: received [0-9]*" "$rec" | grep -o '[0-9]*$')
[ "$alarms_rec" = "$alarms_sent" ] || fail "alarms: recommender sent $alarms_sent, recorder received $alarms_rec"
echo "PASS: over a 4 Mbit/s link: 6/6 condition vectors, 12/12 condition factor batches, $alarms_rec/$alarms_sent alarms;" \
     "sample level $sf_sent sent and received, $sf_dropped dropped by the stated policy (counted)"
