#!/usr/bin/env bash
# Hot standby: a primary and a standby causal-estimator (--standby) receive the 984-snapshot feature replay
# (paced, about 40 s); the primary is killed (SIGKILL) 12 s in. The standby must take over, and the recording
# (conditions, condition-level factors, alarms, recommendations) must equal, byte for byte, that of the same run
# without a crash (run beside it on another domain).
#   hot_standby.sh <build/services dir> <deploy dir> [sharded]
# sharded: two asset groups (the table replayed as ims2-shaft1 and ims2-shaft2) on two estimator shards (a
# shards file: east owns shaft1, west shaft2) and a standby of shard east only. West's primary stays alive all
# along: the standby must still take over from east's primary (it follows only its own shard's primary), and
# both groups' recordings must equal the run without a crash.
set -uo pipefail
bin="$1"; deploy="$2"; mode="${3:-single}"
work="$(mktemp -d)"
pids=()
cleanup() {
  for p in "${pids[@]}"; do kill -TERM "$p" 2>/dev/null; done
  for p in "${pids[@]}"; do wait "$p" 2>/dev/null; done
  rm -rf "$work"
}
trap cleanup EXIT
table="$deploy/data/ims2-features/derived_per_file_stats_all984.csv"
groups=(ims2-shaft1)
shard_args=()  # the primary's and the standby's shard options
if [ "$mode" = sharded ]; then
  groups=(ims2-shaft1 ims2-shaft2)
  printf 'shards:\n  east: ["ims2-shaft1"]\n  west: ["ims2-shaft2"]\n' > "$work/shards.yaml"
  shard_args=(--shards "$work/shards.yaml" --shard east)
fi
estimators=$(( ${#groups[@]} + 1 ))  # a primary per shard and one standby
run() {  # $1 = name, $2 = domain, $3 = kill the primary (1/0)
  local out="$work/$1" c=(--domain "$2") primary
  mkdir -p "$out"
  "$bin/causal_recorder/causal-recorder" "${c[@]}" --out "$out/rec" --idle-exit 6 --max-runtime 150 > "$out/recorder.log" 2>&1 & pids+=($!)
  "$bin/alarm_recommender/alarm-recommender" "${c[@]}" --idle-exit 6 --max-runtime 150 > "$out/recommender.log" 2>&1 & pids+=($!)
  "$bin/causal_estimator/causal-estimator" "${c[@]}" "${shard_args[@]}" --idle-exit 4 --max-runtime 150 \
    --wait-for alarm-recommender --wait-for causal-recorder > "$out/primary.log" 2>&1 & primary=$!; pids+=($primary)
  "$bin/causal_estimator/causal-estimator" "${c[@]}" "${shard_args[@]}" --idle-exit 4 --max-runtime 150 \
    --wait-for alarm-recommender --wait-for causal-recorder --standby > "$out/standby.log" 2>&1 & pids+=($!)
  if [ "$mode" = sharded ]; then
    "$bin/causal_estimator/causal-estimator" "${c[@]}" --shards "$work/shards.yaml" --shard west --idle-exit 4 \
      --max-runtime 150 --wait-for alarm-recommender --wait-for causal-recorder > "$out/west.log" 2>&1 & pids+=($!)
  fi
  for g in "${groups[@]}"; do
    "$bin/sensor_replay/sensor-replay" "${c[@]}" --features "$table" --feature-suffix _meanabs --feature-name meanabs \
      --asset-group "$g" --speed 15000 --wait-for "causal-estimator:$estimators" --wait-timeout 60 \
      > "$out/replay-$g.log" 2>&1 & pids+=($!)
  done
  if [ "$3" = 1 ]; then
    ( sleep 12; kill -KILL "$primary" && echo "$1: primary killed (SIGKILL) 12 s into the run" ) &
  fi
}
if [ "$mode" = sharded ]; then
  run crash 224 1  # fixed ids per fault test (tests/fault/CMakeLists.txt)
  run clean 225 0
else
  run crash 215 1
  run clean 216 0
fi
for p in "${pids[@]}"; do wait "$p" 2>/dev/null; done
pids=()
wait
fail() { echo "FAIL: $1"; exit 1; }
grep -h "taking over" "$work"/crash/standby.log || fail "the standby did not take over:"$'\n'"$(tail -5 "$work/crash/standby.log")"
grep -q "never took over" "$work"/clean/standby.log || fail "the standby took over although the primary lived"
if [ "$mode" = sharded ]; then
  grep -q "summary shard=" "$work/crash/west.log" || fail "shard west did not end with its summary: $(tail -3 "$work/crash/west.log")"
fi
for g in "${groups[@]}"; do
  for f in "conditions_${g}_meanabs.csv" "factors_${g}_condition_filter.csv" "factors_${g}_condition_fixed-lag.csv"; do
    [ -s "$work/clean/rec/$f" ] || fail "$f not recorded in the clean run"
    cmp -s "$work/clean/rec/$f" "$work/crash/rec/$f" || fail "$f differs after the takeover: $(diff <(cut -c1-60 "$work/clean/rec/$f") <(cut -c1-60 "$work/crash/rec/$f") | head -5)"
    echo "$f: $(( $(wc -l < "$work/crash/rec/$f") - 1 )) rows, identical"
  done
done
# Alarms and recommendations: one file for every group, in arrival order, so two groups' rows interleave as
# they happen to arrive; each group's rows (ids start with the group) must be identical and in the same order.
# prognosis.csv: rows start with the group as the first column ("<group>,").
for f in alarms.csv recommendations.csv prognosis.csv; do
  [ -s "$work/clean/rec/$f" ] || fail "$f not recorded in the clean run"
  for g in "${groups[@]}"; do
    clean=$(grep -E "^$g[/,]" "$work/clean/rec/$f"); crash=$(grep -E "^$g[/,]" "$work/crash/rec/$f")
    [ -n "$clean" ] || fail "$f: no row of $g in the clean run"
    [ "$clean" = "$crash" ] || fail "$f ($g) differs after the takeover: $(diff <(cut -c1-60 <<< "$clean") <(cut -c1-60 <<< "$crash") | head -5)"
    echo "$f ($g): $(wc -l <<< "$crash") rows, identical"
  done
  [ "$(wc -l < "$work/clean/rec/$f")" = "$(wc -l < "$work/crash/rec/$f")" ] || fail "$f: row counts differ"
done
echo "PASS ($mode): the standby took over after the primary's SIGKILL; the recording is byte-identical to the run without a crash"
