#!/usr/bin/env bash
# One manual page from a tool's --help (help2man), as the package installs it: section 1, gzip -9n.
#   make_man_page.sh TOOL_PATH NAME "SHORT DESCRIPTION" VERSION SOURCE_DIR BUILD_DIR OUT.1.gz
# Run at build time on the build-tree binary, whose --help names the source tree's files as its defaults; the
# page states what an installed binary finds instead (/etc/causal-twin, /usr/share/causal-twin). A source or
# build path left in the page fails the build: a manual page never names the machine it was built on.
set -euo pipefail
tool="$1"; name="$2"; description="$3"; version="$4"; src="$5"; build="$6"; out="$7"
tmp="$(mktemp -d)"
trap 'rm -rf "$tmp"' EXIT
# help2man runs `NAME --help`; a wrapper of that name runs the tool (argv[0] = NAME, so the usage line names the
# installed command) and rewrites the source tree's defaults to what an installed binary finds.
cat > "$tmp/$name" <<WRAPPER
#!/usr/bin/env bash
set -o pipefail
( exec -a "$name" "$(realpath "$tool")" "\$@" ) 2>&1 | sed -e "s|$src/deploy/dds/|/etc/causal-twin/|g" \
  -e "s|$src/deploy/config/|/etc/causal-twin/|g" -e "s|$src/deploy/|/usr/share/causal-twin/|g" \
  -e "s|(from the source tree (build-tree binary))|(from /etc/causal-twin)|g"
WRAPPER
chmod +x "$tmp/$name"
# The environment of an installed service: no profile or domain from the caller's shell.
env -u FASTRTPS_DEFAULT_PROFILES_FILE -u CAUSAL_TWIN_DOMAIN_ID -u CAUSAL_TWIN_DDS_DIR -u CAUSAL_TWIN_CONFIG_DIR \
  -u CAUSAL_TWIN_SECURITY_DIR -u CAUSAL_TWIN_BUILD_DIR COLUMNS=100 \
  help2man --no-info --no-discard-stderr --version-string="$version" --name="$description" \
  --source="Causal Digital Twin" --section=1 --output="$tmp/page.1" "$tmp/$name"
# help2man writes "-" as "\-": look for the paths in both spellings.
sed -e 's|\\-|-|g' -e "s|$tmp/||g" "$tmp/page.1" > "$tmp/plain.1"
sed -e "s|$tmp/||g" "$tmp/page.1" > "$tmp/page.fixed.1"
for leak in "$src" "$build" "$tmp"; do
  if grep -qF "$leak" "$tmp/plain.1"; then
    grep -nF "$leak" "$tmp/plain.1" >&2
    echo "make_man_page.sh: the page of $name names $leak" >&2
    exit 1
  fi
done
gzip -9n -c "$tmp/page.fixed.1" > "$out"
