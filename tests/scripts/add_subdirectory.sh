#!/usr/bin/env bash
# osplint built inside another CMake project: the C++ example consumer
# (examples/consumers/cpp) with -DOSPLINT_SOURCE_DIR, which adds osplint's
# source tree with add_subdirectory() and links osplint::osplint_static. The
# outer project must configure without osplint's test dependencies, generate
# the rule list and the embedded files under osplint's own binary directory,
# build, and report what `osplint check` reports.
set -euo pipefail
osplint=${1:?usage: add_subdirectory.sh path/to/build/osplint}
build=$(cd "$(dirname "$osplint")" && pwd)
src=$(pwd)
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
fail=0

# The compiler cache of the main build, if it has one, serves this build too.
launcher=$(sed -n 's/^CMAKE_CXX_COMPILER_LAUNCHER:[A-Z]*=//p' "$build/CMakeCache.txt")
outer=$tmp/outer
if ! cmake -S "$src/examples/consumers/cpp" -B "$outer" -G Ninja -DOSPLINT_SOURCE_DIR="$src" -DOSPLINT_STATIC=ON \
  -DCMAKE_CXX_COMPILER_LAUNCHER="$launcher" -DCMAKE_C_COMPILER_LAUNCHER="$launcher" >"$tmp/configure.log" 2>&1; then
  echo "not ok: the outer project does not configure"
  tail -30 "$tmp/configure.log"
  exit 1
fi
echo "ok: the outer project configures"
if ! grep -q '^OSPLINT_RULE(OSP104)$' "$outer/osplint/generated/rules_list.inc"; then
  echo "not ok: the rule list under osplint's binary directory does not list OSP104"
  fail=1
fi
if [[ -e $outer/generated ]]; then
  echo "not ok: osplint generated files into the outer project's binary directory"
  fail=1
fi
if ! cmake --build "$outer" -j "$(nproc)" >"$tmp/build.log" 2>&1; then
  echo "not ok: the outer project does not build"
  grep -E 'error|Error' "$tmp/build.log" | head -20
  exit 1
fi
echo "ok: the outer project builds"

programs=("$src/examples/mistakes/M52CALL.MIN" "$src/examples/mistakes/ZTRAVEL.MIN")
expected=$("$osplint" check --format gcc -j 1 "${programs[@]}" | sed 's/: note: /: info: /' || true)
status=0
out=$("$outer/check_programs" "${programs[@]}") || status=$?
if [[ $status -ne 1 || $out != "$expected" || -z $out ]]; then
  echo "not ok: the outer project's program reports (exit code $status):"
  diff <(echo "$expected") <(echo "$out") | head -10
  fail=1
else
  echo "ok: the outer project's program reports what osplint check reports ($(wc -l <<<"$out") findings)"
fi
exit $fail
