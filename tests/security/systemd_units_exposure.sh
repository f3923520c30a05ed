#!/usr/bin/env bash
# Every shipped unit rates <= 3.0 in `systemd-analyze security --offline=true` (it rated
# 7.6 "EXPOSED" before), has a memory ceiling (MemoryMax=) and a private umask, and passes
# `systemd-analyze verify` apart from the binary path (the units name @CAUSAL_TWIN_BINDIR@, filled in at
# install; here /usr/bin, where nothing needs to be installed).
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
  problems=$(systemd-analyze verify "$unit" 2>&1 | grep -v 'is not executable: No such file or directory' || true)
  [ -z "$problems" ] || { echo "$problems"; ok=0; }
  printf '%-4s %-34s exposure %s  MemoryMax=%s UMask=%s\n' "$([ $ok = 1 ] && echo ok || echo FAIL)" "$name" \
    "${score:-?}" "${memory:-none}" "${umask:-none}"
  [ $ok = 1 ] || fail=1
done
[ "$fail" = 0 ] && echo PASS
exit "$fail"
