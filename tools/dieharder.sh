#!/usr/bin/env bash
# Statistical battery for the pattern generator (linesample::rng::Counter):
# its raw 32-bit output stream, piped into Debian's dieharder (`apt install
# dieharder`), all tests (-a) with the defaults, reading stdin as raw binary
# (-g 200). Prints dieharder's table; the summary line at the end counts
# PASSED / WEAK / FAILED and gives the smallest and largest p-values.
#
#   tools/dieharder.sh [SEED] [PURPOSE] [FIRST]      (defaults: 1, Random's, 0)
#
# A full run reads tens of GB and takes about an hour on one core.
set -euo pipefail
cd "$(dirname "$0")/.."
command -v dieharder >/dev/null || { echo "dieharder.sh: install dieharder (apt install dieharder)" >&2; exit 2; }
cargo build --release --example counter_stream -q
log=$(mktemp)
target/release/examples/counter_stream "$@" | dieharder -a -g 200 -Y 1 | tee "$log"
# Columns: test_name | ntup | tsamples | psamples | p-value | Assessment.
awk -F'|' '/PASSED|WEAK|FAILED/ {
    a = $6; gsub(/ /, "", a); n[a]++; p = $5 + 0
    if (min == "" || p < min) { min = p; mint = $1 "|" $2 }
    if (max == "" || p > max) { max = p; maxt = $1 "|" $2 }
} END {
    printf "summary: %d PASSED, %d WEAK, %d FAILED; smallest p %.8f (%s), largest p %.8f (%s)\n",
        n["PASSED"], n["WEAK"], n["FAILED"], min, mint, max, maxt
}' "$log"
rm -f "$log"
