#!/usr/bin/env bash
# Prognosis evaluation (docs/prognosis.md): time to 2x / 4x the baseline and to the end of life (6x),
# predicted by the twin's prognosis (causal_prognosis, the code alarm-recommender runs) beside two anchors
# (log-linear Theil-Sen with bootstrap intervals; random walk with drift, inverse-Gaussian first passage), at
# every snapshot from the first alarm on; the event: the first snapshot whose trailing 5-snapshot median
# reaches the multiple of the baseline (the stop when never reached):
#   1. IMS test 2, bearing 1 (meanabs; stop at snapshot 981);
#   2. simulated run-to-failure channels with known crossing times (accelerating wear, recording gaps, level
#      steps, Gaussian and uniform noise, spikes), SEEDS seeds per noise kind: seeds 1.. (the ones the
#      parameters were chosen on) and 101.. (held out).
# Usage: tests/bench/prognosis_eval.sh [BUILD_DIR] [SEEDS]   (defaults: build, 20). Prints the tables (also the
# long-run and conformal rows; what a choice among them could reach: tests/bench/prognosis_trace_bounds.py).
set -euo pipefail
root="$(cd "$(dirname "$0")/../.." && pwd)"
build="${1:-$root/build}"
seeds="${2:-20}"
tool="$build/tools/causal_prognosis_eval/causal-prognosis-eval"
[ -x "$tool" ] || { echo "no $tool: build the target causal-prognosis-eval first" >&2; exit 2; }
"$tool" --ims "$root/deploy/data/ims2-features/merged_dataset_BearingTest_2.csv" --feature-name "" --channel 1 --stop-index 981
echo
"$tool" --sim --seeds "$seeds"
echo
"$tool" --sim --seeds "$seeds" --first-seed 101
