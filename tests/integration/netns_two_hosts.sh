#!/usr/bin/env bash
# Multi-host behaviour between two network namespaces that this test creates (and removes): the sensor side
# (host A) runs sensor-replay, the analytics side (host B) runs causal-estimator and alarm-recommender.
# They talk UDPv4 only, with the plant profile (deploy/dds/plant.xml) rewritten for the test hosts'
# addresses: unicast initial peers, no multicast, no shared memory. Exit 77 = skipped (no permission).
#   netns_two_hosts.sh <build/services dir> <deploy dir>
set -uo pipefail
bin="$1"; deploy="$2"
tag=$$; net=231
source "$(dirname "$0")/../support/netns_hosts.sh"

domain=$(( 100 + tag % 100 ))
common_b=(--domain "$domain" --transport "$work/host_b.xml")
ip netns exec "$ns_b" "$bin/alarm_recommender/alarm-recommender" "${common_b[@]}" --idle-exit 4 --max-runtime 120 \
  > "$work/alarm.log" 2>&1 & pids+=($!)
ip netns exec "$ns_b" "$bin/causal_estimator/causal-estimator" "${common_b[@]}" --idle-exit 3 --max-runtime 120 \
  --wait-for alarm-recommender > "$work/estimator.log" 2>&1 & pids+=($!)
ip netns exec "$ns_a" "$bin/sensor_replay/sensor-replay" --domain "$domain" --transport "$work/host_a.xml" \
  --ims-dir "$deploy/data/ims2-slice" --max-snapshots 2 --wait-for causal-estimator --wait-timeout 60 > "$work/replay.log" 2>&1
replay_rc=$?
for p in "${pids[@]}"; do wait "$p"; done
pids=()
cat "$work/replay.log" "$work/estimator.log" | grep -v "snapshot [0-9]* 20" | tail -n 12
[ $replay_rc -eq 0 ] || { echo "FAIL: sensor-replay on host A exited $replay_rc"; exit 1; }
# 2 snapshots x 20 frames of 1024 samples crossed from host A to host B.
grep -q "asset 'ims2-shaft1': 40 frames (0 lost, 0 refused)" "$work/estimator.log" \
  || { echo "FAIL: the estimator on host B did not receive the 40 frames"; exit 1; }
grep -q "condition level: learning the baseline" "$work/alarm.log" \
  || { echo "FAIL: factors did not reach alarm-recommender on host B"; exit 1; }
echo "PASS: 40 frames crossed from $ns_a ($addr_a) to $ns_b ($addr_b) over UDPv4 unicast"
