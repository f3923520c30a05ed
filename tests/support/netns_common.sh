# Shared parts of the multi-host tests (sourced, not run): test hosts are network namespaces this process
# creates and removes. Gives
#   work      a temp dir (removed at exit),   pids  background processes (SIGTERM + wait at exit),
#   netns_create NS        a namespace with lo up, deleted at exit (its veths with it),
#   netns_host_start NS CMD  start CMD in the background in NS (its pid: netns_last_pid, and in pids) with the
#                          host's own /dev/shm (a private tmpfs folder, so Fast DDS shared memory stays between
#                          the services of one test host, as on separate hosts, and its files go away at exit
#                          even after a crash); redirect its output on the call,
# and exits 77 (skipped) without permission to create namespaces, 1 (failed) under deploy/test.sh
# (CAUSAL_TWIN_REQUIRE_ALL: CI is root, so there a multi-host test that cannot run is a failure).
if [ "$(id -u)" -ne 0 ] || ! ip netns add "ctprobe$$" 2>/dev/null; then
  if [ -n "${CAUSAL_TWIN_REQUIRE_ALL:-}" ]; then
    echo "FAIL: creating network namespaces needs root (CAP_NET_ADMIN); deploy/test.sh requires it"; exit 1
  fi
  echo "SKIP: creating network namespaces needs root (CAP_NET_ADMIN)"; exit 77
fi
ip netns del "ctprobe$$"

work="$(mktemp -d)"
netns_shm_root="$(mktemp -d /dev/shm/causal_netns.XXXXXX)"
pids=()
netns_created=()
netns_cleanup() {
  local p ns
  for p in "${pids[@]}"; do kill -TERM "$p" 2>/dev/null; done
  for p in "${pids[@]}"; do wait "$p" 2>/dev/null; done
  for ns in "${netns_created[@]}"; do ip netns del "$ns" 2>/dev/null; done  # removes their veths too
  rm -rf "$netns_shm_root"
  if [ -n "${KEEP_NETNS_WORK:-}" ]; then echo "kept $work (KEEP_NETNS_WORK)"; else rm -rf "$work"; fi
}
trap netns_cleanup EXIT

netns_create() {  # $1 = namespace name
  ip netns add "$1" || { echo "FAIL: cannot create namespace $1"; exit 1; }
  netns_created+=("$1")
  ip -n "$1" link set lo up
}

netns_host_start() {  # $1 = namespace, then the command; `ip netns exec` gives it its own (slave) mount table
  local ns="$1"; shift
  mkdir -p "$netns_shm_root/$ns"
  # exec all the way down, so the pid is the service's own and SIGTERM at clean-up reaches it.
  ( exec ip netns exec "$ns" sh -c 'mount --bind "$0" /dev/shm && exec "$@"' "$netns_shm_root/$ns" "$@" ) &
  netns_last_pid=$!
  pids+=("$netns_last_pid")
}
