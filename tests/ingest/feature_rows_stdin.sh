#!/usr/bin/env bash
# Ready-made condition features through sensor-ingest (services/sensor_ingest/feature_row.hpp): the first 100 rows of
# the IMS test-2 feature table (mean |x| of 4 bearings) as feature rows on stdin, even rows JSON, odd rows CSV, with 4
# bad ones mixed in (a repeated sequence, 3 values for 4 channels, a row that is no JSON, a row whose time goes back).
# Checked, exactly: sensor-ingest published 100 feature rows and rejected duplicate=1 shape=1 malformed=1
# out_of_order=1 (exit 4, as for raw blocks); causal-estimator took 100 condition inputs (lost=0, exit 0); the recorder
# has 100 condition vectors, snapshots 0..99, whose values are the table's.
#   feature_rows_stdin.sh <build/services dir> <deploy dir> <domain>
set -uo pipefail
bin="$1"; deploy="$2"; domain="$3"
work="$(mktemp -d)"
cleanup() {
  local live; live=$(jobs -pr)
  [ -n "$live" ] && kill -TERM $live 2>/dev/null && sleep 1
  live=$(jobs -pr); [ -n "$live" ] && kill -KILL $live 2>/dev/null
  wait 2>/dev/null; rm -rf "$work"
}
trap cleanup EXIT
fail() { echo "FAIL: $1"; tail -5 "$work"/*.log; exit 1; }
TZ=UTC awk -F, 'NR == 1 { for (i = 1; i <= NF; ++i) col[$i] = i; next }
  NR > 101 { exit }
  { split($2, d, /[- :]/); t = sprintf("%d%09d", mktime(d[1] " " d[2] " " d[3] " " d[4] " " d[5] " " d[6]), 0) }
  { s = NR - 2; v = $(col["bearing1_meanabs"]) "," $(col["bearing2_meanabs"]) "," $(col["bearing3_meanabs"]) "," $(col["bearing4_meanabs"])
    if (s % 2 == 0) printf "{\"asset_group\":\"features\",\"feature\":\"meanabs\",\"channels\":[\"bearing1\",\"bearing2\",\"bearing3\",\"bearing4\"],\"time_ns\":%s,\"sequence\":%d,\"values\":[%s]}\n", t, s, v
    else printf "#features asset_group=features feature=meanabs channels=bearing1,bearing2,bearing3,bearing4 time_ns=%s sequence=%d values=%s\n", t, s, v
    if (s == 10) { printf "#features asset_group=features feature=meanabs channels=bearing1,bearing2,bearing3,bearing4 time_ns=%s sequence=%d values=%s\n", t, s, v
                   printf "{\"asset_group\":\"features\",\"feature\":\"meanabs\",\"channels\":[\"bearing1\",\"bearing2\",\"bearing3\",\"bearing4\"],\"time_ns\":%s,\"sequence\":99999,\"values\":[1,2,3]}\n", t
                   printf "{\"asset_group\":\"features\",\"values\":[1,2,3,4]\n"
                   printf "#features asset_group=features feature=meanabs channels=bearing1,bearing2,bearing3,bearing4 time_ns=1 sequence=99998 values=1,2,3,4\n" } }' \
  "$deploy/data/ims2-features/derived_per_file_stats_all984.csv" > "$work/rows.txt"
[ "$(wc -l < "$work/rows.txt")" = 104 ] || fail "the generator wrote $(wc -l < "$work/rows.txt") rows"
c="--domain $domain --qos $deploy/dds/qos.xml --transport $deploy/dds/localhost.xml --max-runtime 60"
"$bin/causal_recorder/causal-recorder" $c --out "$work/rec" > "$work/recorder.log" 2>&1 & rec=$!
"$bin/causal_estimator/causal-estimator" $c --wait-for causal-recorder > "$work/estimator.log" 2>&1 & est=$!
"$bin/sensor_ingest/sensor-ingest" $c --source - --wait-for causal-estimator < "$work/rows.txt" > "$work/ingest.log" 2>&1
code=$?
summary=$(grep '^sensor-ingest: received=' "$work/ingest.log")
echo "sensor-ingest exit $code: $summary"
[ "$code" = 4 ] || fail "sensor-ingest exited $code (want 4: rows were rejected)"
for want in received=104 published=100 rejected=4 lost=0 feature_rows=100 malformed=1 shape=1 duplicate=1 out_of_order=1; do
  grep -q " $want\b" <<< " $summary" || fail "sensor-ingest: want $want"
done
file="$work/rec/conditions_features_meanabs.csv"
for i in $(seq 1 100); do [ -f "$file" ] && [ "$(( $(wc -l < "$file") - 1 ))" -ge 100 ] && break; sleep 0.1; done
sleep 1
kill -TERM "$est"; wait "$est"; ecode=$?
kill -TERM "$rec"; wait "$rec"; rcode=$?
echo "estimator exit $ecode: $(grep 'summary topic=causal_twin/condition_input' "$work/estimator.log" | cut -d' ' -f4-)"
[ "$ecode" = 0 ] || fail "estimator exited $ecode"
[ "$rcode" = 0 ] || fail "recorder exited $rcode"
grep -q 'summary topic=causal_twin/condition_input received=100 refused=0 lost=0' "$work/estimator.log" || fail "estimator did not take 100 inputs"
rows=$(( $(wc -l < "$file") - 1 ))
[ "$rows" = 100 ] || fail "recorded $rows condition vectors (want 100)"
[ "$(tail -n +2 "$file" | cut -d, -f1 | sort -n | uniq | tr '\n' ' ')" = "$(seq 0 99 | tr '\n' ' ')" ] || fail "snapshots not 0..99 once each"
# The values are the table's (row 7: snapshot 7, bearing3 = column 6 of the recording).
want=$(awk -F, 'NR == 9 { print $15 }' "$deploy/data/ims2-features/derived_per_file_stats_all984.csv")
got=$(awk -F, '$1 == 7 { print $6 }' "$file")
awk -v a="$want" -v b="$got" 'BEGIN { exit !(a + 0 == b + 0) }' || fail "snapshot 7 bearing3: recorded $got, table $want"
echo "PASS: 100 feature rows recorded as condition vectors 0..99 (bearing3 of snapshot 7: $got), 4 bad rows rejected by reason"
