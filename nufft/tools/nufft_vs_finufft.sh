#!/usr/bin/env bash
# Side-by-side timing of linesample-nufft's type-1 NUFFT and FINUFFT (Python
# wheel, single thread) on identical point sets, in one run.
#
#   nufft/tools/nufft_vs_finufft.sh [--runs R] [--tols 1e-6,1e-12] [--case 2d-65536,...]
#
# Needs: cargo, python3 with numpy and finufft (pip install finufft).
# Prints our table (with errors against the exact direct sum), FINUFFT's
# (with its error against the same reference), then the ratio
# our_median / finufft_median per case and tolerance, where FINUFFT's time is
# setpts + execute on a reusable plan (our transform also bins the points).
# Our σ is the automatic choice given the number of points
# (Plan::new_for_points).
set -euo pipefail
# Runs from the repository root (the workspace target directory is there).
cd "$(dirname "$0")/../.."

runs=9
tols="1e-3,1e-4,1e-5,1e-6,1e-7,1e-8,1e-9,1e-10,1e-11,1e-12"
cases="2d-65536,2d-4096,3d-4096"
while [ $# -gt 0 ]; do
  case "$1" in
    --runs) runs="$2"; shift 2 ;;
    --tols) tols="$2"; shift 2 ;;
    --case) cases="$2"; shift 2 ;;
    *) echo "unknown argument $1" >&2; exit 2 ;;
  esac
done

export OMP_NUM_THREADS=1
tmp="$(mktemp -d)"
trap 'rm -rf "$tmp"' EXIT

cargo build --release -q -p linesample-nufft --example nufft_bench
bin=target/release/examples/nufft_bench
common=(--runs "$runs" --tols "$tols" --case "$cases")
"$bin" "${common[@]}" --sigma auto --json --ref-dir "$tmp" > "$tmp/ours.jsonl"
python3 nufft/tools/finufft_bench.py "${common[@]}" --json --ref-dir "$tmp" > "$tmp/finufft.jsonl"

python3 - "$tmp/ours.jsonl" "$tmp/finufft.jsonl" <<'EOF'
import json, sys
ours = [json.loads(l) for l in open(sys.argv[1]) if l.strip()]
fin = {(r["case"], r["tol"]): r for r in map(json.loads, filter(str.strip, open(sys.argv[2])))}
hdr = f"{'case':>9} {'tol':>6} {'sigma':>5} {'w':>3} {'n':>5} {'ours_ms':>8} {'(spr/fft/dec)':>20} {'ours_err':>9} {'fin_ms':>8} {'fin_simple':>10} {'fin_err':>9} {'ratio':>6}"
print(hdr)
for r in ours:
    f = fin[(r["case"], r["tol"])]
    split = f"{r['spread_ms']:.2f}/{r['fft_ms']:.2f}/{r['deconv_ms']:.2f}"
    print(f"{r['case']:>9} {r['tol']:>6.0e} {r['sigma']:>5} {r['w']:>3} {r['n']:>5} {r['median_ms']:>8.3f} {split:>20} "
          f"{r['rel_l2']:>9.2e} {f['exec_ms']:>8.3f} {f['simple_ms']:>10.3f} {f['rel_l2']:>9.2e} {r['median_ms'] / f['exec_ms']:>6.2f}")
EOF
