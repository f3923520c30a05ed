# Sourced by the bench scripts (deploy/bench_closed_loop.sh, deploy/bench_transport.sh, tests/bench/*.sh): their
# command line, declared rather than parsed by hand in each.
#   parse_options SCRIPT HELP_LINES SPEC... -- "$@"
# SPEC is --name=VAR (the option takes a value, stored in VAR) or --name+VAR (a flag: VAR=1). -h/--help prints
# lines HELP_LINES (sed range, e.g. 2,13) of SCRIPT and exits 0; an unknown option or a missing value exits 2
# naming the option.
parse_options() {
  local script="$1" help="$2" me spec found
  me="$(basename "$script")"
  shift 2
  local specs=()
  while [ $# -gt 0 ] && [ "$1" != -- ]; do specs+=("$1"); shift; done
  [ $# -gt 0 ] && shift  # the --
  while [ $# -gt 0 ]; do
    case "$1" in -h|--help) sed -n "${help}p" "$script"; exit 0 ;; esac
    found=0
    for spec in "${specs[@]}"; do
      case "$spec" in
        "$1="*)
          [ $# -ge 2 ] || { echo "$me: $1 needs a value" >&2; exit 2; }
          printf -v "${spec#*=}" '%s' "$2"
          shift
          found=1 ;;
        "$1+"*) printf -v "${spec#*+}" '%s' 1; found=1 ;;
      esac
      [ "$found" = 1 ] && break
    done
    [ "$found" = 1 ] || { echo "$me: unknown option $1" >&2; exit 2; }
    shift
  done
}
