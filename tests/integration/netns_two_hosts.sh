#!/usr/bin/env bash
# Multi-host behaviour between two network namespaces that this test creates (and removes): the sensor side
# (host A) runs sensor-replay, the analytics side (host B) runs causal-estimator and alarm-recommender.
# They talk UDPv4 only, with the plant profile (deploy/dds/plant.xml) rewritten for the test hosts'
# addresses: unicast initial peers, no multicast, no shared memory. Exit 77 = skipped (no permission).
#   netns_two_hosts.sh <build/services dir> <deploy dir>
set -uo pipefail
bin="$1"; deploy="$2"
if [ "$(id -u)" -ne 0 ] || ! ip netns add "ctprobe$$" 2>/dev/null; then
  echo "SKIP: creating network namespaces needs root (CAP_NET_ADMIN)"; exit 77
fi
ip netns del "ctprobe$$"

tag=$$
ns_a="ct_a_$tag"; ns_b="ct_b_$tag"; veth_a="vca$tag"; veth_b="vcb$tag"
addr_a="10.231.$(( tag % 200 )).1"; addr_b="10.231.$(( tag % 200 )).2"
work="$(mktemp -d)"
pids=()
cleanup() {
  for p in "${pids[@]}"; do kill -TERM "$p" 2>/dev/null; done
  for p in "${pids[@]}"; do wait "$p" 2>/dev/null; done
  ip netns del "$ns_a" 2>/dev/null; ip netns del "$ns_b" 2>/dev/null  # removes the veth pair too
  rm -rf "$work"
}
trap cleanup EXIT

ip netns add "$ns_a" && ip netns add "$ns_b" || { echo "FAIL: cannot create namespaces"; exit 1; }
ip link add "$veth_a" type veth peer name "$veth_b"
ip link set "$veth_a" netns "$ns_a"; ip link set "$veth_b" netns "$ns_b"
ip -n "$ns_a" addr add "$addr_a/24" dev "$veth_a"; ip -n "$ns_b" addr add "$addr_b/24" dev "$veth_b"
for ns in "$ns_a" "$ns_b"; do ip -n "$ns" link set lo up; done
ip -n "$ns_a" link set "$veth_a" up; ip -n "$ns_b" link set "$veth_b" up

# The plant profile for each host: its own address whitelisted, both hosts as initial peers.
profile() {  # $1 = this host's address
  sed -e "s|<address>192.0.2.10</address>  <!-- this host's plant-network address -->|<address>$1</address>|" \
      -e "s|<address>192.0.2.10</address>  <!-- this host -->|<address>$1</address>|" \
      -e "s|<locator><udpv4><address>192.0.2.10</address></udpv4></locator>  <!-- sensor / replay host -->|<locator><udpv4><address>$addr_a</address></udpv4></locator>|" \
      -e "s|<locator><udpv4><address>192.0.2.11</address></udpv4></locator>  <!-- estimator host -->|<locator><udpv4><address>$addr_b</address></udpv4></locator>|" \
      -e "/192.0.2.12/d" "$deploy/dds/plant.xml"
}
profile "$addr_a" > "$work/host_a.xml"; profile "$addr_b" > "$work/host_b.xml"
grep -q "$addr_a" "$work/host_a.xml" && grep -q "$addr_b" "$work/host_b.xml" && ! grep -q "<address>192.0.2" "$work/host_b.xml" \
  || { echo "FAIL: plant.xml no longer has the expected shape"; exit 1; }

domain=$(( 100 + tag % 100 ))
common_b=(--domain "$domain" --dds-transport "$work/host_b.xml")
ip netns exec "$ns_b" "$bin/alarm_recommender/alarm-recommender" "${common_b[@]}" --idle-exit 4 --max-runtime 120 \
  > "$work/alarm.log" 2>&1 & pids+=($!)
ip netns exec "$ns_b" "$bin/causal_estimator/causal-estimator" "${common_b[@]}" --idle-exit 3 --max-runtime 120 \
  --wait-for alarm-recommender > "$work/estimator.log" 2>&1 & pids+=($!)
ip netns exec "$ns_a" "$bin/sensor_replay/sensor-replay" --domain "$domain" --dds-transport "$work/host_a.xml" \
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
