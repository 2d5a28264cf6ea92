#!/usr/bin/env bash
# -j N: a generated repository of 1,000 small programs gives byte-identical
# reports with -j 1, -j 2 and the default; the progress line appears only on a
# terminal.
set -uo pipefail
osplint=$(realpath "$1")
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
failures=0
pass() { echo "ok: $1"; }
fail() { echo "not ok: $1"; failures=$((failures + 1)); }

# Sources: the examples and the rule fixtures (program files only).
mapfile -t sources < <(find examples tests/rules -type f \( -name '*.MIN' -o -name '*.SSB' \) | sort)
((${#sources[@]} > 20)) || { echo "not enough source programs"; exit 1; }

# 1,000 programs in 20 directories, each a perturbed copy: a header comment,
# shifted numbers on some lines, an extra block, sometimes a suppression or a
# syntax error; every fifth directory has its own osplint.toml.
gen="$work/gen"
for i in $(seq 0 999); do
  src=${sources[$((i % ${#sources[@]}))]}
  dir="$gen/cell$((i % 20))"
  mkdir -p "$dir"
  ext=MIN
  [[ $src == *.SSB ]] && ext=SSB
  out="$dir/P$(printf '%04d' "$i").$ext"
  {
    echo "(GENERATED COPY $i OF $src)"
    case $((i % 4)) in
      0) cat "$src" ;;
      1) sed -E "s/X([0-9]+)\./X\1$((i % 7))./" "$src" ;;
      2) sed -E "0,/^(M30|M02)$/s//G0 X$i. Y-$((i % 13)).\n&/" "$src" ;;
      3) sed -E "s/ M52\$/ M52 (osplint: disable=OSP104 -- generated $i)/; 3s/\$/ (osplint: disable=OSP9$((i % 10))1)/" "$src" ;;
    esac
    ((i % 37 == 0)) && echo "G1 X XPOS+$i F300"
  } >"$out"
done
for c in 0 5 10 15; do cp examples/osplint.toml "$gen/cell$c/osplint.toml"; done
count=$(find "$gen" -name 'P*' | wc -l)
[[ $count == 1000 ]] && pass "generated 1000 programs" || fail "generated 1000 programs ($count)"

for fmt in json text sarif gcc github; do
  "$osplint" check --format "$fmt" --fail-on never -j 1 "$gen" >"$work/j1.$fmt" 2>"$work/j1.$fmt.err"
  rc1=$?
  "$osplint" check --format "$fmt" --fail-on never -j 2 "$gen" >"$work/j2.$fmt" 2>"$work/j2.$fmt.err"
  rc2=$?
  if [[ $rc1 == 0 && $rc2 == 0 ]] && cmp -s "$work/j1.$fmt" "$work/j2.$fmt" && cmp -s "$work/j1.$fmt.err" "$work/j2.$fmt.err"; then
    pass "$fmt: -j 2 output is byte-identical to -j 1 ($(wc -c <"$work/j1.$fmt") bytes)"
  else
    fail "$fmt: -j 2 differs from -j 1 (exit $rc1/$rc2)"
    diff "$work/j1.$fmt" "$work/j2.$fmt" | head -10
  fi
done
"$osplint" check --format json --fail-on never "$gen" >"$work/jd.json"
cmp -s "$work/j1.json" "$work/jd.json" && pass "json: default -j is byte-identical to -j 1" ||
  fail "json: default -j differs from -j 1"
"$osplint" check --format json --fail-on never -j 7 "$gen" >"$work/j7.json"
cmp -s "$work/j1.json" "$work/j7.json" && pass "json: -j 7 is byte-identical to -j 1" || fail "json: -j 7 differs"

# The report covers every file, in path order, with findings and suppressions.
node -e '
const j = JSON.parse(require("fs").readFileSync(process.argv[1], "utf8"));
const paths = j.files.map(f => f.path);
const sorted = [...paths].sort();
const ok = j.files.length === 1000 && paths.every((p, i) => p === sorted[i]) &&
  j.summary.error > 0 && j.summary.suppressed > 0;
if (!ok) { console.log(j.files.length, j.summary); process.exit(1); }' "$work/j1.json" &&
  pass "json: 1000 files in path order, with findings and suppressed findings" || fail "json: files, order or findings"

# Progress: never when stderr is not a terminal; on a terminal for long runs.
grep -q "checked" "$work/j2.json.err" && fail "no progress line when stderr is not a terminal" ||
  pass "no progress line when stderr is not a terminal"
if command -v script >/dev/null; then
  script -qec "$osplint check --format json --fail-on never -j 2 $gen >/dev/null" /dev/null >"$work/tty.log" 2>&1
  grep -q "checked .*/1000 files" "$work/tty.log" && pass "progress line on a terminal" ||
    fail "progress line on a terminal: $(head -c 200 "$work/tty.log")"
fi

if ((failures)); then
  echo "$failures parallel check(s) failed"
  exit 1
fi
echo "all parallel checks passed"
