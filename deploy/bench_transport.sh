#!/usr/bin/env bash
# Same-host transport comparison (docs/cross-user-and-restarts.md): the shipped UDP-loopback profile
# (deploy/dds/localhost-udp.xml, installed as localhost.xml) against shared memory (deploy/dds/localhost.xml), interleaved in one run so
# both see the same machine load. Per profile and round:
#   raw:      causal_bench_raw_dds, 16 groups x 500 frames of 32 KiB (no estimation): frames/s and the CPU
#             seconds of that process (/usr/bin/time: user + system);
#   pipeline: deploy/bench_scale.sh --shards 1 --max-groups 16: end-to-end frames/s (sensor-sim -> estimator ->
#             counter), the IMS-rate live probes at 8 and 16 groups (steady-state p99 frame-to-factor latency),
#             and the CPU seconds of the whole bench (the same work for both profiles when both hold 16 groups).
# Usage: deploy/bench_transport.sh [--build DIR] [--rounds N] [--duration S]
set -u
ROOT=$(cd "$(dirname "$0")/.." && pwd)
BUILD="${BUILD_DIR:-$ROOT/build}"
ROUNDS=1
DURATION=10
. "$ROOT/deploy/bench_options.sh"
parse_options "$0" 2,13 --build=BUILD --rounds=ROUNDS --duration=DURATION -- "$@"
RAW="$BUILD/tests/bench/causal_bench_raw_dds"
[ -x "$RAW" ] && [ -x /usr/bin/time ] || { echo "bench_transport.sh: needs $RAW and /usr/bin/time (package time)" >&2; exit 2; }
WORK=$(mktemp -d /tmp/bench_transport.XXXXXX)
trap 'rm -rf "$WORK"' EXIT
echo "bench_transport: $(date -u +%FT%TZ) on $(nproc) cores, $(uptime | sed 's/.*load average/load average/')"
FAILED=0
for round in $(seq 1 "$ROUNDS"); do
  for profile in localhost-udp.xml localhost.xml; do
    transport="$ROOT/deploy/dds/$profile"
    /usr/bin/time -f "%U %S" -o "$WORK/raw.time" "$RAW" --domain 230 --groups 16 --frames-per-group 500 --channels 4 \
      --frame-samples 1024 --qos "$ROOT/deploy/dds/qos.xml" --transport "$transport" > "$WORK/raw.out" 2>&1 || FAILED=1
    raw_line=$(grep '^raw_dds:' "$WORK/raw.out" | tail -n1)
    raw_cpu=$(awk '{ printf "%.2f", $1 + $2 }' "$WORK/raw.time")
    /usr/bin/time -f "%U %S" -o "$WORK/bench.time" "$ROOT/deploy/bench_scale.sh" --build "$BUILD" --transport "$transport" \
      --shards 1 --max-groups 16 --duration "$DURATION" > "$WORK/bench.out" 2>&1 || FAILED=1
    bench_cpu=$(awk '{ printf "%.2f", $1 + $2 }' "$WORK/bench.time")
    pipeline=$(grep '^pipeline shards=1' "$WORK/bench.out" | sed 's/.*frames_per_s=\([0-9.]*\).*/\1/')
    live=$(grep '^  live shards=1' "$WORK/bench.out" | sed 's/.*groups=\([0-9]*\):.*p99_ms=\([0-9.]*\).*-> \(.*\)/\1 groups p99 \2 ms \3/' | tr '\n' ';')
    echo "round $round $profile: raw [$raw_line] cpu_s=$raw_cpu | pipeline frames_per_s=${pipeline:-?} | live: ${live:-?} | bench cpu_s=$bench_cpu"
    grep -q '^groups_live=' "$WORK/bench.out" || { echo "  bench_scale failed:"; tail -5 "$WORK/bench.out"; }
  done
done
exit "$FAILED"
