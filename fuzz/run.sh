#!/usr/bin/env bash
# Builds the differential fuzzer (fuzz/diff_fuzz.cpp) with clang, libFuzzer,
# AddressSanitizer and UndefinedBehaviorSanitizer, and runs it on the program
# corpus. Extra arguments go to libFuzzer, e.g.
#
#     fuzz/run.sh -max_total_time=600
#     fuzz/run.sh -runs=100000 -jobs=2
#
# The build (and the corpus the fuzzer grows) lives in $OSPLINT_FUZZ_DIR,
# default build-fuzz/ at the top of the repository; a second run only relinks.
# $OSPLINT_FUZZ_CORPUS names another corpus directory (default DIR/corpus).
# Exit status: 0 when the run ends without a crash or divergence.
set -euo pipefail
root=$(cd "$(dirname "$0")/.." && pwd)
dir=${OSPLINT_FUZZ_DIR:-$root/build-fuzz}
jobs=${OSPLINT_FUZZ_BUILD_JOBS:-2}
command -v clang++ >/dev/null || { echo "fuzz/run.sh: clang++ is required" >&2; exit 3; }

mkdir -p "$dir"
# The library, instrumented for coverage and built with the sanitizers, and
# the target (CMake option OSPLINT_FUZZ).
if [[ ! -f "$dir/core/build.ninja" ]]; then
  cmake -S "$root" -B "$dir/core" -G Ninja -DCMAKE_BUILD_TYPE=RelWithDebInfo \
    -DCMAKE_C_COMPILER=clang -DCMAKE_CXX_COMPILER=clang++ -DOSPLINT_SANITIZE=ON -DOSPLINT_FUZZ=ON \
    -DCMAKE_C_FLAGS=-fsanitize=fuzzer-no-link -DCMAKE_CXX_FLAGS=-fsanitize=fuzzer-no-link >/dev/null
fi
# Quiet when the build succeeds; its output when it fails, which would otherwise
# leave only a bare exit status behind.
if ! build_log=$(ninja -C "$dir/core" -j "$jobs" diff_fuzz 2>&1); then
  echo "fuzz/run.sh: building the fuzzer failed:" >&2
  echo "$build_log" | grep -E "error|FAILED" | head -40 >&2
  exit 4
fi
target="$dir/core/diff_fuzz"

# Seeds: every program of the repository (small ones), as they are, and the
# inputs that once made the front ends or the engine diverge (fuzz/regressions).
seeds="$dir/seeds"
corpus=${OSPLINT_FUZZ_CORPUS:-$dir/corpus}
rm -rf "$seeds"  # the programs as they are now, none left from an earlier checkout
mkdir -p "$seeds" "$corpus"
find "$root/tests/programs" "$root/examples" "$root/tests/rules" "$root/tests/frontend" -type f \
  \( -iname '*.MIN' -o -iname '*.SSB' -o -iname '*.SUB' -o -iname '*.LIB' -o -iname '*.NC' -o -iname '*.SDF' \) \
  -size -64k -print0 | xargs -0 -I{} cp -f {} "$seeds/" 2>/dev/null || true

cd "$dir"
exec "$target" -dict="$root/fuzz/osp.dict" -max_len=4096 -timeout=20 -rss_limit_mb=2048 \
  -print_final_stats=1 "$@" "$corpus" "$seeds" "$root/fuzz/regressions"
