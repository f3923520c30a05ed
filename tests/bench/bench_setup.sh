# Sourced by the estimator benches (estimator_cpu.sh, group_join_latency.sh) once their options are read ($here,
# $qos, $keep): bench_start NAME BINARY... checks the binaries, sets the loopback DDS options ($dds) and the run
# folder ($work: --keep DIR keeps the run there, else a temporary one removed at the end) and ends every process
# in $pids on exit.
bench_start() {
  local name="$1" b
  shift
  for b in "$@"; do [ -x "$b" ] || { echo "$name: $b missing" >&2; exit 2; }; done
  dds=(--qos "$qos" --transport "$here/deploy/dds/localhost.xml")
  work="${keep:-$(mktemp -d "/tmp/${name%.sh}.XXXXXX")}"
  mkdir -p "$work"
  pids=()
  trap bench_cleanup EXIT
  trap 'exit 130' INT TERM
}
bench_cleanup() {
  for p in "${pids[@]}"; do kill "$p" 2>/dev/null; done
  [ -n "$keep" ] || rm -rf "$work"
}
