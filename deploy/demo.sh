#!/usr/bin/env bash
# The main job on a fresh machine: install dependencies, build, then run the three services over a private
# loopback DDS domain on the embedded IMS test-2 data, in two parts:
#   1. the raw slice (3 healthy + 3 failing 20 kHz snapshots): sample-level factors and alarms;
#   2. the per-snapshot mean |x| of all 984 snapshots (7 days): condition-level factors, early alarms with
#      their root cause, recommendations, and one what-if question to the live twin (causal-ask: a sustained
#      -10 % on bearing 3); recorded to out/demo (CSV) with a PNG report in out/demo/report.
# Arguments are passed to both parts (see deploy/launch.sh --help).
set -euo pipefail
root="$(cd "$(dirname "$0")/.." && pwd)"
"$root/deploy/install_deps.sh"
"$root/deploy/build.sh"
echo "=== part 1: raw vibration snapshots (sample level) ==="
"$root/deploy/launch.sh" --ims-dir "$root/deploy/data/ims2-slice" "$@"
echo "=== part 2: condition features of the whole 7-day run (condition level) ==="
rm -rf "$root/out/demo"
"$root/deploy/launch.sh" --features "$root/deploy/data/ims2-features/derived_per_file_stats_all984.csv" \
  --feature-suffix _meanabs --feature-name meanabs --record "$root/out/demo" --ask 3:-10 "$@"
echo "=== done: CSV recording and PNG report in out/demo ==="
