#!/usr/bin/env bash
# Hot standby: a primary and a standby causal-estimator (--standby) receive the 984-snapshot feature replay
# (paced, about 40 s); the primary is killed (SIGKILL) 12 s in. The standby must take over, and the recording
# (conditions, condition-level factors, alarms, recommendations) must equal, byte for byte, that of the same run
# without a crash (run beside it on another domain).
#   hot_standby.sh <build/services dir> <deploy dir>
set -uo pipefail
bin="$1"; deploy="$2"
work="$(mktemp -d)"
pids=()
cleanup() {
  for p in "${pids[@]}"; do kill -TERM "$p" 2>/dev/null; done
  for p in "${pids[@]}"; do wait "$p" 2>/dev/null; done
  rm -rf "$work"
}
trap cleanup EXIT
table="$deploy/data/ims2-features/derived_per_file_stats_all984.csv"
run() {  # $1 = name, $2 = domain, $3 = kill the primary (1/0)
  local out="$work/$1" c=(--domain "$2") primary
  mkdir -p "$out"
  "$bin/causal_recorder/causal-recorder" "${c[@]}" --out "$out/rec" --idle-exit 6 --max-runtime 150 > "$out/recorder.log" 2>&1 & pids+=($!)
  "$bin/alarm_recommender/alarm-recommender" "${c[@]}" --idle-exit 6 --max-runtime 150 > "$out/recommender.log" 2>&1 & pids+=($!)
  "$bin/causal_estimator/causal-estimator" "${c[@]}" --idle-exit 4 --max-runtime 150 --wait-for alarm-recommender \
    --wait-for causal-recorder > "$out/primary.log" 2>&1 & primary=$!; pids+=($primary)
  "$bin/causal_estimator/causal-estimator" "${c[@]}" --idle-exit 4 --max-runtime 150 --wait-for alarm-recommender \
    --wait-for causal-recorder --standby > "$out/standby.log" 2>&1 & pids+=($!)
  "$bin/sensor_replay/sensor-replay" "${c[@]}" --features "$table" --feature-suffix _meanabs --feature-name meanabs \
    --speed 15000 --wait-for causal-estimator:2 --wait-timeout 60 > "$out/replay.log" 2>&1 & pids+=($!)
  if [ "$3" = 1 ]; then
    ( sleep 12; kill -KILL "$primary" && echo "$1: primary killed (SIGKILL) 12 s into the run" ) &
  fi
}
run crash $(( 224 + $$ % 4 )) 1  # fault tests own 200..231; this one 224..231
run clean $(( 228 + $$ % 4 )) 0
for p in "${pids[@]}"; do wait "$p" 2>/dev/null; done
pids=()
wait
fail() { echo "FAIL: $1"; exit 1; }
grep -h "taking over" "$work"/crash/standby.log || fail "the standby did not take over:"$'\n'"$(tail -5 "$work/crash/standby.log")"
grep -q "never took over" "$work"/clean/standby.log || fail "the standby took over although the primary lived"
for f in conditions_ims2-shaft1_meanabs.csv factors_ims2-shaft1_condition_filter.csv \
         factors_ims2-shaft1_condition_fixed-lag.csv alarms.csv recommendations.csv; do
  [ -s "$work/clean/rec/$f" ] || fail "$f not recorded in the clean run"
  cmp -s "$work/clean/rec/$f" "$work/crash/rec/$f" || fail "$f differs after the takeover: $(diff <(cut -c1-60 "$work/clean/rec/$f") <(cut -c1-60 "$work/crash/rec/$f") | head -5)"
  echo "$f: $(( $(wc -l < "$work/crash/rec/$f") - 1 )) rows, identical"
done
echo "PASS: the standby took over after the primary's SIGKILL; the recording is byte-identical to the run without a crash"
