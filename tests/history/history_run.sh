#!/usr/bin/env bash
# The historian end to end, on the IMS test-2 feature table (984 snapshots), real services and real databases:
#  1. deploy/launch.sh --record R leaves R/history.db with every row of R's CSV files (same counts per table);
#  2. twin-web --db sqlite:R/history.db alone (no publisher on its domain) serves all 984 points and every alarm;
#  3. the same run with --db on a PostgreSQL 15 server this test starts stores the same rows (skipped without
#     PostgreSQL 15; a failure where CAUSAL_TWIN_REQUIRE_ALL=1);
#  4. causal-recorder killed with SIGKILL mid-run and started again at once: the database still holds every
#     condition vector and factor row exactly once (it resumes from the durable topics; the keys drop repeats).
# Usage: history_run.sh BUILD_DIR DEPLOY_DIR TESTS_DIR. Fixed DDS domains 70..73.
set -euo pipefail
build="$1"; deploy="$2"; tests="$3"
export CAUSAL_TWIN_BUILD_DIR="$build"
table="$deploy/data/ims2-features/derived_per_file_stats_all984.csv"
group=ims2-shaft1
work="$(mktemp -d /tmp/causal-history-run.XXXXXX)"
pg_dir="$work-pg"
pids=()
cleanup() {
  for p in "${pids[@]}"; do kill "$p" 2> /dev/null || true; done
  "$tests/support/postgres_server.sh" stop "$pg_dir" > /dev/null 2>&1 || true
  rm -rf "$work"
}
trap cleanup EXIT
if [ -n "${CAUSAL_HISTORY_KEEP:-}" ]; then  # keep the folders for a look (the server is stopped)
  trap '"$tests/support/postgres_server.sh" stop "$pg_dir" > /dev/null 2>&1 || true; echo "kept $work"' EXIT
fi
fail=0
check() {  # check NAME EXPECTED ACTUAL
  if [ "$2" = "$3" ]; then echo "ok   $1: $3"; else echo "FAIL $1: expected $2, got $3"; fail=1; fi
}
csv_rows() { python3 -c 'import csv,sys; print(sum(1 for _ in csv.reader(open(sys.argv[1]))) - 1)' "$1"; }
sq() { sqlite3 "$1" "$2"; }
launch() {  # launch DOMAIN RECORD [--db URL]
  local domain="$1" rec="$2"; shift 2
  "$deploy/launch.sh" --domain "$domain" --features "$table" --feature-suffix _meanabs --feature-name meanabs \
    --record "$rec" --max-runtime 300 "$@" > "$rec.log" 2>&1 || { echo "launch.sh failed:"; tail -30 "$rec.log"; exit 1; }
}
# Table -> CSV file(s) of the recording: rows of the database table = data rows of those files.
declare -A csv_of=([condition_vectors]="conditions_${group}_meanabs.csv"
  [factors]="factors_${group}_condition_filter.csv factors_${group}_condition_fixed-lag.csv"
  [alarms]=alarms.csv [recommendations]=recommendations.csv [prognoses]=prognosis.csv [asset_status]=asset_status.csv)
csv_count() {
  local n=0
  for f in ${csv_of[$2]}; do n=$(( n + $(csv_rows "$1/$f") )); done
  echo "$n"
}

echo "== 1. launch.sh --record: R/history.db"
launch 70 "$work/R"
for t in "${!csv_of[@]}"; do check "sqlite $t" "$(csv_count "$work/R" "$t")" "$(sq "$work/R/history.db" "SELECT COUNT(*) FROM $t")"; done
check "condition vectors of the run" 984 "$(sq "$work/R/history.db" "SELECT COUNT(DISTINCT snapshot) FROM condition_vectors")"
check "journal" wal "$(sq "$work/R/history.db" "PRAGMA journal_mode")"

echo "== 2. twin-web --db alone"
port=$(python3 -c 'import socket; s=socket.socket(); s.bind(("127.0.0.1",0)); print(s.getsockname()[1])')
"$build/services/twin_web/twin-web" --domain 71 --transport "$deploy/dds/localhost.xml" --port "$port" \
  --db "sqlite:$work/R/history.db" --max-runtime 60 > "$work/web.log" 2>&1 &
pids+=($!)
for _ in $(seq 100); do grep -q "serving http" "$work/web.log" && break; sleep 0.2; done
curl -sf "http://127.0.0.1:$port/api/state?group=$group" > "$work/state.json"
curl -sf "http://127.0.0.1:$port/?group=$group" > "$work/page.html"
curl -sf "http://127.0.0.1:$port/api/history?group=$group&from=2004-02-15T00:00:00Z&to=2004-02-15T23:59:59Z" > "$work/range.json"
kill "${pids[-1]}"; wait "${pids[-1]}" || true; unset 'pids[-1]'
alarm_ids=$(python3 -c 'import csv,sys; print(len({r["alarm_id"] for r in csv.DictReader(open(sys.argv[1]))}))' "$work/R/alarms.csv")
read -r points alarms since < <(python3 -c 'import json,sys; s=json.load(open(sys.argv[1])); g=s["group"]
print(len(g["trend"]["index"]), len(g["alarms"]), "yes" if s["overview"]["info"].get("data_since","").startswith("history since") else "no")' "$work/state.json")
check "points on the page" 984 "$points"
check "alarms on the page" "$alarm_ids" "$alarms"
check "the page says since when" yes "$since"
check "the page carries the history in its first response" 1 "$(grep -c '"time_ms":\[1076581959000' "$work/page.html" || true)"
in_day=$(sq "$work/R/history.db" "SELECT COUNT(*) FROM condition_vectors WHERE time_utc BETWEEN '2004-02-15' AND '2004-02-15 23:59:59'")
check "/api/history one day" "$in_day" "$(python3 -c 'import json,sys; print(len(json.load(open(sys.argv[1]))["group"]["trend"]["index"]))' "$work/range.json")"

# The alarm events of a run, one line each (compared between runs and databases).
q="SELECT alarm_id || ' ' || state || ' ' || severity || ' ' || sample_index FROM alarms ORDER BY 1"

echo "== 3. PostgreSQL"
set +e
url="$("$tests/support/postgres_server.sh" start "$pg_dir")"
pg_status=$?
set -e
if [ "$pg_status" = 77 ]; then
  if [ -n "${CAUSAL_TWIN_REQUIRE_ALL:-}" ]; then echo "FAIL no PostgreSQL 15 (required)"; fail=1; else echo "skip: no PostgreSQL 15"; fi
elif [ "$pg_status" != 0 ]; then
  echo "FAIL PostgreSQL did not start"; fail=1
else
  launch 72 "$work/P" --db "$url"
  for t in "${!csv_of[@]}"; do
    n=$(psql -qtAX "$url" -c "SELECT COUNT(*) FROM $t")
    check "postgresql $t" "$(sq "$work/R/history.db" "SELECT COUNT(*) FROM $t")" "$n"
  done
  # The same rows, not only as many: the alarm events of both runs.
  check "postgresql alarm events equal sqlite's" "$(sq "$work/R/history.db" "$q" | md5sum)" "$(psql -qtAX "$url" -c "$q" | md5sum)"
fi

echo "== 4. kill -9 of causal-recorder mid-run"
K="$work/K"; mkdir -p "$K"
svc() { echo "$build/services/$1/$2"; }
common=(--domain 73 --transport "$deploy/dds/localhost.xml")
rec_cmd=("$(svc causal_recorder causal-recorder)" "${common[@]}" --out "$K/rec" --db "sqlite:$K/history.db" --idle-exit 8 --max-runtime 250)
"${rec_cmd[@]}" > "$K/recorder1.log" 2>&1 & rec=$!; pids+=($rec)
"$(svc alarm_recommender alarm-recommender)" "${common[@]}" --state-dir "$K/alarm_state" --idle-exit 5 --max-runtime 250 > "$K/recommender.log" 2>&1 & pids+=($!)
"$(svc causal_estimator causal-estimator)" "${common[@]}" --state-dir "$K/estimator_state" --idle-exit 4 --max-runtime 250 \
  --wait-for alarm-recommender causal-recorder --wait-timeout 60 > "$K/estimator.log" 2>&1 & est=$!; pids+=($est)
"$(svc sensor_replay sensor-replay)" "${common[@]}" --features "$table" --feature-suffix _meanabs --feature-name meanabs \
  --channel-names bearing1 bearing2 bearing3 bearing4 --asset-group "$group" --speed 15000 \
  --wait-for causal-estimator --wait-timeout 60 > "$K/replay.log" 2>&1 & replay=$!; pids+=($replay)
stored=0
for _ in $(seq 600); do
  stored=$(sq "$K/history.db" "SELECT COUNT(*) FROM condition_vectors" 2> /dev/null || echo 0)
  [ "$stored" -ge 400 ] && break
  sleep 0.1
done
echo "kill -9 causal-recorder at $stored stored condition vectors"
kill -9 "$rec"; wait "$rec" 2> /dev/null || true
"${rec_cmd[@]}" > "$K/recorder2.log" 2>&1 & rec=$!; pids+=($rec)
wait "$replay" || { echo "FAIL sensor-replay"; fail=1; }
wait "$est" || { echo "FAIL causal-estimator"; tail -5 "$K/estimator.log"; fail=1; }
wait "$rec" || true  # its CSV files lost the killed process's tail; the database is what is checked
check "killed: condition vectors" 984 "$(sq "$K/history.db" "SELECT COUNT(*) FROM condition_vectors")"
check "killed: snapshots 0..983" "0 983" "$(sq "$K/history.db" "SELECT MIN(snapshot) || ' ' || MAX(snapshot) FROM condition_vectors")"
check "killed: factor rows" 1968 "$(sq "$K/history.db" "SELECT COUNT(*) FROM factors")"
fq="SELECT * FROM factors ORDER BY asset_group, time_scale, kind, sample_index"
check "killed: factor rows equal the undisturbed run's" "$(sq "$work/R/history.db" "$fq" | md5sum)" "$(sq "$K/history.db" "$fq" | md5sum)"
grep -h "resuming after it" "$K/recorder2.log" | sed 's/^/     /' || { echo "FAIL the restarted recorder did not say where it resumed"; fail=1; }
# The machine's alarms; the twin's own health alarms differ by design (the estimator may report the dead reader).
mq="SELECT alarm_id || ' ' || state || ' ' || severity || ' ' || sample_index FROM alarms WHERE category <> 'health' ORDER BY 1"
check "killed: alarm events equal the undisturbed run's" \
  "$(sq "$work/R/history.db" "$mq" | md5sum)" "$(sq "$K/history.db" "$mq" | md5sum)"
exit "$fail"
