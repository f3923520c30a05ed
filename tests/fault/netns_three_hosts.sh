#!/usr/bin/env bash
# Many hosts from configuration only (README "Many hosts"): three test hosts (network namespaces this test
# creates and removes, joined by a bridge in a fourth, "switch", namespace) run the pipeline with the Fast DDS
# profiles that causal-plant-profiles generates from a plant file:
#   sensor host     two sensor-replays: the raw IMS slice (frames, asset group ims2-raw) and the 984-snapshot
#                   feature table (condition inputs, ims2-shaft1); one reads its profile from
#                   $FASTRTPS_DEFAULT_PROFILES_FILE, the other from --transport (both mechanisms, no code change)
#   estimator host  causal-estimator shards 0/2 and 1/2 (ims2-shaft1 hashes to shard 0, ims2-raw to shard 1)
#   operator host   alarm-recommender and causal-recorder (UDPv4 to the others and between them)
# Every host has its own /dev/shm. The same data runs at once on one host over loopback (localhost.xml, one
# unsharded estimator, in a fifth namespace) as the reference. Checked exactly: frames and condition inputs
# sent == received by the estimators, every service exit 0, and the recordings (condition vectors,
# condition-level factors, alarms, recommendations) byte-identical to the single-host run. DDS-Security is
# OFF by default (open bus): this test is about placement and transport; tests/security covers the secured bus.
# With "discovery-server" the plant file names the operator host as the Fast DDS discovery server: the services
# there and elsewhere are its clients (no peer lists) and fast-discovery-server runs on that host.
# With "secured" the plant file names a PKI made by make-pki.sh (not registered with ctest: 2 of 4 runs failed,
# the recommender with "factor sets never completed" (exit 4), once the recorder wrote a partial fixed-lag row
# for snapshot 981 (duplicates=2): outcome messages of one index arriving after later ones).
# Domains 84 (three hosts) and 85 (reference), each inside its own namespaces, so the variants cannot meet.
# Exit 77 = skipped (no root / no network namespaces).
#   netns_three_hosts.sh <build/services dir> <deploy dir> [discovery-server|secured]
set -uo pipefail
bin="$1"; deploy="$2"; mode="${3:-peers}"
case "$mode" in peers|discovery-server|secured) ;; *) echo "unknown mode '$mode' (peers, discovery-server, secured)"; exit 2;; esac
tag=$$
source "$(dirname "$0")/../support/netns_common.sh"
fail() { echo "FAIL: $1"; exit 1; }

domain=84; ref_domain=85
sub="10.84.$(( tag % 200 ))"
ns_sensor="ct84s_$tag"; ns_est="ct84e_$tag"; ns_ops="ct84o_$tag"; ns_switch="ct84w_$tag"; ns_ref="ct84r_$tag"
for ns in "$ns_switch" "$ns_sensor" "$ns_est" "$ns_ops" "$ns_ref"; do netns_create "$ns"; done
ip -n "$ns_switch" link add br0 type bridge && ip -n "$ns_switch" link set br0 up \
  || { echo "SKIP: no bridge support in this kernel"; exit 77; }
i=0
for ns in "$ns_sensor" "$ns_est" "$ns_ops"; do
  i=$(( i + 1 ))
  # Created inside the namespaces (never in the machine's own), so deleting them removes every link.
  ip -n "$ns_switch" link add "port$i" type veth peer name plant0 netns "$ns" || fail "cannot create veth $i"
  ip -n "$ns_switch" link set "port$i" master br0 up
  ip -n "$ns" addr add "$sub.$i/24" dev plant0 && ip -n "$ns" link set plant0 up || fail "cannot set $sub.$i"
done

security=off  # open bus unless secured (see the header)
if [ "$mode" = secured ]; then
  "$deploy/security/make-pki.sh" "$work/pki" > "$work/pki.log" 2>&1 || fail "make-pki.sh: $(tail -3 "$work/pki.log")"
  security="$work/pki"
fi
cat > "$work/plant.yaml" <<PLANT
domain: $domain
security: $security
hosts:
  - {name: sensor-host, address: $sub.1, interface: plant0, roles: [sensor]}
  - {name: estimator-host, address: $sub.2, interface: plant0, roles: [estimator 0/2, estimator 1/2]}
  - {name: operator-host, address: $sub.3, interface: plant0, roles: [recommender, recorder]}
PLANT
[ "$mode" = discovery-server ] && echo "discovery_server: {host: operator-host, port: 11811}" >> "$work/plant.yaml"
"$bin/../tools/plant_profiles/causal-plant-profiles" "$work/plant.yaml" --out "$work/profiles" > "$work/profiles.log" 2>&1 \
  || fail "causal-plant-profiles: $(cat "$work/profiles.log")"
for h in sensor-host estimator-host operator-host; do [ -s "$work/profiles/$h.xml" ] || fail "no profile for $h"; done

table="$deploy/data/ims2-features/derived_per_file_stats_all984.csv"
slice="$deploy/data/ims2-slice"
# Paced at 5 ms per snapshot (10 min apart in the data), as tests/security does: about 5 s.
features=(--features "$table" --feature-suffix _meanabs --feature-name meanabs --speed 120000)
# run NAME NS (then the command): in the background, logged to $work/NAME.log
services=()
run() { local name="$1" ns="$2"; shift 2; netns_host_start "$ns" "$@" > "$work/$name.log" 2>&1; services+=("$netns_last_pid"); }
started=$(date +%s)

# Reference: everything on one host, loopback profile, one estimator.
ref=(--domain "$ref_domain" --transport "$deploy/dds/localhost.xml")
run ref_recorder "$ns_ref" "$bin/causal_recorder/causal-recorder" "${ref[@]}" --out "$work/ref_rec" --idle-exit 6 --max-runtime 90
run ref_recommender "$ns_ref" "$bin/alarm_recommender/alarm-recommender" "${ref[@]}" --idle-exit 6 --max-runtime 90
run ref_estimator "$ns_ref" "$bin/causal_estimator/causal-estimator" "${ref[@]}" --idle-exit 3 --max-runtime 90 \
  --wait-for alarm-recommender --wait-for causal-recorder
run ref_replay_raw "$ns_ref" "$bin/sensor_replay/sensor-replay" "${ref[@]}" --ims-dir "$slice" --asset-group ims2-raw \
  --wait-for causal-estimator --wait-timeout 60
run ref_replay_features "$ns_ref" "$bin/sensor_replay/sensor-replay" "${ref[@]}" "${features[@]}" \
  --wait-for causal-estimator --wait-timeout 60

# Three hosts: each service with its host's generated profile.
if [ "$mode" = discovery-server ]; then
  grep -q "<discoveryProtocol>CLIENT</discoveryProtocol>" "$work/profiles/sensor-host.xml" || fail "no client profile"
  # Ended by the clean-up (it is in pids), after the services.
  [ -s "$work/profiles/operator-host.discovery-server.xml" ] || fail "no discovery server profile"
  netns_host_start "$ns_ops" fast-discovery-server -x "$work/profiles/operator-host.discovery-server.xml" \
    > "$work/server.log" 2>&1
  server_pid=$netns_last_pid
  sleep 1
  kill -0 "$server_pid" 2>/dev/null || fail "the discovery server did not start: $(cat "$work/server.log")"
fi
p="$work/profiles"
ops=(--domain "$domain" --transport "$p/operator-host.xml")
est=(--domain "$domain" --transport "$p/estimator-host.xml")
run recorder "$ns_ops" "$bin/causal_recorder/causal-recorder" "${ops[@]}" --out "$work/rec" --idle-exit 6 --max-runtime 90
run recommender "$ns_ops" "$bin/alarm_recommender/alarm-recommender" "${ops[@]}" --idle-exit 6 --max-runtime 90
for k in 0 1; do
  run "estimator$k" "$ns_est" "$bin/causal_estimator/causal-estimator" "${est[@]}" --shard-index "$k" --shard-count 2 \
    --idle-exit 3 --max-runtime 90 --wait-for alarm-recommender --wait-for causal-recorder
done
run replay_raw "$ns_sensor" "$bin/sensor_replay/sensor-replay" --domain "$domain" --transport "$p/sensor-host.xml" \
  --ims-dir "$slice" --asset-group ims2-raw --wait-for causal-estimator:2 --wait-timeout 60
run replay_features "$ns_sensor" env FASTRTPS_DEFAULT_PROFILES_FILE="$p/sensor-host.xml" \
  "$bin/sensor_replay/sensor-replay" --domain "$domain" "${features[@]}" --wait-for causal-estimator:2 --wait-timeout 60

names=(ref_recorder ref_recommender ref_estimator ref_replay_raw ref_replay_features
       recorder recommender estimator0 estimator1 replay_raw replay_features)
rcs=()
for p_ in "${services[@]}"; do wait "$p_"; rcs+=($?); done
pids=(${server_pid:+"$server_pid"})  # the services are reaped: only the discovery server is left to end
echo "run took $(( $(date +%s) - started )) s"
for n in "${!names[@]}"; do
  [ "${rcs[$n]}" = 0 ] || grep -h -E "\] [a-z-]* (warning|error|critical) " "$work"/*.log | grep -v ALARM | sed "s/^[^[]*//" | sort | uniq -c | head -n 20
  [ "${rcs[$n]}" = 0 ] || fail "${names[$n]} exited ${rcs[$n]}:"$'\n'"$(tail -n 8 "$work/${names[$n]}.log")"
done
grep -h "summary topic" "$work"/estimator?.log "$work"/replay_*.log | sed 's/^.*\] [a-z]* //'

num() { grep -o "$1" "$2" | tail -n 1 | grep -o '[0-9]*$'; }
# Frames: 6 snapshots x 20 frames of 1024 samples, all to shard 1 (ims2-raw).
frames_sent=$(num 'topic=causal_twin/vibration_frame sent=[0-9]*' "$work/replay_raw.log")
[ "$frames_sent" = 120 ] || fail "sensor-replay sent $frames_sent frames (want 120)"
grep -q "asset 'ims2-raw': 120 frames (0 lost, 0 refused)" "$work/estimator1.log" \
  || fail "estimator shard 1 did not take the 120 frames: $(grep "asset '" "$work/estimator1.log")"
inputs_sent=$(num 'topic=causal_twin/condition_input sent=[0-9]*' "$work/replay_features.log")
inputs_received=$(num 'topic=causal_twin/condition_input received=[0-9]*' "$work/estimator0.log")
[ "$inputs_sent" = 984 ] && [ "$inputs_received" = 984 ] \
  || fail "condition inputs: sent $inputs_sent, received by shard 0 $inputs_received (want 984, 984)"
for k in 0 1; do
  grep -h "asset '" "$work/estimator$k.log" | sed "s/^.*\] [a-z]* /shard $k: /"
done

# The recordings: byte-identical to the single-host run's.
files=(conditions_ims2-raw_meanabs.csv conditions_ims2-shaft1_meanabs.csv alarms.csv recommendations.csv)
for f in "$work"/ref_rec/factors_*_condition_*.csv; do files+=("$(basename "$f")"); done
[ ${#files[@]} -ge 8 ] || fail "the reference recorded ${#files[@]} files: $(ls "$work/ref_rec")"
for f in "${files[@]}"; do
  [ -s "$work/ref_rec/$f" ] || fail "$f not recorded in the single-host run: $(ls "$work/ref_rec")"
  [ -s "$work/rec/$f" ] || fail "$f not recorded across the three hosts"
  cmp -s "$work/ref_rec/$f" "$work/rec/$f" \
    || fail "$f differs from the single-host run: $(diff <(cut -c1-80 "$work/ref_rec/$f") <(cut -c1-80 "$work/rec/$f") | head -5)"
  echo "$f: $(( $(wc -l < "$work/rec/$f") - 1 )) rows, identical to the single-host run"
done

# Remove the hosts now (not only at exit) to check that nothing is left.
netns_cleanup; trap - EXIT
left=$(ip netns list | grep -c "_$tag\b")
[ "$left" = 0 ] && [ ! -e "$netns_shm_root" ] && { [ -n "${KEEP_NETNS_WORK:-}" ] || [ ! -e "$work" ]; } || fail "left behind: $left namespaces, $netns_shm_root, $work"
echo "PASS ($mode): three hosts from generated profiles: 120/120 frames, 984/984 condition inputs, recordings identical" \
     "to the single-host run; namespaces, links and /dev/shm folders removed"
