#!/usr/bin/env bash
# The whole test suite on a fresh machine: install dependencies, build, run ctest (unit + integration).
# Tests that need the full data set run when ../shared/data/ims2 exists, and skip with a message otherwise.
set -euo pipefail
root="$(cd "$(dirname "$0")/.." && pwd)"
build="${CAUSAL_TWIN_BUILD_DIR:-$root/build}"
"$root/deploy/install_deps.sh"
"$root/deploy/build.sh"
# Everything install_deps.sh installed is required: tests that would skip without a tool fail instead.
export CAUSAL_TWIN_REQUIRE_ALL=1
status=0
ctest --test-dir "$build" --output-on-failure -j "${CAUSAL_TWIN_TEST_JOBS:-2}" --timeout 600 || status=$?
command -v fastdds >/dev/null && fastdds shm clean >/dev/null 2>&1 || true
exit $status
