#!/usr/bin/env bash
# One unauthenticated 120-byte discovery packet (discovery_packet.py) makes a secured
# Fast DDS 2.9.1 participant allocate about 1.44 GB. The defence is a memory ceiling per unit (MemoryMax= in
# deploy/systemd): the kernel stops that one service, not the host. Here a secured causal-recorder runs in a
# memory cgroup of 256 MiB (as a unit with MemoryMax=256M) and an alarm-recommender of the same domain outside
# it; after the packet the recorder is killed by the cgroup's OOM killer (exit 137, oom_kill 1) within 10 s
# and the recommender runs on. Private network namespace, fixed domain 54; root and a writable memory cgroup
# (v1 or v2) are needed, else it skips (77; without root it fails under CAUSAL_TWIN_REQUIRE_ALL). About 6 s.
#   discovery_memory_limit.sh BUILD_DIR DEPLOY_DIR
set -euo pipefail
build="$(cd "$1" && pwd)"; deploy="$(cd "$2" && pwd)"; here="$(cd "$(dirname "$0")" && pwd)"
skip() {
  if [ -n "${CAUSAL_TWIN_REQUIRE_ALL:-}" ]; then echo "FAIL: $1"; exit 1; fi
  echo "SKIP: $1"; exit 77
}
if [ -z "${CAUSAL_DISCOVERY_LIMIT_NETNS:-}" ]; then
  if CAUSAL_DISCOVERY_LIMIT_NETNS=1 unshare --net true 2> /dev/null; then
    exec env CAUSAL_DISCOVERY_LIMIT_NETNS=1 unshare --net "$0" "$@"
  fi
  skip "cannot create a network namespace (run as root)"
fi
ip link set lo up
command -v ss > /dev/null || skip "ss (iproute2) is not installed"
domain=54
work="$(mktemp -d /tmp/causal_discovery_limit_XXXXXX)"
cg=""
pids=()
cleanup() {
  for p in "${pids[@]}"; do kill -TERM "$p" 2> /dev/null || true; done
  for p in "${pids[@]}"; do wait "$p" 2> /dev/null || true; done
  [ -z "$cg" ] || rmdir "$cg" 2> /dev/null || true
  rm -rf "$work"
}
trap cleanup EXIT
# A memory cgroup of 256 MiB without swap, as MemoryMax=256M + MemorySwapMax=0 make for a unit.
if [ -w /sys/fs/cgroup/memory ]; then
  cg=/sys/fs/cgroup/memory/causal_discovery_limit_$$
  mkdir "$cg"
  echo 256M > "$cg/memory.limit_in_bytes"
  [ ! -f "$cg/memory.memsw.limit_in_bytes" ] || echo 256M > "$cg/memory.memsw.limit_in_bytes"
  ooms() { awk '$1 == "oom_kill" {print $2}' "$cg/memory.oom_control"; }
elif [ -f /sys/fs/cgroup/cgroup.controllers ] && grep -qw memory /sys/fs/cgroup/cgroup.controllers \
     && echo +memory > /sys/fs/cgroup/cgroup.subtree_control 2> /dev/null; then
  cg=/sys/fs/cgroup/causal_discovery_limit_$$
  mkdir "$cg"
  echo 256M > "$cg/memory.max"
  [ ! -f "$cg/memory.swap.max" ] || echo 0 > "$cg/memory.swap.max"
  ooms() { awk '$1 == "oom_kill" {print $2}' "$cg/memory.events"; }
else
  # A kernel facility of the machine, not a package install_deps.sh could add: a skip even in CI.
  echo "SKIP: no writable memory cgroup (v1 or v2)"; exit 77
fi
"$deploy/security/make-pki.sh" "$work/pki" > "$work/pki.log" 2>&1
common=(--domain "$domain" --security "$work/pki" --max-runtime 60)
# The recorder starts first (participant id 0: its discovery port is 7410 + 250 * domain).
sh -c "echo \$\$ > '$cg/cgroup.procs'; exec '$build/services/causal_recorder/causal-recorder' ${common[*]} --out '$work/out'" \
  > "$work/recorder.log" 2>&1 &
recorder=$!; pids+=("$recorder")
port=$((7410 + 250 * domain))
for _ in $(seq 100); do ss -ulnp | grep -q "127.0.0.1:$port .*pid=$recorder," && break; sleep 0.1; done
ss -ulnp | grep -q "127.0.0.1:$port .*pid=$recorder," || { echo "FAIL: the recorder does not listen on $port"; cat "$work/recorder.log"; exit 1; }
"$build/services/alarm_recommender/alarm-recommender" "${common[@]}" > "$work/recommender.log" 2>&1 &
recommender=$!; pids+=("$recommender")
sleep 1
fail=0
check() {  # check NAME EXPECTED GOT
  if [ "$2" = "$3" ]; then echo "ok   $1: $3"; else echo "FAIL $1: expected $2, got $3"; fail=1; fi
}
check "recorder running before the packet" 1 "$(kill -0 "$recorder" 2> /dev/null && echo 1 || echo 0)"
echo "recorder RSS before: $(awk '/VmRSS/ {print $2, $3}' "/proc/$recorder/status")"
echo "packet bytes: $(python3 "$here/discovery_packet.py" "$port" 20000000)"
code=""
for _ in $(seq 100); do
  if ! kill -0 "$recorder" 2> /dev/null; then set +e; wait "$recorder"; code=$?; set -e; break; fi
  sleep 0.1
done
check "recorder killed by the cgroup's OOM killer (exit code)" 137 "$code"
check "OOM kills in its cgroup" 1 "$(ooms)"
check "recommender outside the cgroup still running" 1 "$(kill -0 "$recommender" 2> /dev/null && echo 1 || echo 0)"
[ "$fail" = 0 ] && echo PASS || { tail -5 "$work/recorder.log"; exit 1; }
