#!/usr/bin/env bash
# `osplint check --fix`, `--unsafe-fixes` and `--diff` on a copy of the
# examples: every safe-fixable finding disappears, nothing else changes (the
# other findings, byte for byte the files without fixes), the diff applies
# with patch and gives what --fix writes, a file with syntax errors or that
# changes while it is checked is never written, stdin gets the fixed program.
set -u
osplint=${1:?usage: fix.sh path/to/osplint}
osplint=$(cd "$(dirname "$osplint")" && pwd)/$(basename "$osplint")
source "$(dirname "${BASH_SOURCE[0]}")/lib/common.bash"
export NO_COLOR=1

# The findings of a tree as "path rule message" lines (sorted), from JSON.
findings() {
  (cd "$1" && "$osplint" check -j 1 --fold 0 --format json . 2>/dev/null) | python3 -c '
import json, sys
d = json.load(sys.stdin)
for f in d["files"]:
    for x in f["diagnostics"]:
        fx = "".join("safe" if y["safe"] else "unsafe" for y in x["fixes"][:1])
        print(f["path"], x["rule"], fx, x["message"])' | sort
}

mkdir -p "$tmp/orig"
cp -r examples/. "$tmp/orig/"
rm -rf "$tmp/orig/consumers"
before=$(findings "$tmp/orig")
safe=$(grep -c ' safe ' <<<"$before")
unsafe=$(grep -c ' unsafe ' <<<"$before")
[[ $safe -ge 2 && $unsafe -ge 1 ]] && ok "the examples have $safe safe and $unsafe unsafe fixes" ||
  not_ok "the examples should have safe and unsafe fixes ($safe, $unsafe)"

# The text summary says how many are fixable.
summary=$(cd "$tmp/orig" && "$osplint" check . | tail -n 1)
grep -q "$safe fixable with --fix ($unsafe more with --unsafe-fixes)" <<<"$summary" &&
  ok "summary: $summary" || not_ok "summary: $summary"

# --diff: changes nothing, exit 1, applies with patch.
cp -r "$tmp/orig" "$tmp/diffed"
(cd "$tmp/diffed" && "$osplint" check --diff . >"$tmp/fixes.diff" 2>"$tmp/diff.err")
status=$?
[[ $status -eq 1 ]] && ok "--diff exits 1 when there is something to fix" || not_ok "--diff exit code $status"
diff -r "$tmp/orig" "$tmp/diffed" >/dev/null && ok "--diff changes no file" || not_ok "--diff changed a file"
grep -q '^--- a/mistakes/M52CALL.MIN$' "$tmp/fixes.diff" && grep -q '^+CALL OZAGR .*PM=52' "$tmp/fixes.diff" &&
  ok "--diff shows the M52 fix" || not_ok "--diff: $(head -20 "$tmp/fixes.diff")"
grep -q 'G114G80' "$tmp/fixes.diff" && not_ok "--diff shows an unsafe fix without --unsafe-fixes" ||
  ok "--diff leaves the unsafe fix out"
(cd "$tmp/diffed" && patch -s -p1 <"$tmp/fixes.diff") && ok "the diff applies with patch -p1" ||
  not_ok "patch refused the diff"

# --fix: the same result as the patch; the safe findings are gone, the others stay.
cp -r "$tmp/orig" "$tmp/fixed"
(cd "$tmp/fixed" && "$osplint" check --fix . >"$tmp/fix.out" 2>"$tmp/fix.err")
status=$?
[[ $status -eq 1 ]] && ok "--fix exits 1: findings are left" || not_ok "--fix exit code $status"
grep -q "applied $safe fixes in" "$tmp/fix.err" && ok "--fix says what it applied" || not_ok "--fix: $(cat "$tmp/fix.err")"
diff -r "$tmp/diffed" "$tmp/fixed" >/dev/null && ok "--fix writes what the diff gives" ||
  not_ok "--fix and patch disagree: $(diff -r "$tmp/diffed" "$tmp/fixed" | head)"
after=$(findings "$tmp/fixed")
expected=$(grep -v ' safe ' <<<"$before")
[[ "$after" == "$expected" ]] && ok "after --fix: exactly the findings without a safe fix are left" ||
  not_ok "after --fix: $(diff <(echo "$expected") <(echo "$after"))"
changed=$(diff -rq "$tmp/orig" "$tmp/fixed" | awk '{print $2}' | sed "s|$tmp/orig/||" | sort)
with_fix=$(grep ' safe ' <<<"$before" | awk '{print $1}' | sed 's|^\./||' | sort -u)
[[ "$changed" == "$with_fix" ]] && ok "only the files with safe fixes changed ($(echo $changed))" ||
  not_ok "changed files: $changed; with fixes: $with_fix"
grep -q '^fix (unsafe): Replace G80 by M204' "$tmp/fix.out" || grep -q 'fix (unsafe): Replace G80' "$tmp/fix.out" &&
  ok "the report marks the unsafe fix" || not_ok "the report does not mark the unsafe fix"
"$osplint" check --fix "$tmp/fixed" >/dev/null 2>"$tmp/again.err"
grep -q "applied 0 fixes in 0 files" "$tmp/again.err" && ok "a second --fix has nothing left to do" ||
  not_ok "second --fix: $(cat "$tmp/again.err")"

# --unsafe-fixes: the G80 of the G114 mode becomes its cancel code.
cp -r "$tmp/orig" "$tmp/unsafe"
(cd "$tmp/unsafe" && "$osplint" check --fix --unsafe-fixes . >/dev/null 2>&1)
after=$(findings "$tmp/unsafe")
grep -qE ' (safe|unsafe) ' <<<"$after" && not_ok "--unsafe-fixes left fixable findings: $after" ||
  ok "--fix --unsafe-fixes leaves no fixable finding"
grep -q '^M204' "$tmp/unsafe/mistakes/G114G80.MIN" && ok "G80 replaced by M204" || not_ok "no M204 in G114G80.MIN"

# A file with syntax errors is not written, even with a fixable finding.
mkdir -p "$tmp/syntax"
printf 'O1000\nG15 H1\nCALL OZAGR PX=0 PY=0 PR=5. PZ=-29. PI=6. PF=50 PS=600 M52\nG0 X[[1\nM30\n' >"$tmp/syntax/BAD.MIN"
cp "$tmp/syntax/BAD.MIN" "$tmp/BAD.orig"
"$osplint" check --fix "$tmp/syntax/BAD.MIN" >/dev/null 2>"$tmp/syntax.err"
cmp -s "$tmp/syntax/BAD.MIN" "$tmp/BAD.orig" && grep -q 'not fixed: it has syntax errors' "$tmp/syntax.err" &&
  ok "a file with syntax errors is left as it is, and says why" || not_ok "syntax: $(cat "$tmp/syntax.err")"

# Standard input: the fixed program on stdout, the report on stderr.
out=$("$osplint" check --fix --stdin-filename M52.MIN - <"$tmp/orig/mistakes/M52CALL.MIN" 2>"$tmp/stdin.err")
grep -q 'PS=600 PM=52 (expect: OSP104)' <<<"$out" && ! grep -q 'M52 (expect' <<<"$out" &&
  ok "--fix - prints the fixed program" || not_ok "--fix -: $out"
[[ $(wc -l <<<"$out") -eq $(wc -l <"$tmp/orig/mistakes/M52CALL.MIN") ]] && ok "--fix - prints the whole program" ||
  not_ok "--fix - printed $(wc -l <<<"$out") lines"
grep -q 'in 1 file$' "$tmp/stdin.err" && ! grep -q 'in 1 file$' <<<"$out" &&
  ok "--fix -: the report goes to stderr" || not_ok "--fix -: no report on stderr"

# Through a symbolic link, the target is fixed and the link stays a link.
mkdir -p "$tmp/link"
cp "$tmp/orig/mistakes/M52CALL.MIN" "$tmp/link/REAL.MIN"
ln -s REAL.MIN "$tmp/link/LINK.MIN"
"$osplint" check --fix "$tmp/link/LINK.MIN" >/dev/null 2>&1
[[ -L "$tmp/link/LINK.MIN" ]] && grep -q 'PM=52' "$tmp/link/REAL.MIN" && ok "a link's target is fixed, the link kept" ||
  not_ok "symbolic link: $(ls -l "$tmp/link")"

# The permissions of a fixed file are kept; a read-only folder is an error (exit 2), the file unchanged.
chmod 640 "$tmp/link/REAL.MIN"
mkdir -p "$tmp/ro"
cp "$tmp/orig/mistakes/M52CALL.MIN" "$tmp/ro/A.MIN"
chmod 751 "$tmp/ro/A.MIN"
"$osplint" check --fix "$tmp/ro/A.MIN" >/dev/null 2>&1
[[ $(stat -c %a "$tmp/ro/A.MIN") == 751 ]] && ok "permissions kept" || not_ok "permissions: $(stat -c %a "$tmp/ro/A.MIN")"
if [[ $(id -u) -ne 0 ]]; then
  cp "$tmp/orig/mistakes/M52CALL.MIN" "$tmp/ro/B.MIN"
  chmod 555 "$tmp/ro"
  "$osplint" check --fix "$tmp/ro/B.MIN" >/dev/null 2>"$tmp/ro.err"
  status=$?
  chmod 755 "$tmp/ro"
  [[ $status -eq 2 ]] && cmp -s "$tmp/ro/B.MIN" "$tmp/orig/mistakes/M52CALL.MIN" &&
    ok "an unwritable folder: exit 2, the file unchanged" || not_ok "unwritable folder: $status $(cat "$tmp/ro.err")"
fi
ls -a "$tmp/ro" "$tmp/link" | grep -q '^\.A\.MIN\.\|^\.REAL' && not_ok "a temporary file was left behind" ||
  ok "no temporary file left behind"

# --diff takes no report options.
"$osplint" check --diff --format json "$tmp/orig" >/dev/null 2>&1
[[ $? -eq 2 ]] && ok "--diff --format json is a usage error" || not_ok "--diff --format json accepted"

exit $fail
