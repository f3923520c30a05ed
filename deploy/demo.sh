#!/usr/bin/env bash
# The main job on a fresh machine: install dependencies, build, then run the three services over a private
# loopback DDS domain on the embedded IMS test-2 data, in two parts:
#   1. the raw slice (3 healthy + 3 failing 20 kHz snapshots): sample-level factors, its alarms as one summary;
#   2. the per-snapshot mean |x| of all 984 snapshots (7 days): condition-level factors, early alarms with
#      their root cause, recommendations, and one what-if question to the live twin (causal-ask: a sustained
#      -10 % on bearing 3); recorded to out/demo (CSV, and the history database out/demo/history.db:
#      docs/historian.md) with a PNG report in out/demo/report.
# While each part runs, the live view (twin-web) is at the address printed as "live view: http://...": the
# first free port from 8080 (--web-port P to choose; --no-web to leave it out).
#   deploy/demo.sh [--web-port P | --no-web] [launch.sh options...]     deploy/demo.sh --help
# Other arguments are passed to both parts (see deploy/launch.sh --help). Installs packages only when some are
# missing (deploy/install_deps.sh, needs root or sudo); the first build takes about 15 minutes on 2 cores.
set -euo pipefail
root="$(cd "$(dirname "$0")/.." && pwd)"
web_port=""
web=1
launch_args=()
while [ $# -gt 0 ]; do
  case "$1" in
    -h|--help) sed -n '2,12p' "$0" | sed 's/^# \{0,1\}//'; exit 0 ;;
    --web-port) web_port="$2"; shift 2 ;;
    --no-web) web=0; shift ;;
    *) launch_args+=("$1"); shift ;;
  esac
done
"$root/deploy/install_deps.sh"
"$root/deploy/build.sh"
web_args=()
if [ "$web" = 1 ]; then
  if [ -z "$web_port" ]; then
    # The first port from 8080 nobody listens on (bash's /dev/tcp: a refused connection means free).
    for p in $(seq 8080 8099); do
      if ! (exec 3<> "/dev/tcp/127.0.0.1/$p") 2>/dev/null; then web_port=$p; break; fi
    done
  fi
  if [ -n "$web_port" ]; then
    web_args=(--web-port "$web_port")
    echo "live view: http://127.0.0.1:$web_port/ (open it in a browser while the demo runs)"
  else
    echo "demo: no free port in 8080..8099: running without the live view" >&2
  fi
fi
echo "=== part 1: raw vibration snapshots (sample level) ==="
"$root/deploy/launch.sh" --ims-dir "$root/deploy/data/ims2-slice" --alarm-summary "${web_args[@]}" "${launch_args[@]}"
echo "=== part 2: condition features of the whole 7-day run (condition level) ==="
[ ${#web_args[@]} -gt 0 ] && echo "live view: http://127.0.0.1:$web_port/ (part 2)"
rm -rf "$root/out/demo"
"$root/deploy/launch.sh" --features "$root/deploy/data/ims2-features/derived_per_file_stats_all984.csv" \
  --feature-suffix _meanabs --feature-name meanabs --record "$root/out/demo" --ask 3:-10 "${web_args[@]}" "${launch_args[@]}"
echo "=== done: CSV recording, history database (out/demo/history.db) and PNG report in out/demo ==="
