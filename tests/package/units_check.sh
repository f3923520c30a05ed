#!/usr/bin/env bash
# Part of package_root_check.sh (inside its private mount namespace, the package installed): the units' commands
# run as the units' own users with DDS-Security on and each unit's key handed over as systemd would (least
# privilege per service). No systemd as PID 1 here, so systemd's part is done by this script as the unit
# files and the key drop-ins say:
#   * a PKI made by the installed make-pki.sh in /etc/causal-twin/security (the README's layout: CA keys
#     included, so the purge's copy to /root is checked later), then the installed install-unit-keys.sh:
#     keys root:root 0600, public files root:causal-twin, one LoadCredential= drop-in per unit;
#   * ExecStart with %i and the EnvironmentFile variables expanded, run with setpriv as the unit's User= and
#     Group=, in its WorkingDirectory, its StateDirectory= made as systemd makes it (owner, StateDirectoryMode);
#   * LoadCredential=dds-key.pem:PATH: PATH copied by root into a folder of the unit's user (0500, file 0400),
#     named by $CREDENTIALS_DIRECTORY (systemd's /run/credentials/UNIT; here under the namespace's /dev/shm).
# Checked: every user reads its own credential and no key file, no other unit's credential or state; recorder,
# recommender, estimator@main and sensor@ims2-slice exchange the slice (6 condition vectors recorded), each
# logs that its key came from the credential, and each exits 0 on SIGTERM.
#   units_check.sh WORK DOMAIN        (writes WORK/units_conditions.csv)
set -euo pipefail
work="$1"; domain="$2"
fail() { echo "FAIL: $*" >&2; exit 1; }
unit_pids=()
trap 'for p in "${unit_pids[@]}"; do kill -TERM "$p" 2>/dev/null || true; done; wait' EXIT
sec=/etc/causal-twin/security
share=/usr/share/causal-twin/security

echo "--- DDS-Security with one key per unit (make-pki.sh, install-unit-keys.sh)"
"$share/make-pki.sh" "$sec" > "$work/units_pki.log" 2>&1 || { cat "$work/units_pki.log"; fail "make-pki.sh $sec"; }
"$share/install-unit-keys.sh" "$sec" > "$work/units_keys.log" 2>&1 || { cat "$work/units_keys.log"; fail "install-unit-keys.sh"; }
grep "install-unit-keys:" "$work/units_keys.log"
for key in "$sec"/*/key.pem; do
  [ "$(stat -c '%U:%G %a' "$key")" = "root:root 600" ] || fail "$key is $(stat -c '%U:%G %a' "$key"), not root:root 600"
done
[ "$(stat -c '%U:%G %a' "$sec/identity_ca.pem")" = "root:causal-twin 640" ] || fail "$sec/identity_ca.pem: $(stat -c '%U:%G %a' "$sec/identity_ca.pem")"
! runuser -u nobody -- ls "$sec" > /dev/null 2>&1 || fail "a user outside the group causal-twin lists $sec"
echo "CAUSAL_TWIN_SECURITY_DIR=$sec" >> /etc/causal-twin/twin.env
# The drop-ins are valid unit configuration (systemd-analyze verify reads them beside the units).
verify=$(systemd-analyze verify /usr/lib/systemd/system/causal-twin-*.service 2>&1) || { echo "$verify"; fail "verify with drop-ins"; }
[ -z "$(grep -i causal-twin <<< "$verify" || true)" ] || { echo "$verify"; fail "systemd-analyze verify warned about the drop-ins"; }

# unit_argv UNIT INSTANCE: argv (ExecStart), envv (EnvironmentFile assignments), user, group, wd, state,
# state_mode and cred (the LoadCredential= path of its drop-ins) of the unit, as systemd reads them.
setting() { sed -n "s/^$2=//p" "$1" | tail -1; }
unit_argv() {
  local unit="/usr/lib/systemd/system/$1" instance="$2" line file key value
  declare -gA unit_env=()
  envv=()
  while read -r file; do
    file="${file#-}"; file="${file//%i/$instance}"
    [ -f "$file" ] || continue
    while IFS= read -r line; do
      [[ "$line" =~ ^[A-Za-z_][A-Za-z0-9_]*= ]] || continue
      key="${line%%=*}"; value="${line#*=}"
      [[ "$value" =~ ^\"(.*)\"$ ]] && value="${BASH_REMATCH[1]}"  # systemd removes the quotes
      unit_env[$key]="$value"; envv+=("$key=$value")
    done < "$file"
  done < <(sed -n 's/^EnvironmentFile=//p' "$unit")
  line="$(setting "$unit" ExecStart)"; line="${line//%i/$instance}"
  for key in "${!unit_env[@]}"; do line="${line//\$$key/${unit_env[$key]}}"; done
  read -ra argv <<< "$line"
  user=$(setting "$unit" User); group=$(setting "$unit" Group)
  wd=$(setting "$unit" WorkingDirectory); wd="${wd//%i/$instance}"
  state=$(setting "$unit" StateDirectory); state="${state//%i/$instance}"; state_mode=$(setting "$unit" StateDirectoryMode)
  [[ "$user" =~ ^causal-twin-[a-z]+$ ]] && [ "$group" = causal-twin ] || fail "$1: User=$user Group=$group"
  cred=$(sed -n 's/^LoadCredential=dds-key.pem://p' "/etc/systemd/system/$1.d/causal-twin-dds-key.conf" 2>/dev/null || true)
  [ -n "$cred" ] || fail "$1: no LoadCredential=dds-key.pem drop-in"
}
# prepare_unit UNIT INSTANCE: what systemd does before ExecStart: the state folder and the credential (in a
# folder named as the unit instance, e.g. causal-twin-estimator@main.service).
prepare_unit() {
  if [ -n "$state" ]; then
    install -d -o "$user" -g "$group" -m "${state_mode:-0755}" "/var/lib/$state"
  fi
  unit_name="${1/@./@$2.}"
  creds="/dev/shm/credentials/$unit_name"
  install -d -o "$user" -g "$group" -m 0500 "$creds"
  install -o "$user" -g "$group" -m 0400 "$cred" "$creds/dds-key.pem"
}
as_unit() { env -C "$wd" "${envv[@]}" CREDENTIALS_DIRECTORY="$creds" setpriv --reuid "$user" --regid "$group" --init-groups "$@"; }
mkdir -p /dev/shm/credentials && chmod 0755 /dev/shm/credentials
unit_names=(); unit_users=()
start_unit() {  # UNIT INSTANCE
  unit_argv "$1" "$2"; prepare_unit "$1" "$2"
  # Not through as_unit: $! must be the service itself (env and setpriv exec it), so SIGTERM reaches it.
  env -C "$wd" "${envv[@]}" CREDENTIALS_DIRECTORY="$creds" setpriv --reuid "$user" --regid "$group" --init-groups \
    "${argv[@]}" > "$work/unit_$unit_name.log" 2>&1 &
  unit_pids+=($!); unit_names+=("$unit_name"); unit_users+=("$user")
}

echo "--- the units' commands as their own users (no systemd here: the unit files and drop-ins read as systemd does)"
echo "CAUSAL_TWIN_DOMAIN_ID=$domain" >> /etc/causal-twin/twin.env  # the operator's one edit: this cell's domain
start_unit causal-twin-recorder.service ""
start_unit causal-twin-recommender.service ""
start_unit causal-twin-estimator@.service main
unit_argv causal-twin-sensor@.service ims2-slice; prepare_unit causal-twin-sensor@.service ims2-slice
as_unit timeout 60 "${argv[@]}" > "$work/unit_sensor.log" 2>&1 || { tail "$work/unit_sensor.log"; fail "causal-twin-sensor@ims2-slice"; }
grep -q "key from the systemd credential dds-key.pem" "$work/unit_sensor.log" || fail "sensor: key not from the credential"

# Least privilege, while they run: each user reads its own credential, no key file and nothing of the others.
for i in "${!unit_names[@]}"; do
  u="${unit_users[$i]}"
  runuser -u "$u" -- cat "/dev/shm/credentials/${unit_names[$i]}/dds-key.pem" > /dev/null || fail "$u cannot read its own credential"
  for key in "$sec"/*/key.pem; do
    ! runuser -u "$u" -- cat "$key" > /dev/null 2>&1 || fail "$u reads $key"
  done
  for other in /dev/shm/credentials/*/; do
    [ "$other" = "/dev/shm/credentials/${unit_names[$i]}/" ] && continue
    ! runuser -u "$u" -- cat "$other/dds-key.pem" > /dev/null 2>&1 || fail "$u reads the credential in $other"
  done
done
! runuser -u causal-twin-recorder -- ls /var/lib/causal-twin/estimator-main > /dev/null 2>&1 || fail "the recorder's user lists the estimator's state"
! runuser -u causal-twin-sensor -- ls /var/lib/causal-twin/recordings > /dev/null 2>&1 || fail "the sensor's user lists the recordings"
echo "units: ${unit_users[*]} causal-twin-sensor: each reads its own credential only; no key file and no other unit's state"

recorded=/var/lib/causal-twin/recordings/conditions_ims2-shaft1_meanabs.csv
statuses=/var/lib/causal-twin/recordings/asset_status.csv
# Stop once the recorder has every condition vector (the estimator's output) and the recommender says it has learned
# from all 6 snapshots ("learning", 6 of 140 in asset_status.csv: it has processed them and has something to
# checkpoint): the recorder alone came first, and a SIGTERM then could reach a recommender that had not yet
# received its first factors.
rows_of() { [ -f "$1" ] && echo $(($(wc -l < "$1") - 1)) || echo 0; }
learned_all() { [ -f "$statuses" ] && awk -F, '$2 == "learning" && $3 == 6 { found = 1 } END { exit !found }' "$statuses"; }
for _ in $(seq 300); do [ "$(rows_of "$recorded")" = 6 ] && learned_all && break; sleep 0.1; done
learned_all || fail "the recommender's status never said 6 of 140 observations learned: $(tail -n 2 "$statuses" 2>/dev/null)"
for p in "${unit_pids[@]}"; do kill -TERM "$p" 2>/dev/null || true; done
for i in "${!unit_pids[@]}"; do
  rc=0; wait "${unit_pids[$i]}" || rc=$?
  [ "$rc" = 0 ] || { tail "$work/unit_${unit_names[$i]}.log"; fail "${unit_names[$i]} exited $rc on SIGTERM"; }
  grep -q "key from the systemd credential dds-key.pem" "$work/unit_${unit_names[$i]}.log" \
    || { tail "$work/unit_${unit_names[$i]}.log"; fail "${unit_names[$i]}: DDS key not from the credential"; }
done
unit_pids=()
[ -f "$recorded" ] || fail "the recorder unit wrote no $recorded"
cp "$recorded" "$work/units_conditions.csv"
echo "units: recorder wrote $(($(wc -l < "$recorded") - 1)) condition vectors to /var/lib/causal-twin/recordings (DDS-Security on, key per unit)"
for d in estimator-main:estimator recommender:recommender recordings:recorder; do
  dir="/var/lib/causal-twin/${d%%:*}"; u="causal-twin-${d##*:}"
  [ -n "$(ls -A "$dir" 2>/dev/null)" ] || { tail -n 25 "$work/unit_causal-twin-${d##*:}"*.log; fail "nothing in $dir"; }
  [ -z "$(find "$dir" ! -user "$u")" ] || fail "$dir: files not owned by $u"
  [ "$(stat -c %a "$dir")" = 700 ] || fail "$dir is $(stat -c %a "$dir"), not 700"
done
echo "units: checkpoints in estimator-main ($(ls /var/lib/causal-twin/estimator-main | wc -l) files) and recommender ($(ls /var/lib/causal-twin/recommender | wc -l) files), each 0700 and owned by its unit's user; every service exited 0 on SIGTERM"
