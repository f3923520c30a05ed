#!/usr/bin/env bash
# Misconfiguration stops cleanly: every executable exits 2 on a usage error and names an option (the unknown one, or
# a required one CLI11 checks first; CLI11's own exit
# codes, e.g. 109 for an unknown option, never leak: the units' RestartPreventExitStatus=2 relies on it), and a
# service under systemd (INVOCATION_ID set) refuses an unknown CAUSAL_TWIN_* variable or a misspelt *_ARGS name
# from its env files with exit 2, naming it and the closest known name. The shipped env files pass.
#   usage_errors.sh <deploy dir> <executable>...
set -uo pipefail
deploy="$1"; shift
failures=0; checked=0
fail() { echo "FAIL: $1"; failures=$(( failures + 1 )); }
expect() {  # $1 = want code, $2 = text the output must contain ("" = any), then the command
  local want="$1" text="$2" out code; shift 2
  out=$("$@" 2>&1 < /dev/null); code=$?
  checked=$(( checked + 1 ))
  [ "$code" = "$want" ] || { fail "$(basename "$1") ${*:2}: exit $code (want $want): $(echo "$out" | tail -2)"; return; }
  [ -z "$text" ] || grep -qE -- "$text" <<< "$out" || fail "$(basename "$1") ${*:2}: output does not name '$text': $(echo "$out" | tail -2)"
}
for exe in "$@"; do
  expect 2 "(--metrics-prot|--[a-z-]+ is required|option from \\[--)" "$exe" --metrics-prot 1
  expect 0 "" "$exe" --help
done
# The services (they share the DDS options and the environment check).
services=()
for exe in "$@"; do help=$("$exe" --help 2>&1); grep -q -- "--domain" <<< "$help" && services+=("$exe"); done
[ "${#services[@]}" -ge 6 ] || fail "only ${#services[@]} services found among the executables"
for exe in "${services[@]}"; do
  expect 2 "--domain" "$exe" --domain abc
  expect 2 "--domain" "$exe" --domain 1000  # outside 0..232: refused before any participant exists
  # env -i: a unit's environment is what systemd and its env files give it, not the test harness's (CAUSAL_TWIN_REQUIRE_ALL).
  expect 2 "CAUSAL_TWIN_DOMIAN_ID" env -i PATH="$PATH" INVOCATION_ID=test CAUSAL_TWIN_DOMIAN_ID=5 "$exe" --help
  expect 2 "did you mean CAUSAL_TWIN_DOMAIN_ID\\?" env -i PATH="$PATH" INVOCATION_ID=test CAUSAL_TWIN_DOMIAN_ID=5 "$exe" --help
  expect 2 "did you mean RECOMMENDER_ARGS\\?" env -i PATH="$PATH" INVOCATION_ID=test RECOMENDER_ARGS=--verbose "$exe" --help
  expect 0 "" env -i PATH="$PATH" INVOCATION_ID=test CAUSAL_TWIN_DOMAIN_ID=5 RECOMMENDER_ARGS=--verbose JAVA_ARGS=-x "$exe" --help
  # Outside systemd the environment is the user's: not checked.
  expect 0 "" env -u INVOCATION_ID CAUSAL_TWIN_DOMIAN_ID=5 "$exe" --help
done
# Every variable the shipped env files set or show (commented examples included) is known.
vars=()
while IFS= read -r v; do vars+=("$v=1"); done < <(sed -n 's/^#\{0,1\}\([A-Z][A-Z0-9_]*\)=.*/\1/p' "$deploy"/systemd/env/*.env | sort -u)
[ "${#vars[@]}" -ge 7 ] || fail "only ${#vars[@]} variables found in the shipped env files"
for v in "${vars[@]}"; do
  case $v in CAUSAL_TWIN_*|*_ARGS=1) expect 0 "" env -i PATH="$PATH" INVOCATION_ID=test "$v" "${services[0]}" --help ;; esac
done
echo "$checked checks, $failures failed (${#services[@]} services, $# executables, ${#vars[@]} shipped variables)"
[ "$failures" = 0 ]
