#!/usr/bin/env bash
# Fuzzing on the stable toolchain: libFuzzer (through the libfuzzer-sys crate) with
# SanitizerCoverage switched on by stable `-C` flags, the same instrumentation cargo-fuzz uses
# minus AddressSanitizer (which needs nightly; the code under test is safe Rust, so a panic,
# an overflow (overflow checks on), a stack overflow or a hang is what there is to find).
#
#   bash scripts/fuzz.sh [SECONDS_PER_TARGET] [TARGET...]
#
# Targets (fuzz/fuzz_targets/): cone, topp, scene, urdf, motion, args, meshes. Each runs SECONDS (default 60)
# from its committed corpus (in CI, from a sample of it: see below) (fuzz/corpus/TARGET, kept small: new inputs go to a scratch
# directory, then only those that add coverage are merged back). A crash leaves its input in
# fuzz/artifacts/TARGET/ and the script fails; turn it into a named regression test.
set -euo pipefail
cd "$(dirname "$0")/../fuzz"
seconds="${1:-60}"
shift || true
targets=("$@")
[ ${#targets[@]} -gt 0 ] || targets=(cone topp scene urdf motion args meshes)
triple="$(rustc -vV | sed -n 's/^host: //p')"
# libfuzzer-sys compiles libFuzzer (C++).
if ! command -v c++ >/dev/null && command -v apt-get >/dev/null; then
    apt-get update -qq && apt-get install -y -qq g++ >/dev/null
fi
export RUSTFLAGS="-Cpasses=sancov-module -Cllvm-args=-sanitizer-coverage-level=4 \
-Cllvm-args=-sanitizer-coverage-inline-8bit-counters -Cllvm-args=-sanitizer-coverage-pc-table \
-Cllvm-args=-sanitizer-coverage-trace-compares --cfg fuzzing -Cdebug-assertions -Coverflow-checks"
# --target: the flags then apply to the fuzz targets only, not to build scripts.
cargo build --release --bins --target "$triple"
bin="target/$triple/release"
for t in "${targets[@]}"; do
    mkdir -p "corpus/$t" "artifacts/$t" "scratch/$t"
    echo "== fuzz $t for ${seconds}s"
    # In CI the run starts from an evenly spaced sample of the corpus (every k-th file in name
    # order, at most 150): libFuzzer first replays every input it is given, and replaying the
    # whole corpus of the slow targets (scene: about 40 ms an input) took minutes of CI's budget.
    seeds=("corpus/$t")
    if [ "${CI:-}" = true ]; then
        files=(corpus/"$t"/*)
        k=$(( (${#files[@]} + 149) / 150 ))
        for ((i = 0; i < ${#files[@]}; i += k)); do cp "${files[i]}" "scratch/$t/"; done
        seeds=()
    fi
    "$bin/$t" "scratch/$t" "${seeds[@]}" -max_total_time="$seconds" -max_len=4096 \
        -rss_limit_mb=4096 -timeout=10 -artifact_prefix="artifacts/$t/" -print_final_stats=1 \
        2>&1 | grep -E "^(#[0-9]+ *DONE|Done|stat::number_of_executed_units|stat::peak_rss)|ERROR|panicked|SUMMARY" || true
    if ls "artifacts/$t"/* >/dev/null 2>&1; then
        echo "fuzz $t: crash inputs in fuzz/artifacts/$t/" >&2
        exit 1
    fi
    # Keep the committed corpus minimal: merge in only the inputs that add coverage. Not in CI,
    # which commits nothing (the merge replays the whole corpus: minutes on the slow targets).
    if [ "${CI:-}" != true ]; then
        "$bin/$t" -merge=1 "corpus/$t" "scratch/$t" >/dev/null 2>&1
    fi
    rm -rf "scratch/$t"
done
