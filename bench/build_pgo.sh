#!/usr/bin/env bash
# A profile-guided build of gonio for packagers (bench/RESULTS.md, 2026-12-06, fourth session:
# 5-13 % faster renders than the `dist` profile the benchmarks measure, the same images).
#
#   bench/build_pgo.sh            # writes $TARGET/pgo-use/dist/gonio and prints its path
#   .venv-mitsuba/bin/python bench/bench.py --gonio "$(bench/build_pgo.sh | tail -1)"
#
# Needs rustup's `llvm-tools` component (its llvm-profdata matches rustc's LLVM; installed here
# if missing). Trains on Mitsuba's documentation scenes (testdata/mitsuba-corpus/docs/scenes) at
# 2 samples per pixel and the built-in gallery, leaving out the three material previews the
# benchmark measures. Measured 6 min 14 s on 2 cores (two fat-LTO builds and the training).
set -euo pipefail
cd "$(dirname "$0")/.."
ROOT=$PWD
TARGET=${CARGO_TARGET_DIR:-target}
case $TARGET in /*) ;; *) TARGET=$ROOT/$TARGET ;; esac

SYSROOT=$(rustc --print sysroot)
HOST=$(rustc -vV | sed -n 's/^host: //p')
PROFDATA=$SYSROOT/lib/rustlib/$HOST/bin/llvm-profdata
if [ ! -x "$PROFDATA" ]; then
    rustup component add llvm-tools >&2
fi

DATA=$TARGET/pgo-data
rm -rf "$DATA"
mkdir -p "$DATA"

echo "# instrumented build" >&2
CARGO_TARGET_DIR=$TARGET/pgo-gen RUSTFLAGS="-Cprofile-generate=$DATA" \
    cargo build --profile dist -p gonio >&2
GEN=$TARGET/pgo-gen/dist/gonio

echo "# training" >&2
OUT=$(mktemp -d)
trap 'rm -rf "$OUT"' EXIT
for scene in testdata/mitsuba-corpus/docs/scenes/*.xml; do
    case $(basename "$scene" .xml) in
        bsdf_roughconductor_copper | bsdf_roughdielectric_glass | bsdf_roughplastic_ggx) continue ;;
    esac
    # Scenes gonio refuses (by design or for missing data) train nothing; that is fine.
    timeout 120 "$GEN" render "$scene" --spp 2 -q -o "$OUT/out.exr" >/dev/null 2>&1 || true
done
"$GEN" render --spp 4 -q -o "$OUT/gallery.exr" >/dev/null 2>&1

"$PROFDATA" merge -o "$DATA/merged.profdata" "$DATA"/*.profraw

echo "# optimized build" >&2
CARGO_TARGET_DIR=$TARGET/pgo-use RUSTFLAGS="-Cprofile-use=$DATA/merged.profdata" \
    cargo build --profile dist -p gonio >&2
echo "$TARGET/pgo-use/dist/gonio"
