#!/usr/bin/env bash
# The plant day with mid-flight kills: a live source that does not wait (the DAQ sends one IMS test-2 snapshot block
# every 100 ms whatever happens downstream), 270 snapshots through sensor-ingest, causal-estimator,
# alarm-recommender and causal-recorder (all with --state-dir/--out), run twice with the same data on a private
# loopback domain: "reference" undisturbed, "faults" with causal-recorder, alarm-recommender, causal-estimator and
# sensor-ingest each killed with SIGKILL while blocks keep coming (after snapshots 50, 100, about 140, 200) and
# restarted with the same command. The estimator is killed 4 s after the recommender, before the dead reader's 5 s
# lease ends: nothing it wrote since is acknowledged and its writers block (64 samples per instance), so its queue
# holds the output of several snapshots; the recommender restarts 0.5 s later, the estimator 2 s after its kill. Over stdin (a FIFO; the DAQ drops what it produces while no ingest reads, as a
# live source does) or MQTT (a real mosquitto broker, QoS 1, --mqtt-keep-session with a fixed client id: the broker
# queues what is published while the ingest is down and redelivers what it has not acknowledged).
# The services use the installed hosts' transport, UDP loopback (deploy/dds/localhost-udp.xml; MIDFLIGHT_TRANSPORT=
# localhost.xml for shared memory): with shared memory a process restarted after SIGKILL takes its predecessor's port,
# and a peer that kept the old segment open can go on writing into the removed one (Fast DDS 2.9; docs/reliability.md
# "Shared memory and SIGKILL").
#   midflight_kills.sh <build/services dir> <deploy dir> <stdin|mqtt> <domain>
# What the design promises (docs/reliability.md "Mid-flight kills"), checked exactly:
#  * the recorder, recommender and estimator kills lose nothing: their input comes again (the recorder and the
#    recommender from the writers' transient-local history and from the estimator's checkpoint, which keeps every
#    condition-level message not yet acknowledged and sends it again; the estimator from sensor-ingest's backlog);
#  * a killed sensor-ingest loses what was inside it (libmosquitto 2.0 acknowledges a QoS 1 message before the
#    program sees it) and, over stdin, what the DAQ sent while it was down: L source blocks, L >= 0 (over stdin
#    L > 0: the DAQ ran on for 2 s). They are counted where they are missed and downstream: the restarted ingest's
#    missed=L, the estimator's lost=L (HEALTH input_lost), the recorder's lost=L, the alarm engine's input_lost naming
#    the same snapshots, and each of them exits 4 when L > 0 (0 otherwise);
#  * every snapshot the ingest took is recorded once: the recorded indices are 0..269 less exactly the L missed, and
#    each recorded condition vector is byte-identical to the reference's row; with L = 0 the conditions and both
#    condition-level factor files are byte-identical files, and the alarm engine's degradation and operating-change
#    events are the reference's.
set -uo pipefail
bin="$1"; deploy="$2"; mode="$3"; domain="$4"
. "$(dirname "$0")/../support/live_pipeline.sh"
work="$(mktemp -d)"; keep="${MIDFLIGHT_KEEP:-0}"
declare -A cmd pid
trap live_cleanup EXIT
fail() {
  echo "FAIL: $1"
  for s in ingest estimator recommender recorder; do
    echo "--- $s"; grep -h 'summary\|error\|lost\|missed\|RAISED\|OPERATING' "$logs/$s.log" 2>/dev/null | tail -6 | cut -c1-300
  done
  exit 1
}
total=270; group=midflight
points=(50 100 200); victims=(recorder recommender ingest)  # the estimator goes with the recommender
live_blocks "$deploy" "$group" 41 "$work/blocks.jsonl" "$total"
[ "$(wc -l < "$work/blocks.jsonl")" = "$total" ] || fail "the generator wrote $(wc -l < "$work/blocks.jsonl") blocks"
if [ "$mode" = mqtt ]; then live_broker "$work" || fail "no mosquitto or mosquitto_pub (deploy/install_deps.sh)"; fi

# The DAQ: block n at t0 + n x 100 ms. Over stdin it writes to the FIFO; a write that fails (no reader: the ingest
# was killed) drops the block, then it waits for the next reader and drops every block that fell due meanwhile.
daq_stdin() {  # $1 = FIFO, $2 = file counting blocks sent
  trap '' PIPE
  local n=0 line t0 now due skip=0
  exec 3> "$1"
  t0=$(date +%s%N)
  while IFS= read -r line; do
    if [ "$skip" -gt 0 ]; then skip=$(( skip - 1 )); n=$(( n + 1 )); continue; fi
    due=$(( t0 + n * 100000000 )); now=$(date +%s%N)
    [ "$now" -lt "$due" ] && sleep "$(printf '0.%09d' $(( due - now )))"
    if ! printf '%s\n' "$line" >&3 2>/dev/null; then
      exec 3>&-
      exec 3> "$1"  # blocks until the restarted ingest opens the FIFO
      now=$(date +%s%N)
      skip=$(( (now - t0) / 100000000 - n ))
      echo "daq: block $n and the $skip due while no ingest read were dropped" >> "$work/daq.log"
    fi
    n=$(( n + 1 )); echo "$n" > "$2"
  done
  exec 3>&-
}
daq_mqtt() {  # $1 = topic, $2 = file counting blocks sent
  local n=0 line t0 now due
  t0=$(date +%s%N)
  while IFS= read -r line; do
    due=$(( t0 + n * 100000000 )); now=$(date +%s%N)
    [ "$now" -lt "$due" ] && sleep "$(printf '0.%09d' $(( due - now )))"
    printf '%s\n' "$line"; n=$(( n + 1 )); echo "$n" > "$2"
  done | mosquitto_pub -h 127.0.0.1 -p "$broker_port" -t "$1" -q 1 -l -i "daq-$run_name"
}

kill_now() {  # $1 = run folder, $2 = service: SIGKILL, and how far the recording was behind the DAQ
  kill -KILL "${pid[$2]}"; wait "${pid[$2]}" 2>/dev/null
  local fed c; fed=$(cat "$1/fed" 2>/dev/null); [ -n "$fed" ] || { sleep 0.02; fed=$(cat "$1/fed"); }
  c=$(tail -1 "$1/rec/conditions_${group}_meanabs.csv" 2>/dev/null | cut -d, -f1)
  echo "$run_name: $2 killed (SIGKILL) after snapshot $(( fed - 1 )) was sent (recorded up to ${c:-none})"
  echo "--- restarted after SIGKILL ---" >> "$1/$2.log"
}

run() {  # $1 = name, $2 = domain, $3 = 1 with kills
  run_name=$1; logs="$work/$1"; local d="$work/$1"
  mkdir -p "$d/state/ingest" "$d/state/estimator" "$d/state/recommender"
  local c="--domain $2 --qos '$deploy/dds/qos.xml' --transport '$deploy/dds/${MIDFLIGHT_TRANSPORT:-localhost-udp.xml}' --max-runtime 100"
  cmd[recorder]="'$bin/causal_recorder/causal-recorder' $c --out '$d/rec'"
  cmd[recommender]="'$bin/alarm_recommender/alarm-recommender' $c --state-dir '$d/state/recommender'"
  cmd[estimator]="'$bin/causal_estimator/causal-estimator' $c --state-dir '$d/state/estimator' --wait-for alarm-recommender --wait-for causal-recorder --wait-timeout 60"
  if [ "$mode" = mqtt ]; then
    cmd[ingest]="'$bin/sensor_ingest/sensor-ingest' $c --source 'mqtt://127.0.0.1:$broker_port/plant/$1/$group' --client-id 'ingest-$1' --mqtt-keep-session --state-dir '$d/state/ingest' --wait-for causal-estimator --wait-timeout 60"
  else
    mkfifo "$d/feed"
    cmd[ingest]="'$bin/sensor_ingest/sensor-ingest' $c --source - --state-dir '$d/state/ingest' --wait-for causal-estimator --wait-timeout 60 < '$d/feed'"
  fi
  start recorder; start recommender; start estimator; start ingest
  if [ "$mode" = mqtt ]; then
    wait_log "$d/ingest.log" "subscribed to" 60 || fail "$1: sensor-ingest did not subscribe"
    daq_mqtt "plant/$1/$group" "$d/fed" < "$work/blocks.jsonl" &
  else
    daq_stdin "$d/feed" "$d/fed" < "$work/blocks.jsonl" &
  fi
  local daq=$! i i2 k v fed
  if [ "$3" = 1 ]; then
    for i in "${!points[@]}"; do
      k=${points[$i]}; v=${victims[$i]}
      for i2 in $(seq 1 1200); do fed=$(cat "$d/fed" 2>/dev/null); [ "${fed:-0}" -gt "$k" ] 2>/dev/null && break; sleep 0.05; done
      kill_now "$d" "$v"
      if [ "$v" = recommender ]; then
        sleep 4; kill_now "$d" estimator; sleep 0.5; start recommender; sleep 1.5; start estimator
        continue
      fi
      sleep 2
      start "$v"
    done
  fi
  wait "$daq"
  if [ "$mode" = stdin ]; then wait "${pid[ingest]}"; ingest_code=$?; fi  # the end of its input ends it
  # Everything the ingest took is through once the recorder has the last snapshot and then stays quiet.
  local conditions="$d/rec/conditions_${group}_meanabs.csv"
  for i in $(seq 1 300); do [ "$(tail -1 "$conditions" 2>/dev/null | cut -d, -f1)" = $(( total - 1 )) ] && break; sleep 0.1; done
  sleep 2
  if [ "$mode" = mqtt ]; then kill -TERM "${pid[ingest]}"; wait "${pid[ingest]}"; ingest_code=$?; fi
  echo "$1: sensor-ingest exit $ingest_code: $(grep '^sensor-ingest: received=' "$d/ingest.log" | tail -1 | cut -c1-160)"
  for s in estimator recommender recorder; do
    kill -TERM "${pid[$s]}"; wait "${pid[$s]}"; codes[$s]=$?
  done
  codes[ingest]=$ingest_code
}

declare -A codes
run reference "$domain" 0
for s in ingest estimator recommender recorder; do [ "${codes[$s]}" = 0 ] || fail "reference: $s exited ${codes[$s]}"; done
ref="$work/reference/rec"
[ "$(rows_of "$ref/conditions_${group}_meanabs.csv")" = "$total" ] || fail "reference: $(rows_of "$ref/conditions_${group}_meanabs.csv") of $total recorded"
run faults "$domain" 1
f="$work/faults"
missed=$(sed -n 's/^sensor-ingest: .* missed=\([0-9]*\)$/\1/p' "$f/ingest.log" | tail -1)
est_lost=$(grep 'causal-estimator: received frames=' "$f/estimator.log" | tail -1 | sed -n 's/.* lost=\([0-9]*\) .*/\1/p')
rec_lost=$(sed -n "s/.*file=conditions_${group}_meanabs.csv written=[0-9]* duplicates=[0-9]* lost=\([0-9]*\) .*/\1/p" "$f/recorder.log" | tail -1)
echo "faults: sensor-ingest missed=${missed:-?} (the restarted one), estimator lost=${est_lost:-?}, recorder lost=${rec_lost:-?};" \
     "exits ingest ${codes[ingest]} estimator ${codes[estimator]} recommender ${codes[recommender]} recorder ${codes[recorder]}"
[ -n "$missed" ] && [ -n "$est_lost" ] && [ -n "$rec_lost" ] || fail "a summary line is missing"
[ "$mode" = mqtt ] || [ "$missed" -gt 0 ] || fail "over stdin the DAQ ran on while the ingest was down: missed=0?"
# The estimator and the recorder count the same gap. The ingest counts the blocks it never took; the frames the
# killed ingest had numbered (its state is written first) but not delivered are lost too: their numbers stay unused,
# so the estimator counts them, the restarted ingest cannot know them.
[ "$est_lost" = "$rec_lost" ] || fail "lost counts differ: estimator $est_lost, recorder $rec_lost"
[ "$est_lost" -ge "$missed" ] || fail "lost counts differ: ingest missed $missed, estimator $est_lost"
missed=$est_lost
want=0; [ "$missed" -gt 0 ] && want=4
for s in estimator recorder; do [ "${codes[$s]}" = "$want" ] || fail "$s exited ${codes[$s]} (want $want)"; done
[ "${codes[ingest]}" = "$([ "$(sed -n 's/^sensor-ingest: .* missed=\([0-9]*\)$/\1/p' "$f/ingest.log" | tail -1)" -gt 0 ] && echo 4 || echo 0)" ] ||
  fail "sensor-ingest exited ${codes[ingest]}"
[ "${codes[recommender]}" = 0 ] || fail "recommender exited ${codes[recommender]}"
# The case under test: the killed estimator's output was not caught up. Its restart sends again what its checkpoint
# kept, the output of more than one snapshot (one snapshot makes a condition vector and at most two factor batches).
resent=$(sed -n 's/.*: \([0-9]*\) condition-level output messages the readers had not acknowledged.*/\1/p' "$f/estimator.log" | tail -1)
echo "faults: the restarted estimator sent ${resent:-0} unacknowledged condition-level messages again"
[ "${resent:-0}" -gt 3 ] || fail "the estimator was killed with its output caught up (${resent:-0} messages resent)"

# The condition-level smoother's lag (the second fixed_lag in estimator.yaml): its estimate of snapshot n uses n+lag.
lag=$(grep 'fixed_lag:' "$deploy/config/estimator.yaml" | sed -n 2p | awk '{print $2}')
python3 - "$ref" "$f/rec" "$group" "$total" "$missed" "$f/recommender.log" "$lag" <<'EOF' || fail "the recording differs from what the design promises"
import csv, re, sys
ref, got, group, total, missed, rec_log, lag = sys.argv[1], sys.argv[2], sys.argv[3], int(sys.argv[4]), int(sys.argv[5]), sys.argv[6], int(sys.argv[7])
def rows(path):
    with open(path, newline="") as f:
        return list(csv.reader(f))
name = "conditions_%s_meanabs.csv" % group
r, g = rows("%s/%s" % (ref, name)), rows("%s/%s" % (got, name))
assert r[0] == g[0], "headers differ"
by_index = {row[0]: row for row in r[1:]}
indices = [row[0] for row in g[1:]]
assert len(indices) == len(set(indices)), "a snapshot recorded twice"
gone = sorted(set(by_index) - set(indices), key=int)
assert len(gone) == missed, "%d snapshots missing from the recording, the ingest missed %d" % (len(gone), missed)
for row in g[1:]:
    assert row == by_index[row[0]], "snapshot %s differs: %s vs %s" % (row[0], row[:4], by_index[row[0]][:4])
if gone:
    first, last = int(gone[0]), int(gone[-1])
    assert last - first + 1 == missed, "the missing snapshots are not one range: %s" % gone
    text = open(rec_log).read()
    want = "observations %d..%d," % (first, last) if first != last else "observation %d," % first
    assert re.search(r"HEALTH RAISED %s/observations/input_lost/\d+: %d observations? never reached the alarm engine \(%s" % (re.escape(group), missed, re.escape(want)), text), \
        "the alarm engine did not report snapshots %d..%d as input lost" % (first, last)
    print("missed snapshots %d..%d: counted by the ingest, the estimator, the recorder and the alarm engine" % (first, last))
    # Before the missed range the factors are the reference's, row for row (the estimator's kill lost none); the
    # smoothed ones up to the lag before it (those after saw the gap).
    for f, end in (("factors_%s_condition_filter.csv" % group, first), ("factors_%s_condition_fixed-lag.csv" % group, first - lag)):
        before = lambda t: [row for row in t[1:] if int(row[0]) < end]
        a, b = before(rows("%s/%s" % (ref, f))), before(rows("%s/%s" % (got, f)))
        assert len(a) == end and a == b, "%s: %d rows before snapshot %d, the reference has %d (first difference at %s)" % (
            f, len(b), end, len(a), next((x[0] for x, y in zip(a, b) if x != y), "the end"))
        print("%s: the %d rows before snapshot %d equal to the reference" % (f, len(a), end))
else:
    for f in (name, "factors_%s_condition_filter.csv" % group, "factors_%s_condition_fixed-lag.csv" % group):
        assert open("%s/%s" % (ref, f), "rb").read() == open("%s/%s" % (got, f), "rb").read(), "%s differs" % f
    print("conditions and both condition-level factor files byte-identical to the reference")
# The alarm engine's judgement of the machine: degradation and operating-change events (condition level).
def machine(path):
    out = []
    for row in rows(path)[1:]:
        if row[16] in ("degradation", "operating_change") and "/sample/" not in row[0] and not row[0].startswith("causal-estimator/"):
            out.append(tuple(row[:16]))
    return sorted(out)
a, b = machine(ref + "/alarms.csv"), machine(got + "/alarms.csv")
for row in b:
    assert not (row[3] == "discontinuity"), "a recording gap reported as an operating change: %s" % (row,)
if missed == 0:
    assert a == b, "alarm events differ: %s" % (sorted(set(a) ^ set(b))[:3],)
    print("%d condition-level machine events equal to the reference" % len(a))
print("recorded %d of %d snapshots" % (len(indices), total))
EOF
echo PASS
