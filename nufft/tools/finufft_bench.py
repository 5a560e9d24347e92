#!/usr/bin/env python3
"""Time FINUFFT's type-1 transform on the same cases as nufft/examples/nufft_bench.rs.

Usage: OMP_NUM_THREADS=1 python3 nufft/tools/finufft_bench.py [--json] [--runs R]
           [--case 2d-65536,2d-4096,3d-4096] [--tols 1e-6,1e-12] [--ref-dir DIR]

Points are uniform in [0,1)^D from SplitMix64 with seed 42, bit-identical to the
Rust example, scaled to [0, 2*pi) for FINUFFT. Weights are 1. For every case and
tolerance it reports the median over R >= 7 runs of
  - exec_ms:   plan.setpts + plan.execute on a reusable finufft.Plan
               (the counterpart of our Plan::transform, which also sorts points),
  - simple_ms: one call of finufft.nufft2d1 / nufft3d1 (includes planning),
with isign = -1, eps = tol, nthreads = 1, default modeord (-K..K) and default
upsampfac. If --ref-dir holds <case>.re/.im (raw little-endian f64 half-grid
reference written by `nufft_bench --ref-dir`), FINUFFT's relative l2 error on
the half grid (j0 in [0,K]) is reported too.
"""
import argparse
import json
import os
import statistics
import sys
import time

import numpy as np

os.environ.setdefault("OMP_NUM_THREADS", "1")
import finufft  # noqa: E402

CASES = {"2d-65536": (2, 65536, 128), "2d-4096": (2, 4096, 319), "3d-4096": (3, 4096, 32)}


def splitmix_uniforms(seed, count):
    """SplitMix64 stream, (z >> 11) / 2^53, identical to the Rust example."""
    with np.errstate(over="ignore"):
        i = np.arange(1, count + 1, dtype=np.uint64)
        s = np.uint64(seed) + i * np.uint64(0x9E3779B97F4A7C15)
        z = s
        z = (z ^ (z >> np.uint64(30))) * np.uint64(0xBF58476D1CE4E5B9)
        z = (z ^ (z >> np.uint64(27))) * np.uint64(0x94D049BB133111EB)
        z = z ^ (z >> np.uint64(31))
    return (z >> np.uint64(11)).astype(np.float64) / float(1 << 53)


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--json", action="store_true")
    ap.add_argument("--runs", type=int, default=9)
    ap.add_argument("--case", default=",".join(CASES))
    ap.add_argument("--tols", default=",".join(f"1e-{e}" for e in range(3, 13)))
    ap.add_argument("--ref-dir", default=None)
    a = ap.parse_args()
    runs = max(a.runs, 1)
    tols = [float(t) for t in a.tols.split(",")]
    if not a.json:
        print(f"finufft {finufft.__version__}, OMP_NUM_THREADS={os.environ.get('OMP_NUM_THREADS')}")
    for name in a.case.split(","):
        d, npts, k = CASES[name]
        u = splitmix_uniforms(42, npts * d).reshape(npts, d)
        xs = [np.ascontiguousarray(2.0 * np.pi * u[:, i]) for i in range(d)]
        c = np.ones(npts, dtype=np.complex128)
        m = 2 * k + 1
        shape = (m,) * d
        ref = None
        if a.ref_dir:
            pr = os.path.join(a.ref_dir, name + ".re")
            if os.path.exists(pr):
                ref = np.fromfile(pr, dtype="<f8") + 1j * np.fromfile(
                    os.path.join(a.ref_dir, name + ".im"), dtype="<f8")
        if not a.json:
            print(f"\n== {name}: D={d} N={npts} K={k}")
            print(f"{'tol':>7} {'exec_ms':>9} {'simple_ms':>10} {'rel_l2':>10}")
        simple = finufft.nufft2d1 if d == 2 else finufft.nufft3d1
        for tol in tols:
            plan = finufft.Plan(1, shape, n_trans=1, eps=tol, isign=-1, nthreads=1)
            plan.setpts(*xs)
            f = plan.execute(c)  # warm-up
            times = []
            for _ in range(runs):
                t0 = time.perf_counter()
                plan.setpts(*xs)
                f = plan.execute(c)
                times.append((time.perf_counter() - t0) * 1e3)
            stimes = []
            for _ in range(runs):
                t0 = time.perf_counter()
                simple(*xs, c, shape, eps=tol, isign=-1, nthreads=1)
                stimes.append((time.perf_counter() - t0) * 1e3)
            rel = float("nan")
            if ref is not None:
                half = f[k:].ravel()
                rel = float(np.linalg.norm(half - ref) / np.linalg.norm(ref))
            ex, si = statistics.median(times), statistics.median(stimes)
            if a.json:
                print(json.dumps({"case": name, "tol": tol, "exec_ms": ex,
                                  "simple_ms": si, "rel_l2": rel}))
            else:
                print(f"{tol:>7.0e} {ex:>9.3f} {si:>10.3f} {rel:>10.2e}")
            sys.stdout.flush()


if __name__ == "__main__":
    main()
