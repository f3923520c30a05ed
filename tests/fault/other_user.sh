# The second Linux user of the cross-user fault tests (sourced): ctwin-other, created when missing. Root only:
# without it need_other_user skips the test (exit 77). made_user=1 when it was made here, so that the caller's
# clean-up removes it again; the caller defines fail() first.
other=ctwin-other
made_user=0
need_other_user() {
  [ "$(id -u)" = 0 ] || { echo "SKIP: needs root to create a second user"; exit 77; }
  if ! id "$other" >/dev/null 2>&1; then
    useradd --system --no-create-home --shell /usr/sbin/nologin "$other" || fail "useradd $other"
    made_user=1
  fi
}
