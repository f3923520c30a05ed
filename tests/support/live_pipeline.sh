# Shared set-up of the live-path fault tests (tests/fault/plant_day.sh, live_restart_stdin.sh, midflight_kills.sh).
# Sourced, not run. The caller declares `declare -A cmd pid`, sets $work (a temporary folder) and $logs (where the
# services' logs go), and installs `trap live_cleanup EXIT`; $keep (1 = keep $work) and $on_exit (a command run before
# the folder goes) are optional.

# Ends only this shell's jobs still running (a pid that has exited may belong to another process by now), then runs
# $on_exit and removes $work.
live_cleanup() {
  local live
  live=$(jobs -pr)
  [ -n "$live" ] && kill -TERM $live 2>/dev/null && sleep 1
  live=$(jobs -pr)
  [ -n "$live" ] && kill -KILL $live 2>/dev/null
  wait 2>/dev/null
  [ -n "${on_exit:-}" ] && eval "$on_exit"
  if [ "${keep:-0}" = 1 ]; then echo "kept $work"; else rm -rf "$work"; fi
}

# (Re)starts service $1 with its command ${cmd[$1]}, log appended to $logs/$1.log; its pid in ${pid[$1]}.
start() {
  eval "exec ${cmd[$1]}" >> "$logs/$1.log" 2>&1 &
  pid[$1]=$!
}

# Data rows of a CSV file (0 when it does not exist).
rows_of() { [ -f "$1" ] && echo $(( $(wc -l < "$1") - 1 )) || echo 0; }

wait_rows() {  # $1 = file, $2 = rows, $3 = seconds
  local i
  for i in $(seq 1 $(( $3 * 10 ))); do [ "$(rows_of "$1")" -ge "$2" ] && return 0; sleep 0.1; done
  return 1
}

wait_log() {  # $1 = file, $2 = pattern, $3 = seconds, $4 = occurrences (default 1)
  local i
  for i in $(seq 1 $(( $3 * 10 ))); do [ "$(grep -c -- "$2" "$1" 2>/dev/null)" -ge "${4:-1}" ] && return 0; sleep 0.1; done
  return 1
}

# The IMS test-2 snapshots as sensor-ingest JSON blocks (tests/fault/plant_day_blocks.awk: 256 samples x 4
# bearings, one block per snapshot): $1 = deploy dir, $2 = asset group, $3 = seed, $4 = output file, $5 = how many
# (default all 984).
live_blocks() {
  local awk_file
  awk_file="$(cd "$(dirname "${BASH_SOURCE[0]}")/../fault" && pwd)/plant_day_blocks.awk"
  awk -F, -v group="$2" -v rows=256 -v seed="$3" -f "$awk_file" \
    "$1/data/ims2-features/derived_per_file_stats_all984.csv" | head -n "${5:-984}" > "$4"
}

live_free_port() { python3 -c 'import socket; s = socket.socket(); s.bind(("127.0.0.1", 0)); print(s.getsockname()[1])'; }

# A mosquitto broker on 127.0.0.1 for the test: loopback only, no persistence, no limit on queued messages (the
# default 1000 would drop). $1 = folder for its configuration and log; sets $broker_port. Returns 1 when mosquitto
# or mosquitto_pub is missing.
live_broker() {
  [ -x /usr/sbin/mosquitto ] && command -v mosquitto_pub > /dev/null || return 1
  broker_port=$(live_free_port)
  printf 'listener %s 127.0.0.1\nallow_anonymous true\npersistence false\nmax_queued_messages 0\n' "$broker_port" \
    > "$1/mosquitto.conf"
  /usr/sbin/mosquitto -c "$1/mosquitto.conf" > "$1/mosquitto.log" 2>&1 &
  local i
  for i in $(seq 1 50); do grep -q "Opening ipv4 listen socket on port $broker_port" "$1/mosquitto.log" 2>/dev/null && return 0; sleep 0.1; done
  return 0
}
