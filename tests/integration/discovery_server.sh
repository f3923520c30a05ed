#!/usr/bin/env bash
# The pipeline through a Fast DDS discovery server on loopback (README "Networks"): a discovery server
# (fastdds-tools; `fastdds discovery -i 0 -l 127.0.0.1 -p PORT` runs this same program) and the services as its
# clients with the shipped deploy/dds/discovery_client.xml (its port changed to this test's). The client profile
# has no initial peers and no multicast, so the services can only meet through the server. Passes when
# deploy/launch.sh exits 0 (every count exact: nothing lost, dropped or refused) and the replay's sent count
# equals the estimator's received count for condition_input. With `factor-sets` the estimator writes one
# CausalFactorSet per input (estimator.yaml output.factor_messages: set, in a copy of deploy/config): the set
# writer announces itself through the server too, and alarm-recommender's set count must equal the sets sent.
#   discovery_server.sh <build dir> <deploy dir> [factor-sets]
set -euo pipefail
build="$1"
deploy="$2"
mode="${3:-batch}"
domain=96
port=11896
work="$(mktemp -d)"
server_pid=""
cleanup() {
  [ -n "$server_pid" ] && { kill -TERM "$server_pid" 2>/dev/null || true; wait "$server_pid" 2>/dev/null || true; }
  rm -rf "$work"
}
trap cleanup EXIT

sed "s|<port>11811</port>|<port>$port</port>|" "$deploy/dds/discovery_client.xml" > "$work/client.xml"
grep -q "<port>$port</port>" "$work/client.xml" || { echo "FAIL: could not set the server port"; exit 1; }

fast-discovery-server -i 0 -l 127.0.0.1 -p "$port" > "$work/server.log" 2>&1 &
server_pid=$!
sleep 1
kill -0 "$server_pid" 2>/dev/null || { echo "FAIL: discovery server did not start"; cat "$work/server.log"; exit 1; }

config_env=()
if [ "$mode" = factor-sets ]; then
  cp -r "$deploy/config" "$work/config"
  sed -i 's/^\(  factor_messages:\) batch /\1 set   /' "$work/config/estimator.yaml"
  grep -q '^  factor_messages: set ' "$work/config/estimator.yaml" || { echo "FAIL: could not set factor-sets"; exit 1; }
  config_env=(CAUSAL_TWIN_CONFIG_DIR="$work/config")
elif [ "$mode" != batch ]; then
  echo "usage: discovery_server.sh <build dir> <deploy dir> [factor-sets]" >&2; exit 2
fi

rc=0
env "${config_env[@]}" CAUSAL_TWIN_BUILD_DIR="$build" "$deploy/launch.sh" --domain "$domain" --transport "$work/client.xml" \
  --features "$deploy/data/ims2-features/derived_per_file_stats_all984.csv" --feature-suffix _meanabs \
  --feature-name meanabs --max-runtime 100 --logs "$work/logs" > "$work/launch.out" 2>&1 || rc=$?
cat "$work/launch.out" | grep -E "launch:|summary|condition_input|condition_vector" || true
if [ "$rc" != 0 ]; then echo "FAIL: launch.sh exited $rc"; tail -40 "$work/launch.out"; exit 1; fi

sent=$(grep -o 'summary topic=causal_twin/condition_input sent=[0-9]*' "$work/logs/sensor-replay.log" | grep -o '[0-9]*$')
received=$(grep -o 'summary topic=causal_twin/condition_input received=[0-9]*' "$work/logs/causal-estimator.log" | grep -o '[0-9]*$')
echo "condition_input: sent=$sent received=$received"
[ "$sent" = 984 ] && [ "$received" = 984 ] || { echo "FAIL: want 984 sent and 984 received"; exit 1; }
if [ "$mode" = factor-sets ]; then
  sets=$(grep -o 'summary topic=causal_twin/causal_factor_sets/condition sent=[0-9]*' \
    "$work/logs/causal-estimator.log" | grep -o '[0-9]*$' || true)
  taken=$(grep -o 'summary topic=causal_twin/causal_factor_sets received=[0-9]*' \
    "$work/logs/alarm-recommender.log" | grep -o '[0-9]*$' || true)
  echo "causal_factor_sets: sent=$sets received=$taken"
  [ -n "$sets" ] && [ "$sets" -gt 0 ] && [ "$sets" = "$taken" ] || { echo "FAIL: want the sets sent received"; exit 1; }
fi
echo "PASS: the pipeline ($mode) ran through the discovery server on 127.0.0.1:$port"
