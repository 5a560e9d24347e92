#!/usr/bin/env bash
# Regression check for refactors of the lab: runs a fixed set of commands with
# two linesample-lab binaries and compares their outputs.
#
#   tools/lab_compare.sh OLD_BINARY NEW_BINARY [WORK_DIR]
#
# CSV tables and point files must be byte-identical (the gallery's index.csv
# without its timing column, median_us); PNG images must have identical pixels
# (compared through `convert FILE ppm:-` when ImageMagick's convert is
# installed; skipped otherwise). Plots (SVG) and manifests are not compared.
# Prints one line per differing file and a count; exits 1 if any differ.
set -uo pipefail
OLD=$(realpath "$1"); NEW=$(realpath "$2"); WORK=${3:-$(mktemp -d)}

capture() {
    local bin=$1 out=$2
    rm -rf "$out"; mkdir -p "$out"; cd "$out" || exit 2
    run() { "$bin" "$@" > /dev/null 2>> stderr.log || echo "FAILED: $*" >> cmds.log; }
    run
    for s in random jittered n-rooks sobol halton poisson-disk; do
        for d in 1 2 3; do run patterns --sampler $s --dims $d -n 64 --out pat/$s-$d; done
    done
    run patterns --sampler cmj -n 256 --seed 3 --realization 2 --shift --out pat/cmj
    run patterns --sampler multi-jittered --grid 16x4 --out pat/mj
    run patterns --sampler ccvt --dims 3 -n 128 --out pat/ccvt3
    run patterns --sampler jittered --strata 8,4 --out pat/jit84
    local c="convergence --realisations 200 --threads 2"
    run $c --n 16,64,256 --out conv/a
    run $c --integrand gaussian --sigma 0.05 --primitive segments --length 0.2 --sampler random --n 16,100 --out conv/b
    run $c --integrand ball --dims 3 --primitive lines --sampler sobol --n 16,64 --out conv/c
    run $c --integrand edge --primitive lines --direction 1,2 --sampler n-rooks --n 10,40 --out conv/d
    run $c --integrand gaussian --dims 3 --primitive segments --groups 3 --sampler poisson-disk --n 30,90 --out conv/e
    run $c --integrand disk --primitive lines --random-direction --sampler halton --n 8,32 --out conv/f
    run $c --integrand ball --dims 3 --sampler ccvt --n 32,64 --out conv/g
    run $c --integrand gaussian --dims 3 --primitive lines --groups 2 --sampler cmj --n 32,128 --seed 9 --out conv/h
    run $c --integrand edge --dims 3 --primitive points --sampler jittered --n 27,200 --out conv/i
    run spectrum --sampler jittered -n 256 --realizations 5 --threads 2 --out spec/a
    run spectrum --sampler random --dims 1 -n 100 --realizations 3 --out spec/b
    run spectrum --sampler sobol --dims 3 -n 128 --k 10 --realizations 3 --out spec/c
    run spectrum --sampler poisson-disk -n 256 --realizations 4 --method nufft --tol 1e-6 --out spec/d
    run spectrum --sampler halton --dims 3 -n 64 --primitive lines --axis 1 --realizations 3 --out spec/e
    run spectrum --sampler cmj -n 64 --primitive segments --length 0.3 --direction 1,1 --realizations 3 --out spec/f
    run spectrum --sampler n-rooks -n 100 --primitive lines --realizations 40 --method nufft --out spec/g
    run spectrum --sampler ccvt -n 128 --realizations 2 --k 20 --out spec/h
    run spectrum --input pat/random-2.txt pat/sobol-2.txt pat/halton-2.txt --out spec/i
    run spectrum --sampler jittered -n 64 --realizations 70 --k 12 --out spec/j
}

capture "$OLD" "$WORK/old"
capture "$NEW" "$WORK/new"
cat "$WORK"/old/cmds.log "$WORK"/new/cmds.log 2>/dev/null
same=0; diff=0
cd "$WORK/old" || exit 2
for f in $(find . \( -name '*.csv' -o -name '*.txt' \) -not -path '*.state/*' | sort); do
    if [[ $f == */index.csv ]]; then
        cmp -s <(cut -d, -f1-4,6- "$f") <(cut -d, -f1-4,6- "$WORK/new/$f")
    else
        cmp -s "$f" "$WORK/new/$f"
    fi && same=$((same + 1)) || { echo "differs: $f"; diff=$((diff + 1)); }
done
if command -v convert > /dev/null; then
    for f in $(find . -name '*.png' | sort); do
        cmp -s <(convert "$f" ppm:- 2>/dev/null) <(convert "$WORK/new/$f" ppm:- 2>/dev/null) \
            && same=$((same + 1)) || { echo "differs: $f"; diff=$((diff + 1)); }
    done
else
    echo "convert (ImageMagick) not found: PNG pixels not compared"
fi
echo "identical: $same, different: $diff (outputs in $WORK)"
[ "$diff" -eq 0 ]
