# Sourced by the shell tests that start processes and count: `pids` holds what the test started (each ended by
# its pid on exit, then $work is removed: set work before sourcing), and `check NAME EXPECTED GOT` prints ok or
# FAIL and sets fail=1 on a mismatch (the test ends with exit "$fail").
pids=()
cleanup() {
  for p in "${pids[@]}"; do kill -TERM "$p" 2> /dev/null || true; done
  for p in "${pids[@]}"; do wait "$p" 2> /dev/null || true; done
  rm -rf "$work"
}
trap cleanup EXIT
fail=0
check() {  # check NAME EXPECTED GOT
  if [ "$2" = "$3" ]; then echo "ok   $1: $3"; else echo "FAIL $1: expected $2, got $3"; fail=1; fi
}
