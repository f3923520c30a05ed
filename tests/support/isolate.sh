#!/usr/bin/env bash
# Runs a command in a private network + mount namespace with its own /dev/shm and loopback, so DDS tests of
# several developers on this machine (same domain ids, same shared-memory port files) cannot see each other.
# Usage (root): tests/support/isolate.sh COMMAND [ARGS...], e.g. tests/support/isolate.sh ctest --test-dir build -R foo
# (no network to the outside inside: the browser test's first npm ci needs one run outside).
set -euo pipefail
exec unshare --net --mount --propagation private -- bash -c '
  mount -t tmpfs -o size=4g tmpfs /dev/shm
  mkdir -p /run/netns && mount -t tmpfs tmpfs /run/netns
  ip link set lo up
  exec "$@"' isolate "$@"
