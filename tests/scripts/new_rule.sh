#!/usr/bin/env bash
# tools/new-rule in a copy of the tree (the files git tracks or would track,
# as they are now): the rule it writes builds, `osplint rules` lists it, and
# its fixtures, snapshots and doc page pass the rule's tests, run with one
# command; a broken snapshot of it fails them. A whole build of the copy:
# the compiler cache of the main build (CMAKE_CXX_COMPILER_LAUNCHER), with
# paths taken relative to the copy, makes the next run of this test fast.
set -uo pipefail
osplint=${1:?usage: new_rule.sh path/to/build/osplint}
build=$(cd "$(dirname "$osplint")" && pwd)
src=$(pwd)
source "$src/tests/scripts/lib/common.bash"

if ! git -C "$src" rev-parse --git-dir >/dev/null 2>&1; then
  echo "skip: the tree is not a git checkout (the copy is made of the files git tracks)"
  exit 77
fi
copy=$tmp/osplint
mkdir "$copy"
(cd "$src" && git ls-files -z --cached --others --exclude-standard |
  while IFS= read -r -d '' f; do [[ -e $f ]] && printf '%s\0' "$f"; done |
  xargs -0 cp --parents -t "$copy")
ok "the tree is copied ($(find "$copy" -type f | wc -l) files)"

launcher=$(sed -n 's/^CMAKE_CXX_COMPILER_LAUNCHER:[A-Z]*=//p' "$build/CMakeCache.txt")
if [[ $launcher == *ccache* ]]; then
  export CCACHE_BASEDIR=$copy
fi
if command -v ninja >/dev/null; then
  export CMAKE_GENERATOR=Ninja
fi
export OSPLINT_BUILD_DIR=$copy/build-dev
cd "$copy" || exit 1

# The ID tools/new-rule must pick: one past the highest of the range.
last=$(ls rules docs/rules tests/rules | grep -o 'OSP3[0-9][0-9]' | sort -u | tail -1)
id=$(printf 'OSP3%02d' $((10#${last:4:2} + 1)))

if ! tools/new-rule sample-check --range 3 >"$tmp/new-rule.log" 2>&1; then
  not_ok "tools/new-rule sample-check --range 3 fails"
  tail -30 "$tmp/new-rule.log"
  exit 1
fi
if grep -q "^new-rule: $id sample-check$" "$tmp/new-rule.log"; then
  ok "tools/new-rule picks $id, the next ID of the range"
else
  not_ok "tools/new-rule does not pick $id:"
  head -3 "$tmp/new-rule.log"
fi
grep -q "^Next:" "$tmp/new-rule.log" && ok "it prints the next steps" || not_ok "it prints no next steps"
for f in "rules/${id}_sample_check.cpp" "docs/rules/$id.md" "tests/rules/$id/fires.MIN" "tests/rules/$id/near_miss.MIN" \
  "tests/rules/$id/fires.MIN.snap" "tests/rules/$id/near_miss.MIN.snap"; do
  [[ -s $f ]] && ok "it writes $f" || not_ok "it does not write $f"
done
if grep -q "^$id sample-check warning" "tests/rules/$id/fires.MIN.snap" &&
  grep -q "^(no findings)$" "tests/rules/$id/near_miss.MIN.snap"; then
  ok "the snapshots hold the findings on fires.MIN and none on near_miss.MIN"
else
  not_ok "the snapshots are not what the rule finds:"
  cat "tests/rules/$id/fires.MIN.snap" "tests/rules/$id/near_miss.MIN.snap"
fi

osplint=$OSPLINT_BUILD_DIR/osplint
expect "osplint rules lists $id" 0 "^$id +sample-check " -- rules
expect "osplint check --select $id reports it on fires.MIN" 1 "fires.MIN:3:1: warning: .*\[$id\]" -- \
  check --select "$id" --format gcc "tests/rules/$id/fires.MIN"

if grep -q "\"$id\"" schema/osplint.schema.json && grep -q '"sample-check"' schema/osplint.schema.json &&
  tools/update-schema --check "$osplint" >/dev/null 2>&1; then
  ok "the configuration schema offers $id and sample-check in [rules]"
else
  not_ok "the configuration schema does not offer $id, or is out of date"
fi

# The rule's tests, with one command: its fixtures, snapshots, doc page.
run_rule_tests() { OSPLINT_ONLY_RULE=$id "$OSPLINT_BUILD_DIR/osplint_tests" --test-case='every rule*' 2>&1; }
if out=$(run_rule_tests); then
  ok "the tests of $id pass ($(grep -o 'test cases: *[0-9]* | *[0-9]* passed' <<<"$out"))"
else
  not_ok "the tests of $id fail:"
  tail -30 <<<"$out"
fi
cp "tests/rules/$id/fires.MIN.snap" "$tmp/snap"
sed -i 's/warning 3:1-/error 3:1-/' "tests/rules/$id/fires.MIN.snap"
if out=$(run_rule_tests); then
  not_ok "the tests of $id pass with a wrong snapshot"
elif grep -q "tests/rules/$id/fires.MIN.snap does not match" <<<"$out" && grep -q "^-$id sample-check error" <<<"$out"; then
  ok "a wrong snapshot fails the tests with a diff naming the file"
else
  not_ok "a wrong snapshot fails the tests without saying where:"
  tail -20 <<<"$out"
fi
cp "$tmp/snap" "tests/rules/$id/fires.MIN.snap"

# IDs are not taken twice, nor names.
if tools/new-rule sample-check --range 3 --no-snapshots >"$tmp/again.log" 2>&1; then
  not_ok "tools/new-rule takes a name already used"
else
  ok "tools/new-rule refuses a name already used"
fi
next=$(printf 'OSP3%02d' $((10#${id:4:2} + 1)))
if tools/new-rule other-check --range 3 --no-snapshots >"$tmp/other.log" 2>&1 &&
  grep -q "^new-rule: $next other-check$" "$tmp/other.log"; then
  ok "the next rule of the range gets $next"
else
  not_ok "the next rule of the range does not get $next:"
  head -5 "$tmp/other.log"
fi
exit $fail
