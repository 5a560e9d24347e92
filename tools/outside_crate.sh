#!/usr/bin/env bash
# The embedding example as a renderer's own crate sees it: `examples/render`
# compiled as the binary of a new crate outside this repository, which depends
# on `linesample` by path with its default features, built with
# `cargo build --release` and no flags. Outside the repository, cargo does not
# read this repository's `.cargo/config.toml` (its x86-64-v3 flags), so the
# kernel is built for baseline x86-64 (SSE2, no FMA), as a dependent crate's is.
#
# It fails if
#   * the example does not compile against the public API (a missing
#     re-export, a renamed item);
#   * the binary calls a fused multiply-add routine (`libm`'s software `fma`,
#     or the C library's `fma`/`fmaf`): without the instruction that is a
#     software routine, the 35x slow default this check keeps out;
#   * the example does not run, or does not write its PNG.
# It prints the example's throughput and the SIMD level it ran at (a figure
# for the log; no timing is asserted).
#
# Usage: tools/outside_crate.sh [width height spp]   (default 320 180 4)
# Needs only cargo and binutils' `nm`. Takes about a minute on 2 cores.
set -euo pipefail
REPO="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
W="${1:-320}"
H="${2:-180}"
SPP="${3:-4}"

DIR="$(mktemp -d "${TMPDIR:-/tmp}/linesample-outside.XXXXXX")"
trap 'rm -rf "$DIR"' EXIT
case "$DIR" in
    "$REPO"/*)
        echo "error: the scratch crate $DIR is inside the repository; set TMPDIR elsewhere" >&2
        exit 1
        ;;
esac

# The example's other dependencies (its header lists them), at the versions
# the repository's own lock file resolved, so this build fetches nothing new.
locked() {
    awk -v n="$1" '$0 == "name = \"" n "\"" { getline; gsub(/"/, "", $3); print $3; exit }' "$REPO/Cargo.lock"
}
PNG_VERSION="$(locked png)"
LIBM_VERSION="$(locked libm)"
cat >"$DIR/Cargo.toml" <<EOF
[package]
name = "renderer"
version = "0.0.0"
edition = "2021"
publish = false

[dependencies]
linesample = { path = "$REPO" }
png = "=${PNG_VERSION}"
libm = "=${LIBM_VERSION}"

[[bin]]
name = "render"
path = "$REPO/examples/render/main.rs"

[workspace]
EOF

# No flags: the environment must not bring any either.
unset RUSTFLAGS CARGO_ENCODED_RUSTFLAGS CARGO_BUILD_RUSTFLAGS
echo "-- building examples/render as an outside crate ($DIR), default flags"
(cd "$DIR" && cargo build --release --quiet)
BIN="$DIR/target/release/render"

# Who calls a fused multiply-add routine. The C library's `fma`/`fmaf` (what
# `f64::mul_add` becomes without the instruction) must not be linked at all.
# `libm`'s `fma` may be called only from `linesample::num::dd`'s cold
# fallback `err_outside_dekker` (zeros, NaN, infinities, extreme exponents),
# directly or through the GOT.
if nm -D "$BIN" 2>/dev/null | grep -Eq '[[:space:]]U fmaf?(@|$)'; then
    echo "error: the default build links the C library's fma (f64::mul_add without the instruction)" >&2
    exit 1
fi
CALLERS="$(
    FMA_ADDR="$(nm "$BIN" | awk '$3 ~ /4libm4math3fma3fma17h/ { sub(/^0+/, "", $1); print $1 }')"
    if [ -n "$FMA_ADDR" ]; then
        GOT="$(readelf -rW "$BIN" | awk -v a="$FMA_ADDR" '$3 == "R_X86_64_RELATIVE" && $4 == a { sub(/^0+/, "", $1); print $1 }')"
        objdump -d --no-show-raw-insn -C "$BIN" | awk -v a="$FMA_ADDR" -v g="${GOT:-none}" '
            /^[0-9a-f]+ <.*>:$/ { fn = $0; sub(/^[0-9a-f]+ </, "", fn); sub(/>:$/, "", fn) }
            /(call|jmp)/ && (index($0, " " a " ") || index($0, "# " g " ")) { print fn }' | sort -u
    fi
)"
BAD="$(grep -v -E '^linesample::num::dd::err_outside_dekker$' <<<"$CALLERS" | grep -v '^$' || true)"
if [ -n "$BAD" ]; then
    echo "error: in the default build these functions call libm's software fma:" >&2
    echo "$BAD" >&2
    exit 1
fi
echo "-- fused multiply-add routine called only from: ${CALLERS:-nowhere}"

(cd "$DIR" && ./target/release/render out/render.png "$W" "$H" "$SPP")
test -s "$DIR/out/render.png"
