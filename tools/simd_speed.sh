#!/usr/bin/env bash
# What a renderer's own build gets: the kernel's hot criterion benchmarks in
# three builds, in one run, with the ratios (README, "Build flags").
#
#   v3        this repository's flags (.cargo/config.toml: x86-64-v3, AVX2 + FMA)
#   default   a dependent crate's default flags (baseline x86-64, SSE2) with
#             the `std` feature, so the hot paths pick their AVX2 copy at run
#             time (linesample::simd)
#   compiled  the same binary with that turned off (LINESAMPLE_SIMD=compiled):
#             what a `no_std` build, or a CPU without AVX2, gets
#
# The benchmark binaries are dependent crates of the kernel built with
# cargo's release profile and no LTO, as a renderer's are. Medians of
# criterion's samples. Takes about 15 minutes on 2 cores (three builds, then
# about 30 benchmarks three times); run nothing else meanwhile.
#
# Usage: tools/simd_speed.sh [criterion filter regex]
set -euo pipefail
cd "$(dirname "${BASH_SOURCE[0]}")/.."

FILTER="${1:-^(patterns_[23]d_65536/[a-z-]+/simd|pmj_2d_4096/[a-z0-9]+/fill|direct_2d/n4096/k319|direct_3d/n4096/k32|direct_1d/n4096/k4096|segments_2d/n1024/k64|world .*/(f32 SIMD batch|f64 exact)/|(chord|gaussian) [23]D (lines|segments)/f32 SIMD batch|torus f64 .*/3D segment mean)}"
ARGS=(--warm-up-time 1 --measurement-time 3 --noplot)
BENCHES=(--bench patterns --bench pmj --bench spectrum --bench world --bench integrands)
SSE2_DIR=target/sse2-bench

echo "== building and running: v3 (repository flags)"
cargo bench -p linesample "${BENCHES[@]}" -- "${ARGS[@]}" --save-baseline v3 "$FILTER"
echo "== building and running: default flags, run-time dispatch"
RUSTFLAGS="-C target-cpu=x86-64" cargo bench -p linesample "${BENCHES[@]}" \
    --target-dir "$SSE2_DIR" -- "${ARGS[@]}" --save-baseline dispatch "$FILTER"
echo "== running: default flags, dispatch off (LINESAMPLE_SIMD=compiled)"
LINESAMPLE_SIMD=compiled RUSTFLAGS="-C target-cpu=x86-64" cargo bench -p linesample \
    "${BENCHES[@]}" --target-dir "$SSE2_DIR" -- "${ARGS[@]}" --save-baseline compiled "$FILTER"

# criterion writes every baseline under target/criterion (it does not see
# --target-dir), each under its own name.
python3 - "target/criterion" "target/criterion" <<'EOF'
import json, os, sys
v3_root, sse_root = sys.argv[1], sys.argv[2]
def medians(root, baseline):
    out = {}
    for d, _, files in os.walk(root):
        if os.path.basename(d) == baseline and "estimates.json" in files:
            bench = json.load(open(os.path.join(d, "benchmark.json")))
            est = json.load(open(os.path.join(d, "estimates.json")))
            out[bench["full_id"]] = est["median"]["point_estimate"]
    return out
v3 = medians(v3_root, "v3")
dis = medians(sse_root, "dispatch")
com = medians(sse_root, "compiled")
def fmt(ns):
    for unit, f in (("s", 1e9), ("ms", 1e6), ("µs", 1e3)):
        if ns >= f:
            return f"{ns / f:.3g} {unit}"
    return f"{ns:.3g} ns"
print("| benchmark | v3 | default (dispatch) | ÷ v3 | dispatch off | ÷ v3 |")
print("|---|---:|---:|---:|---:|---:|")
worst_d, worst_c = 0.0, 0.0
for k in sorted(v3):
    if k in dis and k in com:
        rd, rc = dis[k] / v3[k], com[k] / v3[k]
        worst_d, worst_c = max(worst_d, rd), max(worst_c, rc)
        print(f"| {k} | {fmt(v3[k])} | {fmt(dis[k])} | {rd:.2f} | {fmt(com[k])} | {rc:.2f} |")
print(f"\nworst ratio: default (dispatch) {worst_d:.2f}, dispatch off {worst_c:.2f}")
EOF
