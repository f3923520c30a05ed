#!/usr/bin/env bash
# Runs inside a private mount namespace (test_package_deb.sh starts it with unshare -m): /usr, /etc and /var
# become copy-on-write overlays on a tmpfs, so the real dpkg -i / dpkg -P below change nothing outside this
# namespace; /dev/shm and /root are private. Then: install the .deb, check that a build-tree binary still reads
# its own source tree, hide the source and build trees under empty tmpfs mounts, run the installed binaries, the
# demo and the units' commands (as their own users, units_check.sh) from /, purge, and check that nothing is left
# but the CA keys' copy in /root.
#   package_root_check.sh WORK DEB DOMAIN BUILD_TREE_ESTIMATOR PREFIX_DIR HIDE_DIR...
# PREFIX_DIR: a `cmake --install --prefix` tree, run after the purge (no /etc/causal-twin then).
# Writes its results under WORK/installed_* and WORK/units_conditions.csv (WORK must not be under a hidden
# folder); exit 0 = all checks passed.
set -euo pipefail
work="$1"; deb="$2"; domain="$3"; build_estimator="$4"; prefix_dir="$5"; shift 5
fail() { echo "FAIL: $*" >&2; exit 1; }

mount --make-rprivate /
mkdir -p "$work/ov"
mount -t tmpfs tmpfs "$work/ov"
for d in usr etc var; do
  mkdir -p "$work/ov/$d/upper" "$work/ov/$d/work" "$work/ov/$d/lower"
  mount --bind "/$d" "$work/ov/$d/lower"  # the original, to compare with after the purge
  mount -t overlay overlay -o "lowerdir=/$d,upperdir=$work/ov/$d/upper,workdir=$work/ov/$d/work" "/$d"
done
mount -t tmpfs tmpfs /dev/shm
mount -t tmpfs -o mode=0700 tmpfs /root  # the purge keeps CA keys in /root/causal-twin-ca-keys.*: checked below

cd /
dev_deb=$(ls "$(dirname "$deb")"/causal-twin-dev_*.deb)
echo "--- dpkg -i $(basename "$deb") $(basename "$dev_deb")"
dpkg -i "$deb" "$dev_deb" > "$work/installed_dpkg_i.log" 2>&1 || { cat "$work/installed_dpkg_i.log"; fail "dpkg -i"; }
# One user per service, each in the group causal-twin (a unit reads only its own key and state).
services=(estimator ingest recommender recorder sensor web)
getent group causal-twin > /dev/null || fail "postinst made no group causal-twin"
for s in "${services[@]}"; do
  getent passwd "causal-twin-$s" > /dev/null || fail "postinst made no user causal-twin-$s"
  [ "$(id -gn "causal-twin-$s")" = causal-twin ] || fail "causal-twin-$s is not in the group causal-twin"
done
[ "$(stat -c '%U:%G %a' /var/lib/causal-twin)" = "root:causal-twin 750" ] \
  || fail "/var/lib/causal-twin is $(stat -c '%U:%G %a' /var/lib/causal-twin), not root:causal-twin 750"
echo "postinst: users ${services[*]/#/causal-twin-} in the group causal-twin; /var/lib/causal-twin root:causal-twin 0750"
listed=$(dpkg -L causal-twin causal-twin-dev)

echo "--- with the package installed, a build-tree binary still reads its own source tree"
# (--help captured first: grep -q ending the pipe early would fail it under pipefail)
help=$("$build_estimator" --help) || fail "build-tree causal-estimator --help exited non-zero"
qos_line=$(grep -m1 -o "default: [^ ]*qos.xml[^;]*" <<< "$help" || true)
grep -qF "qos.xml (from the source tree (build-tree binary))" <<< "$qos_line" \
  || fail "the build-tree causal-estimator does not take qos.xml from its source tree: $qos_line"
echo "$qos_line"

# From here on no source or build tree: a folder inside one hidden before (the build tree) is already gone.
for d in "$@"; do if [ -d "$d" ]; then mount -t tmpfs tmpfs "$d"; fi; done
for d in "$@"; do [ ! -d "$d" ] || [ -z "$(ls -A "$d")" ] || fail "$d still visible"; done

echo "--- causal-estimator --help from /"
help=$(causal-estimator --help) || fail "causal-estimator --help exited non-zero"
qos_line=$(grep -m1 -o "default: [^ ]*qos.xml[^;]*" <<< "$help" || true)
[ "$qos_line" = "default: /etc/causal-twin/qos.xml (from /etc/causal-twin)" ] || fail "--help: qos.xml not from /etc/causal-twin: $qos_line"
echo "$qos_line"

# The -dev package, the documentation and manual pages, and an example sensor built against the installed files.
bash "$work/dev_package_check.sh" "$work" "$domain"

echo "--- systemd-analyze verify"
units=(/usr/lib/systemd/system/causal-twin.target /usr/lib/systemd/system/causal-twin-*.service)
[ ${#units[@]} = 7 ] || fail "expected 7 units, found ${#units[@]}"
verify=$(systemd-analyze verify "${units[@]}" 2>&1) || { echo "$verify"; fail "systemd-analyze verify"; }
[ -z "$(grep -i causal-twin <<< "$verify" || true)" ] || { echo "$verify"; fail "systemd-analyze verify warned"; }
for u in "${units[@]}"; do
  grep -q '^Wants=network-online.target$' "$u" || fail "$u: After=network-online.target without Wants="
done
echo "7 units verified, each with Wants= beside After= for the network-online target"
# The environment files are systemd's format and also valid shell: a shell reads the same values.
for f in /etc/causal-twin/*.env; do
  while IFS= read -r line; do
    [[ "$line" =~ ^([A-Za-z_][A-Za-z0-9_]*)=(.*)$ ]] || continue
    key="${BASH_REMATCH[1]}"; value="${BASH_REMATCH[2]}"
    [[ "$value" =~ ^\"(.*)\"$ ]] && value="${BASH_REMATCH[1]}"
    shell_value=$(env -i bash -c "set -a; . '$f' && printf '%s' \"\${$key}\"") || fail "$f cannot be sourced by a shell"
    [ "$shell_value" = "$value" ] || fail "$f: $key is '$value' for systemd, '$shell_value' for a shell"
  done < "$f"
done
echo "$(ls /etc/causal-twin/*.env | wc -l) environment files: the same values for systemd and a shell"

echo "--- causal-twin-demo from / (the slice, domain $domain)"
timeout 120 causal-twin-demo --domain "$domain" --record "$work/installed_slice" > "$work/installed_slice.log" 2>&1 \
  || { tail -20 "$work/installed_slice.log"; fail "causal-twin-demo (slice) exited non-zero"; }
echo "--- causal-twin-demo from / (the 984-snapshot feature table, domain $domain)"
timeout 120 causal-twin-demo --domain "$domain" --features /usr/share/causal-twin/data/ims2-features/derived_per_file_stats_all984.csv \
  --feature-suffix _meanabs --feature-name meanabs --ask 3:-10 --record "$work/installed_features" \
  > "$work/installed_features.log" 2>&1 || { tail -20 "$work/installed_features.log"; fail "causal-twin-demo (features) exited non-zero"; }
# The demo wrote nothing under /usr (only the package's own files are in its upper layer).
extra=$(cd "$work/ov/usr/upper" && find . -type f | sed 's|^\.|/usr|' | grep -vxF -f <(echo "$listed") || true)
[ -z "$extra" ] || fail "written under /usr besides the package: $extra"

# The units as their own users, DDS-Security on, each with only its own key (units_check.sh).
bash "$work/units_check.sh" "$work" "$domain"

echo "--- dpkg -P causal-twin-dev causal-twin"
dpkg -P causal-twin-dev causal-twin > "$work/installed_dpkg_p.log" 2>&1 || { cat "$work/installed_dpkg_p.log"; fail "dpkg -P"; }
# Every path dpkg -L listed is gone, unless it existed before the install (a folder such as /usr/bin).
left=""
while read -r f; do
  top="${f#/}"; top="${top%%/*}"
  case "$top" in usr|etc|var) ;; *) continue ;; esac
  [ -e "$f" ] || [ -L "$f" ] || continue
  [ -d "$f" ] && [ -d "$work/ov/$top/lower${f#/$top}" ] && continue
  left+="$f "
done <<< "$listed"
[ -z "$left" ] || fail "left after purge: $left"
for p in /etc/causal-twin /var/lib/causal-twin /usr/share/causal-twin; do [ ! -e "$p" ] || fail "$p left after purge"; done
for s in "${services[@]}"; do ! getent passwd "causal-twin-$s" > /dev/null || fail "user causal-twin-$s left after purge"; done
[ -z "$(ls -d /etc/systemd/system/causal-twin-* 2>/dev/null)" ] || fail "left after purge: $(ls -d /etc/systemd/system/causal-twin-*)"
# The CA keys of the PKI made under /etc/causal-twin (units_check.sh) are kept for root, root-only.
kept=$(ls -d /root/causal-twin-ca-keys.*/private 2>/dev/null || true)
[ -n "$kept" ] && [ -f "$kept/identity_ca.key" ] && [ -f "$kept/permissions_ca.key" ] || fail "purge kept no CA keys in /root"
[ "$(stat -c '%U %a' "$(dirname "$kept")")" = "root 700" ] || fail "$(dirname "$kept") is not root 0700"
echo "purge: CA keys kept in $(dirname "$kept") (root 0700)"
# The recordings and the history database are plant data: kept (root 0700), then removed here for the comparison.
recs=$(ls -d /var/lib/causal-twin-recordings.* 2>/dev/null || true)
[ -n "$recs" ] && [ -f "$recs/history.db" ] && [ -f "$recs/conditions_ims2-shaft1_meanabs.csv" ] || fail "purge kept no recordings and history database"
[ "$(stat -c '%U %a' "$recs")" = "root 700" ] || fail "$recs is not root 0700"
[ "$(sqlite3 "$recs/history.db" 'SELECT COUNT(*) FROM condition_vectors')" -gt 0 ] || fail "the kept history database holds no condition vector"
echo "purge: recordings and history database kept in $recs (root 0700)"
rm -rf "$recs"
! getent group causal-twin > /dev/null || fail "group causal-twin left after purge"
# Every file the install touched is back as it was, except dpkg's own records and the account files' backups.
changed=""
for d in usr etc var; do
  while read -r f; do
    case "/$d/$f" in /var/lib/dpkg/*|/var/log/*|/var/cache/*|/etc/passwd-|/etc/group-|/etc/shadow-|/etc/gshadow-|/etc/subuid-|/etc/subgid-) continue ;; esac
    cmp -s "$work/ov/$d/upper/$f" "$work/ov/$d/lower/$f" || changed+="/$d/$f "
  done < <(cd "$work/ov/$d/upper" && find . -type f | sed 's|^\./||')
done
[ -z "$changed" ] || fail "changed after purge: $changed"
echo "purge: nothing left"

echo "--- an install into a separate prefix, from / with no source or build tree and no /etc/causal-twin"
help=$("$prefix_dir/bin/causal-estimator" --help) || fail "the prefix's causal-estimator --help exited non-zero"
qos_line=$(grep -m1 -o "default: [^ ]*qos.xml[^;]*" <<< "$help" || true)
[ "$qos_line" = "default: $prefix_dir/share/causal-twin/dds/qos.xml (from the installed defaults)" ] \
  || fail "the prefix's causal-estimator does not take qos.xml from $prefix_dir/share/causal-twin/dds: $qos_line"
echo "$qos_line"
timeout 120 "$prefix_dir/bin/causal-twin-demo" --domain "$domain" --record "$work/prefix_slice" > "$work/prefix_slice.log" 2>&1 \
  || { tail -20 "$work/prefix_slice.log"; fail "the prefix's causal-twin-demo exited non-zero"; }
echo "prefix demo: exit 0"
