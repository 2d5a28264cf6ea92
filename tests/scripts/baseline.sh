#!/usr/bin/env bash
# Baselines: --write-baseline records today's findings; --baseline reports only
# new ones, after unrelated edits above the findings and from any directory.
set -uo pipefail
osplint=$(realpath "$1")
examples=$(realpath examples/mistakes)
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
failures=0
pass() { echo "ok: $1"; }
fail() { echo "not ok: $1"; failures=$((failures + 1)); }

mkdir -p "$work/repo/progs" "$work/elsewhere"
cp "$examples"/*.MIN "$work/repo/progs/"
cd "$work/repo"

before=$("$osplint" check --format gcc --fail-on never progs/ | wc -l)
((before > 10)) && pass "the copied programs have findings ($before)" || fail "the copied programs have findings ($before)"

"$osplint" check --write-baseline .osplint-baseline.json progs/ >"$work/out" 2>"$work/err"
rc=$?
[[ $rc == 0 ]] && pass "--write-baseline exits 0" || fail "--write-baseline exits 0 (got $rc)"
grep -q "recorded $before findings in .osplint-baseline.json" "$work/err" && pass "--write-baseline says what it recorded" ||
  fail "--write-baseline says what it recorded: $(cat "$work/err")"
node -e '
const b = JSON.parse(require("fs").readFileSync(".osplint-baseline.json", "utf8"));
const ok = b.version === 1 && b.tool.name === "osplint" && typeof b.tool.version === "string" &&
  b.entries.length === Number(process.argv[1]) &&
  b.entries.every(e => e.path.startsWith("progs/") && /^OSP[0-9]{3}$/.test(e.rule) && /^[0-9a-f]{16}$/.test(e.fingerprint));
process.exit(ok ? 0 : 1);' "$before" && pass "baseline format: version, tool, relative paths, rule, fingerprint" ||
  fail "baseline format: $(head -c 400 .osplint-baseline.json)"

out=$("$osplint" check --format gcc --baseline .osplint-baseline.json progs/)
rc=$?
[[ $rc == 0 && -z "$out" ]] && pass "unchanged files: nothing reported, exit 0" || fail "unchanged files: exit $rc, $out"

# Unrelated edits above the findings: a comment line at the top of every file,
# a blank line and a comment after the program name.
for f in progs/*.MIN; do
  { echo "(REVISION B - REVIEWED 2024-05-02)"; sed '0,/^O[0-9A-Z]*/s//&\n\n(SETUP SHEET 12)/' "$f"; } >"$f.new" && mv "$f.new" "$f"
done
head -3 progs/M52CALL.MIN | grep -q "REVISION B" && pass "files were shifted" || fail "files were shifted"
out=$("$osplint" check --format gcc --baseline .osplint-baseline.json progs/)
rc=$?
[[ $rc == 0 && -z "$out" ]] && pass "shifted files: old findings stay hidden, exit 0" ||
  fail "shifted files: exit $rc, $(head -5 <<<"$out")"

# The same from another directory: baseline paths are relative to the baseline file.
out=$(cd "$work/elsewhere" && "$osplint" check --format gcc --baseline ../repo/.osplint-baseline.json ../repo/progs/)
rc=$?
[[ $rc == 0 && -z "$out" ]] && pass "from another directory: still hidden" || fail "from another directory: exit $rc, $(head -3 <<<"$out")"
out=$(cd / && "$osplint" check --format gcc --baseline "$work/repo/.osplint-baseline.json" "$work/repo/progs/")
[[ -z "$out" ]] && pass "with absolute paths: still hidden" || fail "with absolute paths: $(head -3 <<<"$out")"

# The baselined findings are still listed as suppressed in JSON.
n=$("$osplint" check --format json --baseline .osplint-baseline.json progs/ |
  node -e 'const j = JSON.parse(require("fs").readFileSync(0, "utf8"));
    console.log(j.files.flatMap(f => f.suppressed).filter(s => s.suppression.kind === "baseline").length);')
[[ "$n" == "$before" ]] && pass "json lists the $n baselined findings as suppressed" || fail "json lists baselined findings ($n of $before)"

# A new mistake: only it is reported.
sed -i 's/^M30$/CALL OZAGR PX=1. PY=2. PR=5. PZ=-29. PI=6. PF=50 PS=600 M52\nM30/' progs/VC120.MIN
out=$("$osplint" check --format gcc --baseline .osplint-baseline.json progs/)
rc=$?
lines=$(grep -c . <<<"$out")
[[ $rc == 1 && $lines == 1 && "$out" == progs/VC120.MIN:*"[OSP104]" ]] && pass "a new mistake is the only finding, exit 1" ||
  fail "a new mistake is the only finding: exit $rc, $out"

# A second identical mistake in the same program is new too (occurrence counts).
sed -i 's/^M30$/CALL OZAGR PX=1. PY=2. PR=5. PZ=-29. PI=6. PF=50 PS=600 M52\nM30/' progs/M52CALL.MIN
before_m52=$(grep -c "M52 (expect" progs/M52CALL.MIN)
out=$("$osplint" check --format gcc --baseline .osplint-baseline.json progs/M52CALL.MIN)
[[ $(grep -c "OSP104" <<<"$out") == 1 ]] && pass "a repeated mistake in a baselined file is reported once ($before_m52 old)" ||
  fail "a repeated mistake in a baselined file: $out"

if ((failures)); then
  echo "$failures baseline check(s) failed"
  exit 1
fi
echo "all baseline checks passed"
