#!/usr/bin/env bash
# A private PostgreSQL 15 server for one test: initdb in a temporary folder, listening only on a unix socket in
# that folder (no TCP port, nothing shared with another test or a system server), stopped and removed again.
#   postgres_server.sh start DIR   -> prints the libpq URL (postgresql:///postgres?host=DIR/socket&port=PORT&user=...)
#   postgres_server.sh stop DIR    -> stops the server and removes DIR
# Exit 77 when PostgreSQL 15 is not installed (deploy/install_deps.sh installs it): callers skip, or fail where
# CAUSAL_TWIN_REQUIRE_ALL=1. As root the server runs as the user postgres (PostgreSQL refuses to run as root).
set -euo pipefail
bin=/usr/lib/postgresql/15/bin
cmd="${1:?start|stop}"; dir="${2:?DIR}"
as_owner() {
  if [ "$(id -u)" = 0 ]; then runuser -u postgres -- "$@"; else "$@"; fi
}
case "$cmd" in
  start)
    [ -x "$bin/initdb" ] && [ -x "$bin/pg_ctl" ] || { echo "no PostgreSQL 15 at $bin" >&2; exit 77; }
    if [ "$(id -u)" = 0 ] && ! id postgres > /dev/null 2>&1; then echo "no user postgres" >&2; exit 77; fi
    mkdir -p "$dir/socket"
    [ "$(id -u)" = 0 ] && chown -R postgres "$dir"
    user="$(if [ "$(id -u)" = 0 ]; then echo postgres; else id -un; fi)"
    as_owner "$bin/initdb" -D "$dir/data" -U "$user" -A trust --no-sync > "$dir/initdb.log" 2>&1 ||
      { cat "$dir/initdb.log" >&2; exit 1; }
    # A port number only names the socket file (no TCP: listen_addresses ''); any free-looking one will do.
    port=$(( 20000 + RANDOM % 20000 ))
    as_owner "$bin/pg_ctl" -D "$dir/data" -l "$dir/server.log" -w -t 60 \
      -o "-c listen_addresses='' -k $dir/socket -p $port -c fsync=off" start > /dev/null ||
      { cat "$dir/server.log" >&2; exit 1; }
    echo "postgresql:///postgres?host=$dir/socket&port=$port&user=$user"
    ;;
  stop)
    [ -d "$dir/data" ] && as_owner "$bin/pg_ctl" -D "$dir/data" -m immediate -w stop > /dev/null 2>&1 || true
    rm -rf "$dir"
    ;;
  *) echo "postgres_server.sh: start|stop DIR" >&2; exit 2 ;;
esac
