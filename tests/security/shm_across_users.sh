#!/usr/bin/env bash
# A measurement, not a ctest (one user per unit): does Fast DDS 2.9 deliver between processes of
# DIFFERENT users of ONE group, on a given transport profile and umask? sensor-replay (user A) sends the
# 984-row feature table to causal-estimator (user B), whose condition vectors causal-recorder (user C) records;
# all three are in the group ctwin-shm and start with the given umask (as UMask= would set it). Prints the
# /dev/shm listing 4 s in, sent and received counts and the rows recorded. Run it isolated (root: it creates the
# users ctwin-shm-a/b/c and the group ctwin-shm, and removes them at the end; domain 151):
#   tests/support/isolate.sh tests/security/shm_across_users.sh build deploy localhost.xml 0077
#   (profiles: localhost.xml = shared memory + UDP, localhost-udp.xml = UDP only; SAME_USER=1: all as user A)
set -uo pipefail
build="$(cd "$1" && pwd)"; deploy="$(cd "$2" && pwd)"; profile="$3"; um="$4"
[ "$(id -u)" = 0 ] || { echo "SKIP: needs root (useradd)"; exit 77; }
grp=ctwin-shm
users=(ctwin-shm-a ctwin-shm-b ctwin-shm-c)
made=()
work="$(mktemp -d /tmp/shm_across_users.XXXXXX)"; chmod 0777 "$work"
pids=()
cleanup() {
  for p in "${pids[@]}"; do kill -TERM "$p" 2>/dev/null; wait "$p" 2>/dev/null; done
  for u in "${made[@]}"; do userdel "$u"; done
  [ ${#made[@]} = 0 ] || groupdel "$grp"
  rm -rf "$work"
}
trap cleanup EXIT
if ! getent group "$grp" > /dev/null; then
  groupadd --system "$grp"
  for u in "${users[@]}"; do useradd --system --no-create-home --shell /usr/sbin/nologin -g "$grp" "$u" && made+=("$u"); done
fi
a=${users[0]}; b=${users[1]}; c=${users[2]}
[ -n "${SAME_USER:-}" ] && { b=$a; c=$a; }
bin="$build/services"
dds=(--domain 151 --qos "$deploy/dds/qos.xml" --transport "$deploy/dds/$profile")
as() { local u=$1; shift; setpriv --reuid "$u" --regid "$grp" --init-groups sh -c "umask $um; exec \"\$@\"" sh "$@"; }
as "$c" "$bin/causal_recorder/causal-recorder" "${dds[@]}" --out "$work/rec" --idle-exit 6 --max-runtime 40 > "$work/recorder.log" 2>&1 & pids+=($!)
as "$b" "$bin/causal_estimator/causal-estimator" "${dds[@]}" --idle-exit 4 --max-runtime 40 --wait-for causal-recorder \
  > "$work/estimator.log" 2>&1 & pids+=($!)
as "$a" "$bin/sensor_replay/sensor-replay" "${dds[@]}" --features "$deploy/data/ims2-features/derived_per_file_stats_all984.csv" \
  --feature-suffix _meanabs --feature-name meanabs --speed 36000 --wait-for causal-estimator --wait-timeout 20 \
  > "$work/replay.log" 2>&1 & pids+=($!)
sleep 4
echo "--- /dev/shm 4 s in ($profile, umask $um; users $a $b $c, group $grp):"
ls -ln /dev/shm | grep -v '^total' | head -8
names=(recorder estimator replay)
for i in 2 1 0; do wait "${pids[$i]}"; echo "${names[$i]} exit $?"; done
pids=()
sent=$(sed -n 's/.*summary topic=causal_twin\/condition_input sent=\([0-9]*\).*/\1/p' "$work/replay.log")
got=$(sed -n 's/.*summary topic=causal_twin\/condition_input received=\([0-9]*\).*/\1/p' "$work/estimator.log")
rows=0; [ -f "$work/rec/conditions_ims2-shaft1_meanabs.csv" ] && rows=$(( $(wc -l < "$work/rec/conditions_ims2-shaft1_meanabs.csv") - 1 ))
stalls=$(cat "$work"/*.log | grep -c "HEALTH RAISED .*reader_not_acknowledging" || true)
echo "result: $profile umask $um: condition inputs sent=${sent:-none (the replay did not finish)} received=${got:-?}; condition vectors recorded=$rows; reader_not_acknowledging alarms=$stalls"
