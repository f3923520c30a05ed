#!/usr/bin/env bash
# The main job on a fresh machine: install dependencies, build, run the three services on the embedded
# IMS slice over a private loopback DDS domain. Extra arguments go to deploy/launch.sh.
set -euo pipefail
root="$(cd "$(dirname "$0")/.." && pwd)"
"$root/deploy/install_deps.sh"
"$root/deploy/build.sh"
exec "$root/deploy/launch.sh" "$@"
