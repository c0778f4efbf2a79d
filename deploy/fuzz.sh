#!/usr/bin/env bash
# Fuzzes lpss's input decoders with libFuzzer (clang from Debian): the scene loader and validation, a
# client's command as the coordinator checks it, and sequences of sector samples as a reader decodes,
# checks, orders and applies them (tests/fuzz).
# usage: deploy/fuzz.sh [RUNS]   (inputs per target; default 1000000). Builds build-fuzz/ with clang,
# AddressSanitizer and UBSan. A crash leaves its input in build-fuzz/crash-* and exits non-zero; make it a
# regression test (a file in tests/fuzz/regressions/TARGET/, which every run replays first).
set -euo pipefail
root="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
runs=${1:-1000000}
build=${LPSS_FUZZ_BUILD:-$root/build-fuzz}
mkdir -p "$build"
CC=clang CXX=clang++ cmake -S "$root" -B "$build" -DLPSS_FUZZ=ON -DCMAKE_BUILD_TYPE=RelWithDebInfo \
    >"$build/configure.log" 2>&1 || { cat "$build/configure.log"; exit 1; }
cmake --build "$build" -j2 --target lpss_fuzz_scene lpss_fuzz_sector_frames lpss_fuzz_command lpss_fuzz_seeds \
    >"$build/build.log" 2>&1 || { tail -40 "$build/build.log"; exit 1; }
status=0
for target in scene command sector_frames; do
    corpus=$(mktemp -d)
    seeds=$(mktemp -d)
    case $target in
    scene) cp "$root"/deploy/scenes/*.textproto "$seeds/" ;;
    *) "$build/tests/fuzz/lpss_fuzz_seeds" "$target" "$seeds" ;;
    esac
    regressions="$root/tests/fuzz/regressions/$target"
    [[ -d "$regressions" ]] || regressions=""
    start=$(date +%s.%N)
    if ! "$build/tests/fuzz/lpss_fuzz_$target" -runs="$runs" -max_len=65536 -rss_limit_mb=2048 -timeout=10 \
        -artifact_prefix="$build/crash-$target-" -print_final_stats=1 "$corpus" "$seeds" $regressions \
        >"$build/fuzz-$target.log" 2>&1; then
        tail -40 "$build/fuzz-$target.log"
        echo "lpss: fuzz target $target failed: see $build/fuzz-$target.log and $build/crash-$target-*"
        status=1
    fi
    end=$(date +%s.%N)
    done_line=$(grep -E "^Done [0-9]+ runs" "$build/fuzz-$target.log" | tail -1 || true)
    cov=$(grep -E "^#[0-9]+.*(DONE|pulse|NEW)" "$build/fuzz-$target.log" | tail -1 | grep -oE "cov: [0-9]+ ft: [0-9]+" || true)
    printf 'lpss: fuzz %s: %s (%s; %.0f s wall)\n' "$target" "${done_line:-no summary}" "${cov:-no coverage line}" \
        "$(awk -v a="$start" -v b="$end" 'BEGIN { print b - a }')"
    rm -rf "$corpus" "$seeds"
done
exit $status
