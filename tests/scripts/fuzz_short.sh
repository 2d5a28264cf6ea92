#!/usr/bin/env bash
# A short run of the differential fuzzer (fuzz/diff_fuzz.cpp): the tree-sitter
# and the streaming front ends on the program corpus and on what libFuzzer
# derives from it; fails on any crash or divergence. The fuzzer is built once
# into build-fuzz/ (clang, libFuzzer, ASan, UBSan) and only relinked later.
# $1 (the osplint binary) is not used.
set -uo pipefail
if ! command -v clang++ >/dev/null || ! echo 'int main(){}' | clang++ -x c++ -fsanitize=fuzzer-no-link - -o /dev/null 2>/dev/null; then
  echo "not ok: clang++ with libFuzzer is not available (scripts/deps.sh installs clang and libclang-rt-14-dev)"
  exit 1
fi
log=$(mktemp)
corpus=$(mktemp -d)
trap 'rm -rf "$log" "$corpus"' EXIT
# A fresh corpus grown from the repository's programs (the one fuzz/run.sh keeps
# for long runs grows without bound). A fixed number of runs from a fixed seed:
# every machine tries the same inputs, however fast it is.
OSPLINT_FUZZ_CORPUS=$corpus fuzz/run.sh -runs="${OSPLINT_FUZZ_RUNS:-2500}" -max_total_time=900 -seed=1 >"$log" 2>&1
status=$?
grep -E "^#[0-9]+ +DONE|stat::number_of_executed_units|stat::peak_rss_mb|DIVERGENCE|ERROR:" "$log" | head -20
if ((status != 0)); then
  echo "not ok: the fuzzer stopped with status $status"
  tail -60 "$log"
  exit 1
fi
echo "ok: no crash and no divergence"
