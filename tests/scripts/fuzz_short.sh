#!/usr/bin/env bash
# The differential fuzzer (fuzz/diff_fuzz.cpp: both front ends, the outline
# and the engine against the reference analysis) on a fixed set of inputs:
# the repository's programs, the inputs that once diverged (fuzz/regressions)
# and mutants of the programs written by fuzz/mutants.py from a fixed seed.
# Fails on any crash or divergence. The same inputs on every machine and with
# every build: a run of libFuzzer's own mutations depends on the binary's
# coverage, so it belongs to exploration (fuzz/run.sh), not to a test.
# The fuzzer is built once into build-fuzz/ (clang, libFuzzer, ASan, UBSan)
# and only relinked later. $1 (the osplint binary) is not used.
# OSPLINT_FUZZ_MUTANTS (default 5000) and OSPLINT_FUZZ_SEED (default 1) ask
# for another set, e.g. a longer search before a release:
#     OSPLINT_FUZZ_SEED=7 OSPLINT_FUZZ_MUTANTS=50000 tests/scripts/fuzz_short.sh
set -uo pipefail
root=$(cd "$(dirname "$0")/../.." && pwd)
if ! command -v clang++ >/dev/null || ! echo 'int main(){}' | clang++ -x c++ -fsanitize=fuzzer-no-link - -o /dev/null 2>/dev/null; then
  echo "not ok: clang++ with libFuzzer is not available (scripts/deps.sh installs clang and libclang-rt-14-dev)"
  exit 1
fi
log=$(mktemp)
work=$(mktemp -d)
trap 'rm -rf "$log" "$work"' EXIT
count=${OSPLINT_FUZZ_MUTANTS:-5000}
seed=${OSPLINT_FUZZ_SEED:-1}
if ! python3 "$root/fuzz/mutants.py" --dict "$root/fuzz/osp.dict" --out "$work/mutants" --count "$count" --seed "$seed" \
  "$root/tests/programs" "$root/examples" "$root/tests/rules" "$root/tests/frontend"; then
  echo "not ok: fuzz/mutants.py failed"
  exit 1
fi
# -runs=0: every input is run once, none derived from it. An empty corpus, so
# that what a long exploration left in build-fuzz/corpus is not replayed.
mkdir -p "$work/corpus"
OSPLINT_FUZZ_CORPUS=$work/corpus "$root/fuzz/run.sh" -runs=0 "$work/mutants" >"$log" 2>&1
status=$?
grep -E "INITED|stat::number_of_executed_units|stat::peak_rss_mb|DIVERGENCE|ERROR:" "$log" | head -20
if ((status != 0)); then
  echo "not ok: the fuzzer stopped with status $status"
  tail -80 "$log"
  exit 1
fi
ran=$(sed -n 's/^stat::number_of_executed_units: *//p' "$log")
if [[ -z $ran ]] || ((ran < count)); then
  echo "not ok: the fuzzer ran ${ran:-no} inputs, fewer than the $count mutants"
  tail -20 "$log"
  exit 1
fi
echo "ok: $ran inputs, no crash and no divergence"
