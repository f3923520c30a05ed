#!/usr/bin/env bash
# The development package and the Debian documentation, checked inside package_root_check.sh's mount namespace
# with causal-twin and causal-twin-dev installed and the source and build trees hidden:
#   1. /usr/share/doc/<package>/{copyright,changelog.Debian.gz,README.md} for both packages, and one manual page
#      per command in /usr/bin;
#   2. the example sensor (/usr/share/doc/causal-twin-dev/examples/sensor_publisher) is configured with
#      find_package(CausalTwin) and built against the INSTALLED headers and library only;
#   3. it publishes SNAPSHOTS x FRAMES frames to the installed causal-estimator (recorded by the installed
#      causal-recorder, domain DOMAIN): the estimator received exactly that many frames (none lost or refused)
#      and the recorder wrote one condition vector per snapshot.
#   dev_package_check.sh WORK DOMAIN
set -euo pipefail
work="$1"; domain="$2"
snapshots=3; frames=4
fail() { echo "FAIL: $*" >&2; exit 1; }
pids=()
trap 'for p in "${pids[@]}"; do kill -TERM "$p" 2>/dev/null || true; done; wait' EXIT

echo "--- /usr/share/doc and manual pages"
for p in causal-twin causal-twin-dev; do
  for f in copyright changelog.Debian.gz README.md; do [ -s "/usr/share/doc/$p/$f" ] || fail "no /usr/share/doc/$p/$f"; done
  head -1 "/usr/share/doc/$p/copyright" | grep -q '^Format: https://www.debian.org/doc/packaging-manuals/copyright-format/1.0/' \
    || fail "/usr/share/doc/$p/copyright is not machine-readable (DEP-5)"
done
pages=0
for cmd in $(dpkg -L causal-twin | grep '^/usr/bin/'); do
  page="/usr/share/man/man1/$(basename "$cmd").1.gz"
  [ -s "$page" ] || fail "no manual page for $cmd"
  zcat "$page" | grep -q '^\.SH DESCRIPTION' || fail "$page has no DESCRIPTION"
  pages=$((pages + 1))
done
echo "$pages commands in /usr/bin, $pages manual pages"

echo "--- the example sensor, built against the installed causal-twin-dev"
cp -r /usr/share/doc/causal-twin-dev/examples/sensor_publisher "$work/example_src"
cmake -S "$work/example_src" -B "$work/example_build" -DCMAKE_BUILD_TYPE=Release > "$work/example_cmake.log" 2>&1 \
  || { cat "$work/example_cmake.log"; fail "cmake of the example"; }
grep -Eq "CausalTwin_DIR:PATH=/usr/lib/([a-z0-9_-]+/)?cmake/CausalTwin" "$work/example_build/CMakeCache.txt" \
  || fail "find_package(CausalTwin) did not take /usr/lib/cmake/CausalTwin: $(grep CausalTwin_DIR "$work/example_build/CMakeCache.txt")"
cmake --build "$work/example_build" > "$work/example_build.log" 2>&1 || { cat "$work/example_build.log"; fail "building the example"; }
publisher="$work/example_build/example-sensor"
lib=$(ldd "$publisher" | awk '/libcausal_twin_types/ {print $3}')
[ -n "$lib" ] && [ "$(readlink -f "$lib")" = "$(readlink -f /usr/lib/libcausal_twin_types.so.0)" ] \
  || fail "the example does not load the installed libcausal_twin_types.so.0 (ldd: ${lib:-none})"
echo "built $(basename "$publisher"), linked to $lib"

echo "--- the example sensor against the installed services (domain $domain)"
causal-recorder --domain "$domain" --out "$work/example_recorded" --idle-exit 3 --max-runtime 90 \
  > "$work/example_recorder.log" 2>&1 & pids+=($!)
causal-estimator --domain "$domain" --idle-exit 3 --max-runtime 90 --wait-for causal-recorder \
  > "$work/example_estimator.log" 2>&1 & pids+=($!)
timeout 60 "$publisher" --domain "$domain" --snapshots "$snapshots" --frames "$frames" > "$work/example_publisher.log" 2>&1 \
  || { cat "$work/example_publisher.log"; tail "$work/example_estimator.log"; fail "the example sensor exited non-zero"; }
for i in 0 1; do
  rc=0; wait "${pids[$i]}" || rc=$?
  [ "$rc" = 0 ] || { tail "$work/example_estimator.log" "$work/example_recorder.log"; fail "service $i exited $rc"; }
done
pids=()
sent=$((snapshots * frames))
cat "$work/example_publisher.log"
grep -qx "example-sensor: sent frames=$sent snapshots=$snapshots failed=0 acknowledged=yes" "$work/example_publisher.log" \
  || fail "the example did not send and have acknowledged $sent frames"
summary=$(grep -o "summary topic=causal_twin/vibration_frame .*" "$work/example_estimator.log" || true)
echo "causal-estimator: $summary"
[ "$summary" = "summary topic=causal_twin/vibration_frame received=$sent lost=0 refused=0 not_entitled=0" ] \
  || fail "the estimator did not receive exactly $sent frames: $summary"
conditions="$work/example_recorded/conditions_example-pump_meanabs.csv"
[ -f "$conditions" ] || fail "the recorder wrote no $conditions: $(ls "$work/example_recorded" 2>&1)"
rows=$(($(wc -l < "$conditions") - 1))
[ "$rows" = "$snapshots" ] || fail "$rows condition vectors recorded, $snapshots snapshots sent"
echo "causal-recorder: $rows condition vectors (= snapshots sent)"
