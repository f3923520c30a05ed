#!/usr/bin/env bash
# Starts the three services on one DDS domain, replays a data set through them, and stops them all.
#   deploy/launch.sh [--domain N] [--ims-dir DIR | --features FILE [--feature-suffix S --feature-name F]]
#                    [--speed X] [--transport XML] [--record DIR] [--max-runtime S]
#                    [--asset-group ID] [--ask CHANNEL:PERCENT]...
# Defaults: a private domain between 100 and 199, the embedded IMS slice, as fast as possible, loopback only.
# --record DIR also runs causal-recorder (CSV per topic) and renders the PNG report into DIR/report.
# --ask 2:-10 asks the live twin (causal-ask) after the replay: a sustained -10 % on channel 2 of the asset group.
# Every process is ended by its pid (only those started here); the run is bounded by --max-runtime.
set -euo pipefail
root="$(cd "$(dirname "$0")/.." && pwd)"
bin="${CAUSAL_TWIN_BUILD_DIR:-$root/build}/services"
domain=$(( 100 + $$ % 100 ))
source_args=(--ims-dir "$root/deploy/data/ims2-slice")
speed=0
transport="$root/deploy/dds/localhost.xml"
max_runtime=900
record=""
feature_args=()
asset_group="ims2-shaft1"
asks=()
while [ $# -gt 0 ]; do
  case "$1" in
    --domain) domain="$2"; shift 2 ;;
    --ims-dir) source_args=(--ims-dir "$2"); shift 2 ;;
    --features) source_args=(--features "$2"); shift 2 ;;
    --feature-suffix) feature_args+=(--feature-suffix "$2"); shift 2 ;;
    --feature-name) feature_args+=(--feature-name "$2"); shift 2 ;;
    --speed) speed="$2"; shift 2 ;;
    --transport) transport="$2"; shift 2 ;;
    --max-runtime) max_runtime="$2"; shift 2 ;;
    --record) record="$2"; shift 2 ;;
    --asset-group) asset_group="$2"; shift 2 ;;
    --ask) asks+=("$2"); shift 2 ;;
    -h|--help) sed -n '2,10p' "$0"; exit 0 ;;
    *) echo "launch.sh: unknown option $1 (see --help)" >&2; exit 2 ;;
  esac
done
common=(--domain "$domain" --dds-transport "$transport")
pids=()
stop_all() {
  for p in "${pids[@]}"; do kill -TERM "$p" 2>/dev/null || true; done
  for p in "${pids[@]}"; do wait "$p" 2>/dev/null || true; done
  command -v fastdds >/dev/null && fastdds shm clean >/dev/null 2>&1 || true
}
trap stop_all EXIT INT TERM

echo "launch: DDS domain $domain, transport $(basename "$transport")"
subscribers=1
if [ -x "$bin/causal_recorder/causal-recorder" ] && [ -n "$record" ]; then
  "$bin/causal_recorder/causal-recorder" "${common[@]}" --out "$record" --idle-exit 6 --max-runtime "$max_runtime" &
  pids+=($!)
  subscribers=2
fi
# With questions to ask, the recommender stays up a little longer after its sources are gone.
recommender_idle=5
[ ${#asks[@]} -gt 0 ] && recommender_idle=12
"$bin/alarm_recommender/alarm-recommender" "${common[@]}" --idle-exit "$recommender_idle" --max-runtime "$max_runtime" &
pids+=($!)
"$bin/causal_estimator/causal-estimator" "${common[@]}" --idle-exit 4 --max-runtime "$max_runtime" \
  --wait-subscribers "$subscribers" &
estimator_pid=$!
pids+=($estimator_pid)
"$bin/sensor_replay/sensor-replay" "${common[@]}" "${source_args[@]}" --speed "$speed" --wait-subscribers 1 \
  "${feature_args[@]}" --wait-timeout 60 --asset-group "$asset_group"
status=0
if [ ${#asks[@]} -gt 0 ]; then
  # Ask the final model: once the estimator has published everything and left, the recommender holds the
  # model of the last snapshot for recommender_idle seconds.
  wait "$estimator_pid" || status=$?
  remaining=()
  for p in "${pids[@]}"; do [ "$p" != "$estimator_pid" ] && remaining+=("$p"); done
  pids=("${remaining[@]}")
  for q in "${asks[@]}"; do
    echo "launch: asking the twin: sustained ${q#*:} % on channel ${q%%:*} of $asset_group"
    "$bin/whatif_ask/causal-ask" "${common[@]}" --asset-group "$asset_group" --intervene "${q%%:*}" \
      --percent "${q#*:}" --timeout 5 || echo "launch: causal-ask exit code $? (see above)"
  done
fi
# The replay has finished; the others drain their queues and exit when idle.
for p in "${pids[@]}"; do wait "$p" || status=$?; done
pids=()
if [ -n "$record" ] && [ -x "$bin/causal_report/causal-report" ]; then
  "$bin/causal_report/causal-report" --run "$record" --out "$record/report" || status=$?
fi
exit $status
