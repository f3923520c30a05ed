#!/usr/bin/env bash
# A DDS process of ANOTHER USER on the services' host must not stop their delivery.
#   cross_user.sh <build/services dir> <deploy dir> [shipped|shm]
# The services (causal-estimator, alarm-recommender, causal-recorder, sensor-replay of the 984-snapshot feature
# table, ~16 s) run as this user (root in CI); 5 s into the run a second Linux user, created here
# (useradd ctwin-other, removed at the end when made here), starts its own causal-recorder (an integrator's
# historian) with runuser.
#  shipped (default): the services on the shipped profile deploy/dds/localhost-udp.xml, installed as /etc/causal-twin/localhost.xml (UDP loopback, no shared
#    memory); the other user's tool on the source tree's localhost.xml (the worst case: a tool with shared memory on, as Fast
#    DDS's defaults have it). Checked: every count exact (984 condition inputs sent = received, 984 condition
#    vectors recorded, every factor message the estimator sent received by the recommender, exit 0
#    everywhere), no reader_not_acknowledging alarm, and the other user's recorder got the data too.
#  shm: the services on the shared-memory localhost.xml (what was installed before): the other user's recorder cannot
#    acknowledge over shared memory (Fast DDS 2.9 creates its segments and ports with mode 0644), so the
#    services' writers stall; checked: a reader_not_acknowledging HEALTH alarm within 15 s of the tool joining (--ack-stall 7 s),
#    naming it (causal-recorder [user ctwin-other ...]). Bounded: the run is stopped once it is seen.
# Fixed DDS domains: 223 shipped, 68 shm (tests/fault/CMakeLists.txt): the two modes must never hear each other
# (on one domain a second causal-estimator appears, the replay rewinds for it and resends).
set -uo pipefail
bin="$1"; deploy="$2"; mode="${3:-shipped}"
. "$(dirname "$0")/other_user.sh"
work="$(mktemp -d)"
chmod 755 "$work"
pids=()
cleanup() {
  for p in "${pids[@]}"; do kill -TERM "$p" 2>/dev/null; done
  sleep 1
  for p in "${pids[@]}"; do kill -KILL "$p" 2>/dev/null; wait "$p" 2>/dev/null; done
  pkill_user_tools
  # userdel refuses a user with a running process: give the other user's tool 5 s to end on SIGTERM, then
  # SIGKILL (before, its pid file could not be written, the tool ran on to its --max-runtime and the user
  # ctwin-other was left behind).
  if [ -n "${other_job:-}" ]; then
    for _ in $(seq 50); do kill -0 "$other_job" 2>/dev/null || break; sleep 0.1; done
    [ -f "$work/other/tool.pid" ] && kill -KILL "$(cat "$work/other/tool.pid")" 2>/dev/null
    wait "$other_job" 2>/dev/null
  fi
  [ "$made_user" = 1 ] && { userdel "$other" || echo "warning: userdel $other failed: the user is left" >&2; }
  rm -rf "$work"
}
pkill_user_tools() {  # only the tool this script started as the other user (its pid file)
  [ -f "$work/other/tool.pid" ] && kill -TERM "$(cat "$work/other/tool.pid")" 2>/dev/null
}
trap cleanup EXIT
fail() { echo "FAIL: $1"; exit 1; }
need_other_user
services_profile="$deploy/dds/localhost-udp.xml"
[ "$mode" = shm ] && services_profile="$deploy/dds/localhost.xml"
tool_profile="$deploy/dds/localhost.xml"
table="$deploy/data/ims2-features/derived_per_file_stats_all984.csv"
domain=223
[ "$mode" = shm ] && domain=68
c=(--domain "$domain" --qos "$deploy/dds/qos.xml" --transport "$services_profile")
limit=90
[ "$mode" = shm ] && limit=40
echo "services: $(id -un) on $(basename "$services_profile"); the other user's tool: $other on $(basename "$tool_profile")"
"$bin/causal_recorder/causal-recorder" "${c[@]}" --out "$work/rec" --idle-exit 6 --max-runtime "$limit" > "$work/recorder.log" 2>&1 & pids+=($!)
"$bin/alarm_recommender/alarm-recommender" "${c[@]}" --idle-exit 6 --max-runtime "$limit" > "$work/recommender.log" 2>&1 & pids+=($!)
"$bin/causal_estimator/causal-estimator" "${c[@]}" --idle-exit 4 --max-runtime "$limit" \
  --wait-for alarm-recommender --wait-for causal-recorder > "$work/estimator.log" 2>&1 & est=$!; pids+=($est)
"$bin/sensor_replay/sensor-replay" "${c[@]}" --features "$table" --feature-suffix _meanabs --feature-name meanabs \
  --speed 36000 --wait-for causal-estimator --wait-timeout 60 > "$work/replay.log" 2>&1 & replay=$!; pids+=($replay)
# The other user's tool joins mid-run (its own output folder, its own profile).
mkdir -p "$work/other"; chown "$other" "$work/other"
sleep 5
grep -q "ingest\|snapshot\|sent" "$work/replay.log" || echo "note: replay log so far: $(tail -2 "$work/replay.log")"
runuser -u "$other" -- sh -c 'echo $$ > "$1/other/tool.pid"; exec "$2" --domain "$6" --qos "$3" --transport "$4" --out "$1/other/rec" --idle-exit 6 --max-runtime "$5"' \
  sh "$work" "$bin/causal_recorder/causal-recorder" "$deploy/dds/qos.xml" "$tool_profile" "$limit" "$domain" > "$work/other.log" 2>&1 &
other_job=$!
joined_at=$(date +%s.%N)
echo "$other's causal-recorder joined 5 s into the run"

if [ "$mode" = shm ]; then
  for i in $(seq 1 150); do
    grep -q "HEALTH RAISED .*reader_not_acknowledging" "$work"/estimator.log "$work"/recommender.log && break
    sleep 0.1
  done
  line=$(grep -h "HEALTH RAISED .*reader_not_acknowledging" "$work"/estimator.log "$work"/recommender.log | head -1)
  [ -n "$line" ] || fail "no reader_not_acknowledging alarm within 15 s of the other user's tool joining (estimator: $(tail -3 "$work/estimator.log"))"
  echo "detected $(awk -v a="$joined_at" -v b="$(date +%s.%N)" 'BEGIN { printf "%.1f", b - a }') s after the other user's tool started: ${line:0:600}"
  echo "$line" | grep -q "causal-recorder \[user $other" || fail "the alarm does not name the other user's reader"
  exit 0
fi

for p in "${pids[@]}"; do wait "$p"; echo "exit $? <- pid $p"; done > "$work/exits"
wait "$other_job"; other_rc=$?
pids=()
cat "$work/exits"
! grep -qv "exit 0 " "$work/exits" || fail "a service did not exit 0: $(cat "$work/exits"); estimator: $(grep summary "$work/estimator.log")"
[ "$other_rc" = 0 ] || fail "the other user's recorder exited $other_rc: $(tail -3 "$work/other.log")"
sent=$(sed -n 's/.*summary topic=causal_twin\/condition_input sent=\([0-9]*\).*/\1/p' "$work/replay.log")
got=$(sed -n 's/.*summary topic=causal_twin\/condition_input received=\([0-9]*\).*/\1/p' "$work/estimator.log")
[ "$sent" = 984 ] && [ "$got" = 984 ] || fail "condition inputs: sent=$sent received=$got (want 984 = 984); replay: $(grep -h "summary\|warn" "$work/replay.log" | head -5)"
cond="$work/rec/conditions_ims2-shaft1_meanabs.csv"
rows=$(( $(wc -l < "$cond") - 1 ))
[ "$rows" = 984 ] || fail "recorded condition vectors: $rows (want 984)"
f_sent=$(sed -n 's/.*summary topic=causal_twin\/causal_factors\/condition sent=\([0-9]*\).*/\1/p' "$work/estimator.log")
f_got=$(sed -n 's/.*summary topic=causal_twin\/causal_factors received=\([0-9]*\).*/\1/p' "$work/recommender.log")
[ -n "$f_sent" ] && [ "$f_sent" = "$f_got" ] || fail "factor messages: estimator sent=$f_sent, recommender received=$f_got"
if grep -h "reader_not_acknowledging" "$work"/*.log; then fail "a reader_not_acknowledging alarm on the shipped profile"; fi
other_cond="$work/other/rec/conditions_ims2-shaft1_meanabs.csv"
[ -s "$other_cond" ] || fail "the other user's recorder recorded no condition vector: $(tail -3 "$work/other.log")"
last=$(tail -1 "$other_cond" | cut -d, -f1)
echo "condition inputs sent=$sent received=$got; condition vectors recorded=$rows; factor messages sent=$f_sent received=$f_got"
echo "the other user's recorder: $(( $(wc -l < "$other_cond") - 1 )) condition vectors, the last $last"
echo PASS
