#!/usr/bin/env bash
# Every shipped unit rates <= 3.0 in `systemd-analyze security --offline=true` (it rated
# 7.6 "EXPOSED" before), has a memory ceiling (MemoryMax=) and a private umask, and passes
# `systemd-analyze verify` apart from the binary path (the units name @CAUSAL_TWIN_BINDIR@, filled in at
# install; here /usr/bin, where nothing needs to be installed). And a restart policy that keeps a unit out of a
# tight kill/restart loop (one discovery packet every few seconds kills it at its memory ceiling): Restart=on-failure
# at most StartLimitBurst <= 10 times within StartLimitIntervalSec >= 60 s, RestartSec >= 2; then systemd leaves it
# failed and its journal says "Start request repeated too quickly".
#   systemd_units_exposure.sh SOURCE_DIR
set -euo pipefail
src="$1"
command -v systemd-analyze > /dev/null || { echo "SKIP: no systemd-analyze"; exit 77; }
work="$(mktemp -d /tmp/causal_units_XXXXXX)"
trap 'rm -rf "$work"' EXIT
cp "$src"/deploy/systemd/*.service "$work/"
sed -i 's#@CAUSAL_TWIN_BINDIR@#/usr/bin#' "$work"/*.service
fail=0
for unit in "$work"/*.service; do
  name=$(basename "$unit")
  score=$( (cd "$work" && systemd-analyze security --offline=true "$name" 2>&1) | sed -n 's/.*Overall exposure level for .*: \([0-9.]*\) .*/\1/p')
  memory=$(sed -n 's/^MemoryMax=//p' "$unit")
  umask=$(sed -n 's/^UMask=//p' "$unit")
  ok=1
  awk -v s="${score:-99}" 'BEGIN { exit !(s <= 3.0) }' || ok=0
  [ -n "$memory" ] && [ "$umask" = 0077 ] || ok=0
  interval=$(sed -n 's/^StartLimitIntervalSec=//p' "$unit"); burst=$(sed -n 's/^StartLimitBurst=//p' "$unit")
  restart_sec=$(sed -n 's/^RestartSec=//p' "$unit"); restart=$(sed -n 's/^Restart=//p' "$unit")
  [ "$restart" = on-failure ] && [ "${interval:-0}" -ge 60 ] && [ "${burst:-0}" -ge 1 ] && [ "${burst:-0}" -le 10 ] \
    && [ "${restart_sec:-0}" -ge 2 ] || { echo "$name: restart policy Restart=$restart RestartSec=$restart_sec" \
      "StartLimitIntervalSec=$interval StartLimitBurst=$burst (want on-failure, >= 2, >= 60, 1..10)"; ok=0; }
  problems=$(systemd-analyze verify "$unit" 2>&1 | grep -v 'is not executable: No such file or directory' || true)
  [ -z "$problems" ] || { echo "$problems"; ok=0; }
  printf '%-4s %-34s exposure %s  MemoryMax=%s UMask=%s starts<=%s/%ss\n' "$([ $ok = 1 ] && echo ok || echo FAIL)" \
    "$name" "${score:-?}" "${memory:-none}" "${umask:-none}" "${burst:-?}" "${interval:-?}"
  [ $ok = 1 ] || fail=1
done
[ "$fail" = 0 ] && echo PASS
exit "$fail"
