#!/usr/bin/env bash
# Installs the Debian packages the project builds and runs with. Idempotent: packages already present are
# not touched, and apt is only called when something is missing. Needs root (or sudo) for the install.
set -euo pipefail

PACKAGES=(
  build-essential cmake            # C++17 toolchain and build
  libfastrtps-dev libfastcdr-dev   # Fast DDS 2.9 and its CDR serialisation
  fastddsgen fastdds-tools         # IDL code generator (build time) and the fastdds CLI (shm clean)
  libeigen3-dev                    # estimation core
  libspdlog-dev                    # service logging
  libgtest-dev libbenchmark-dev    # tests and benchmarks
  libcli11-dev                     # command-line parsing with a truthful --help
  libyaml-cpp-dev                  # parameter files
  zlib1g-dev                       # gzip-compressed embedded snapshots
  gnuplot-nox                      # causal-report's plots
  graphviz                         # causal-report's causal graph (dot places edge labels without overlap)
  libmicrohttpd-dev                # the HTTP server of twin-web and the /metrics endpoints (common/http): bounded connections (total, per address), header bytes, idle time
  prometheus-cpp-dev               # metrics registry and text exposition (prometheus-cpp 1.0, "core")
  prometheus curl                  # metrics test: a real Prometheus scrapes the running pipeline; promtool lints
  iproute2                         # network-namespace tests (ip netns)
  nlohmann-json3-dev               # twin-web's JSON
  libjs-chart.js                   # twin-web's trend charts, served from /usr/share/javascript (no CDN)
  chromium fonts-dejavu-core       # the browser test (ctest -L browser): headless Chromium, a font to render
  nodejs                           # the browser test's driver: Node >= 20 with npm (as on the build image), runs playwright-core
  openssl libssl-dev               # DDS-Security: the PKI scripts (deploy/security) and the credential checks
  dpkg-dev file                    # cpack -G DEB: dpkg-shlibdeps derives the package's Depends from the binaries
  help2man                         # the package's manual pages, made at build time from each command's --help
  lintian                          # the package test: Debian's package checker must report no error
  systemd adduser                  # the package test: systemd-analyze verify on the units; the postinst's adduser
  libmosquitto-dev mosquitto mosquitto-clients  # sensor-ingest's MQTT source; the broker and mosquitto_pub for its tests
  passwd util-linux time           # cross-user fault test: useradd/userdel and runuser (a second Linux user); bench_transport.sh's CPU times
  python3-minimal                  # tests/security/ingest_hardening.sh: UDP datagrams from a chosen source address
  libsqlite3-dev sqlite3           # the historian's default database (common/history) and the sqlite3 CLI its tests and docs query with
  libpq-dev postgresql             # the historian's PostgreSQL backend (libpq); PostgreSQL 15 server + psql for its tests (started by the test)
)

missing=()
for p in "${PACKAGES[@]}"; do
  dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed" || missing+=("$p")
done
if [ ${#missing[@]} -eq 0 ]; then
  echo "install_deps: all ${#PACKAGES[@]} packages present"
  exit 0
fi
SUDO=""
[ "$(id -u)" -ne 0 ] && SUDO="sudo"
echo "install_deps: installing ${missing[*]}"
$SUDO apt-get update -qq
DEBIAN_FRONTEND=noninteractive $SUDO apt-get install -y -qq --no-install-recommends "${missing[@]}"
