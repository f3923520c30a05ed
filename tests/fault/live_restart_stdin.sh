#!/usr/bin/env bash
# A service killed with SIGKILL mid-stream on a live source that cannot rewind, and restarted 2 s later with the
# same command (same --state-dir): sensor-ingest reads the IMS test-2 snapshots as JSON blocks on stdin
# (tests/fault/plant_day_blocks.awk, 256 samples x 4 bearings per snapshot), one block per snapshot at 10 per
# second, 300 snapshots, through causal-estimator, alarm-recommender and causal-recorder on a private loopback
# domain. The victim (causal-estimator, alarm-recommender or causal-recorder) dies after snapshot 120 while the
# blocks keep coming. Checked, exactly: the recording has all 300 condition vectors, each snapshot index 0..299
# once; every service exits 0; sensor-ingest and the estimator report lost=0. With "beyond" the victim is the
# estimator, killed after snapshot 170 (the recommender's baseline is learned by 140), and sensor-ingest keeps only
# 5 frames (--backlog 5): the frames older than that are lost and must be counted by the estimator (lost=N, HEALTH
# input_lost naming the range, exit 4), the recorder's gap equals it (its lost=, exit 4), and the recommender's
# alarm engine reports the same range as input lost (HEALTH input_lost), never as a recording gap or an operating
# change (no "OPERATING CHANGE", no discontinuity event in the recording).
# Over UDP loopback, the installed hosts' transport (shared memory after SIGKILL: docs/reliability.md "Shared memory and
# SIGKILL"; LIVE_RESTART_TRANSPORT=localhost.xml runs it on shared memory).
#   live_restart_stdin.sh <build/services dir> <deploy dir> <estimator|recommender|recorder|beyond> <domain>
set -uo pipefail
bin="$1"; deploy="$2"; victim="$3"; domain="$4"
. "$(dirname "$0")/../support/live_pipeline.sh"
work="$(mktemp -d)"; logs="$work"; keep="${LIVE_RESTART_KEEP:-0}"
declare -A cmd pid
trap live_cleanup EXIT
fail() { echo "FAIL: $1"; for s in ingest estimator recommender recorder; do echo "--- $s"; grep -h 'summary\|error\|lost\|resen\|RAISED\|continuation' "$work/$s.log" 2>/dev/null | tail -8; done; exit 1; }
total=300; kill_after=120
[ "$victim" = beyond ] && kill_after=170
group=live-restart
live_blocks "$deploy" "$group" 33 "$work/blocks.jsonl" "$total"
[ "$(wc -l < "$work/blocks.jsonl")" = "$total" ] || fail "the generator wrote $(wc -l < "$work/blocks.jsonl") blocks"
backlog=600; [ "$victim" = beyond ] && backlog=5
c="--domain $domain --qos '$deploy/dds/qos.xml' --transport '$deploy/dds/${LIVE_RESTART_TRANSPORT:-localhost-udp.xml}' --max-runtime 120"
mkdir -p "$work/state/estimator" "$work/state/recommender" "$work/state/ingest"
cmd[recorder]="'$bin/causal_recorder/causal-recorder' $c --out '$work/rec'"
cmd[recommender]="'$bin/alarm_recommender/alarm-recommender' $c --state-dir '$work/state/recommender'"
cmd[estimator]="'$bin/causal_estimator/causal-estimator' $c --state-dir '$work/state/estimator' --wait-for alarm-recommender --wait-for causal-recorder --wait-timeout 60"
cmd[ingest]="'$bin/sensor_ingest/sensor-ingest' $c --source - --state-dir '$work/state/ingest' --backlog $backlog --wait-for causal-estimator --wait-timeout 60 < '$work/feed'"
conditions="$work/rec/conditions_${group}_meanabs.csv"

mkfifo "$work/feed"
start recorder; start recommender; start estimator; start ingest
# The DAQ: one block every 100 ms, whatever happens downstream (a live source does not wait).
( exec 3> "$work/feed"
  n=0
  while IFS= read -r line; do
    printf '%s\n' "$line" >&3; n=$(( n + 1 )); echo "$n" > "$work/fed"; sleep 0.1
  done < "$work/blocks.jsonl" ) &
feeder=$!
for i in $(seq 1 600); do fed=$(cat "$work/fed" 2>/dev/null); [ "${fed:-0}" -ge "$kill_after" ] && break; sleep 0.05; done
v=$victim; [ "$v" = beyond ] && v=estimator
kill -KILL "${pid[$v]}"; wait "${pid[$v]}" 2>/dev/null
echo "$v killed (SIGKILL) after snapshot $(cat "$work/fed") of $total was fed"
echo "--- restarted after SIGKILL ---" >> "$work/$v.log"
sleep 2
[ "$victim" = beyond ] && sleep 6  # longer than 5 frames of backlog
start "$v"
wait "$feeder"
wait "${pid[ingest]}"; code=$?
echo "sensor-ingest exit $code: $(grep '^sensor-ingest: received=' "$work/ingest.log" | tail -1)"
if [ "$victim" = beyond ]; then
  for i in $(seq 1 300); do [ -f "$conditions" ] && [ "$(tail -1 "$conditions" | cut -d, -f1)" = $(( total - 1 )) ] && break; sleep 0.1; done
else
  [ "$code" = 0 ] || fail "sensor-ingest exited $code"
  grep -q '^sensor-ingest: received=300 published=300 rejected=0 lost=0' "$work/ingest.log" || fail "sensor-ingest did not publish 300 frames with lost=0"
  for i in $(seq 1 300); do [ "$(rows_of "$conditions")" -ge "$total" ] && break; sleep 0.1; done
fi
sleep 1
for s in estimator recommender recorder; do
  kill -TERM "${pid[$s]}"; wait "${pid[$s]}"; code=$?
  echo "$s exit $code: $(grep -h 'causal-estimator: received\|summary topic=causal_twin/condition_vector\|condition level: resumed' "$work/$s.log" | tail -2 | tr '\n' ' ')"
  # Beyond the backlog: the estimator that missed the input and the recorder whose recording has the gap say so.
  want=0; [ "$victim" = beyond ] && [ "$s" != recommender ] && want=4
  [ "$code" = "$want" ] || fail "$s exited $code (want $want)"
done
rows=$(rows_of "$conditions")
distinct=$(tail -n +2 "$conditions" | cut -d, -f1 | sort -un | wc -l)
echo "recorded $rows condition vectors, $distinct distinct snapshot indices"
if [ "$victim" = beyond ]; then
  lost=$(grep 'causal-estimator: received frames=' "$work/estimator.log" | tail -1 | sed -n 's/.* lost=\([0-9]*\) .*/\1/p')
  grep -q 'HEALTH RAISED live-restart/input/input_lost' "$work/estimator.log" || fail "no input_lost HEALTH alarm"
  grep 'HEALTH RAISED live-restart/input/input_lost' "$work/estimator.log" | tail -1
  [ "$rows" = "$distinct" ] || fail "duplicate rows in the recording"
  [ $(( rows + lost )) = "$total" ] || fail "recorded $rows + estimator lost $lost != $total"
  [ "$lost" -gt 0 ] || fail "nothing lost beyond a 5-frame backlog?"
  grep -q "summary topic=causal_twin/condition_vector file=conditions_${group}_meanabs.csv written=[0-9]* duplicates=[0-9]* lost=$lost " \
    "$work/recorder.log" || fail "the recorder's lost= is not the estimator's $lost"
  echo "beyond the backlog: estimator lost=$lost, recorded $rows: together $total"
  # The alarm engine: the same range, as input the twin lost; nothing about it as a change of the machine.
  range=$(grep 'HEALTH RAISED live-restart/input/input_lost' "$work/estimator.log" | tail -1 | sed -n 's/.*(snapshots \([0-9]*\.\.[0-9]*\);.*/\1/p')
  [ -n "$range" ] || fail "the estimator's input_lost names no range"
  grep -q "HEALTH RAISED live-restart/observations/input_lost/1: $lost observations never reached the alarm engine (observations $range," \
    "$work/recommender.log" || fail "the recommender did not report snapshots $range as input lost: $(grep -h 'HEALTH\|OPERATING' "$work/recommender.log" | head -3)"
  [ "$(grep -c 'HEALTH RAISED live-restart/observations/input_lost' "$work/recommender.log")" = 1 ] || fail "more than one input_lost in the recommender"
  grep -q "summary topic=causal_twin/causal_factors received=[0-9]* rejected=0 lost=$lost\$" "$work/recommender.log" ||
    fail "the recommender's lost= is not $lost: $(grep 'summary topic=causal_twin/causal_factors' "$work/recommender.log")"
  ! grep -q 'OPERATING CHANGE' "$work/recommender.log" || fail "operating change reported: $(grep 'OPERATING CHANGE' "$work/recommender.log" | head -1 | cut -c1-300)"
  [ "$(grep -c '^[^,]*,[^,]*,[^,]*,\(discontinuity\|operating_change\|level_step\),' "$work/rec/alarms.csv")" = 0 ] || fail "operating-change events in the recording"
  [ "$(grep -c '^live-restart/observations/input_lost/1,\(raised\|cleared\),warning,input_lost,' "$work/rec/alarms.csv")" = 2 ] ||
    fail "the recording has not the input_lost event raised and cleared"
  echo "alarm engine: snapshots $range reported as input lost (HEALTH input_lost), no operating change"
else
  [ "$rows" = "$total" ] && [ "$distinct" = "$total" ] || fail "recorded $rows rows ($distinct distinct) of $total"
  [ "$(tail -n +2 "$conditions" | cut -d, -f1 | sort -n | head -1)" = 0 ] || fail "snapshot 0 missing"
  grep 'causal-estimator: received frames=' "$work/estimator.log" | tail -1 | grep -q ' lost=0 ' || fail "estimator lost input"
fi
echo "PASS"
