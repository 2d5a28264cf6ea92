#!/usr/bin/env bash
# `osplint check` for CI: exit codes (--fail-on), gcc and github formats,
# --select/--ignore, --stdin-filename, suppressed findings in JSON.
set -uo pipefail
osplint=$(realpath "$1")
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
failures=0
pass() { echo "ok: $1"; }
fail() { echo "not ok: $1"; failures=$((failures + 1)); }
expect_eq() {  # NAME EXPECTED ACTUAL
  if [[ "$2" == "$3" ]]; then pass "$1"; else
    fail "$1"
    diff <(printf '%s\n' "$2") <(printf '%s\n' "$3") | head -20
  fi
}
run() {  # run ARGS... : sets out, err, rc
  out=$("$osplint" check "$@" 2>"$work/stderr")
  rc=$?
  err=$(cat "$work/stderr")
}

# A program with one error (OSP104), one warning (OSP108), one info (OSP005).
cat >"$work/P.MIN" <<'EOF'
O1000
G0 X50 Y30 F100 S500
CALL OZAGR PR=5 PZ=-20 PI=12 M52
CALL OZAGR PR=5 PZ=-20 PI=12 PM=52 M8
CALL OCLMP
M30
EOF
# Only a warning.
cat >"$work/W.MIN" <<'EOF'
O1000
CALL OZAGR PR=5 PZ=-20 PI=12 PM=52 M8 PF=100 PS=500
M30
EOF
# Only an info finding.
cat >"$work/I.MIN" <<'EOF'
O1000
CALL OCLMP
M30
EOF
cat >"$work/CLEAN.MIN" <<'EOF'
O1000
G0 X50 Y30
M30
EOF

# --- exit codes -------------------------------------------------------------
run "$work/CLEAN.MIN";                      expect_eq "clean file: exit 0" 0 "$rc"
run "$work/P.MIN";                          expect_eq "error, default --fail-on warning: exit 1" 1 "$rc"
run --fail-on error "$work/W.MIN";          expect_eq "warning only, --fail-on error: exit 0" 0 "$rc"
run --fail-on warning "$work/W.MIN";        expect_eq "warning only, --fail-on warning: exit 1" 1 "$rc"
run --fail-on warning "$work/I.MIN";        expect_eq "info only, --fail-on warning: exit 0" 0 "$rc"
run --fail-on info "$work/I.MIN";           expect_eq "info only, --fail-on info: exit 1" 1 "$rc"
run --fail-on never "$work/P.MIN";          expect_eq "errors, --fail-on never: exit 0" 0 "$rc"
run "$work/CLEAN.MIN" "$work/MISSING.MIN";  expect_eq "missing file: exit 2" 2 "$rc"
[[ "$err" == *"MISSING.MIN: no such file"* ]] && pass "missing file reported on stderr" || fail "missing file reported on stderr"
run --fail-on never "$work/MISSING.MIN";    expect_eq "missing file, --fail-on never: still exit 2" 2 "$rc"
run --select OSP9999 "$work/P.MIN";         expect_eq "unknown --select pattern: exit 2" 2 "$rc"
run --format xml "$work/P.MIN";             expect_eq "unknown --format: exit 2" 2 "$rc"
run --baseline "$work/none.json" "$work/P.MIN"; expect_eq "unreadable baseline: exit 2" 2 "$rc"

# --- gcc --------------------------------------------------------------------
run --format gcc "$work/P.MIN"
expect_eq "gcc format lines" \
"$work/P.MIN:3:30: error: M52 on the CALL line of OZAGR is not read by the macro: the tool does not return to the upper limit after the cycle; command PM=52 instead [OSP104]
$work/P.MIN:4:36: warning: M8 on the subprogram call block of OZAGR may be ignored: the cut may run without coolant; command it on the block before [OSP108]
$work/P.MIN:5:6: note: OCLMP is neither a macro osplint knows nor a program of the checked files: its arguments are not checked, and the control alarms if it cannot find it [OSP005]" \
"$out"
expect_eq "gcc format exit code" 1 "$rc"

# --- github -----------------------------------------------------------------
mkdir -p "$work/a,b:c"
cp "$work/P.MIN" "$work/a,b:c/P%1.MIN"
(cd "$work" && "$osplint" check --format github --color never "a,b:c/P%1.MIN" >"$work/gh.out" 2>"$work/gh.err")
rc=$?
expect_eq "github exit code" 1 "$rc"
gh=$(cat "$work/gh.out")
first=$(head -1 <<<"$gh")
expect_eq "github: first command is the error, escaped" \
  "::error file=a%2Cb%3Ac/P%251.MIN,line=3,col=30,endLine=3,endColumn=33,title=OSP104::M52 on the CALL line of OZAGR is not read by the macro: the tool does not return to the upper limit after the cycle; command PM=52 instead%0Anote: \"M52 commanded in the CALL block has no effect, because the sub cannot read M52 internally. In that case command PM=52.\" (Back counterboring macros manual, \"Common rules (3)\")%0Afix: Replace M52 by PM=52" \
  "$first"
expect_eq "github: order error, warning, notice" "error warning notice" \
  "$(sed -E 's/^::([a-z]+) .*/\1/' <<<"$gh" | tr '\n' ' ' | sed 's/ $//')"
grep -q "^a,b:c/P%1.MIN:3:30: error\[OSP104\]" "$work/gh.err" && pass "github: text report on stderr" ||
  fail "github: text report on stderr"
grep -q "1 error, 1 warning, 1 info in 1 file" "$work/gh.err" && pass "github: summary on stderr" ||
  fail "github: summary on stderr"

# --- --select / --ignore ----------------------------------------------------
run --format gcc --fail-on never --select OSP1 "$work/P.MIN"
expect_eq "--select OSP1 (prefix)" "OSP104 OSP108" "$(grep -o '\[OSP[0-9]*\]' <<<"$out" | tr -d '[]' | tr '\n' ' ' | sed 's/ $//')"
run --format gcc --fail-on never --ignore OSP104,OSP005 "$work/P.MIN"
expect_eq "--ignore OSP104,OSP005" "OSP108" "$(grep -o '\[OSP[0-9]*\]' <<<"$out" | tr -d '[]' | tr '\n' ' ' | sed 's/ $//')"
run --format gcc --fail-on never --select OSP1 --ignore OSP108 "$work/P.MIN"
expect_eq "--select OSP1 --ignore OSP108" "OSP104" "$(grep -o '\[OSP[0-9]*\]' <<<"$out" | tr -d '[]' | tr '\n' ' ' | sed 's/ $//')"

# --- --stdin-filename ---------------------------------------------------------
out=$("$osplint" check --format gcc --stdin-filename shop/PART7.MIN - <"$work/P.MIN")
rc=$?
expect_eq "stdin: exit code" 1 "$rc"
[[ "$(head -1 <<<"$out")" == "shop/PART7.MIN:3:30: error: "* ]] && pass "stdin: reported under --stdin-filename" ||
  fail "stdin: reported under --stdin-filename ($out)"
out=$("$osplint" check --format gcc - <"$work/P.MIN")
[[ "$(head -1 <<<"$out")" == "<stdin>:3:30: error: "* ]] && pass "stdin: default name" || fail "stdin: default name"
# The configuration of --stdin-filename's directory applies.
mkdir -p "$work/quiet"
printf '[rules]\nOSP104 = "off"\n' >"$work/quiet/osplint.toml"
out=$("$osplint" check --format gcc --stdin-filename "$work/quiet/P.MIN" - <"$work/P.MIN")
[[ "$out" != *OSP104* && "$out" == *OSP108* ]] && pass "stdin: configuration of --stdin-filename's directory" ||
  fail "stdin: configuration of --stdin-filename's directory ($out)"

# --- suppressions through the CLI ---------------------------------------------
cat >"$work/S.MIN" <<'EOF'
O1000
CALL OZAGR PR=5 PZ=-20 PI=12 M52 PF=100 PS=500 (osplint: disable=OSP104 -- checked on the machine)
(osplint: disable=OSP108)
CALL OZAGR PR=5 PZ=-20 PI=12 PM=52 M8
G0 X0 (osplint: disable=OSP1O4)
M30
EOF
run --format gcc "$work/S.MIN"
expect_eq "suppressed findings are not in gcc output; OSP901 is" \
  "$work/S.MIN:5:25: warning: unknown rule 'OSP1O4' in suppression: no rule has this ID or name, so the directive silences nothing (did you mean 'OSP104'?) (see \`osplint rules\`) [OSP901]" \
  "$out"
run --format json "$work/S.MIN"
reasons=$(node -e '
const j = JSON.parse(require("fs").readFileSync(0, "utf8"));
const s = j.files[0].suppressed.map(x => `${x.rule}:${x.range.start.line}:${x.suppression.reason}`);
console.log(s.join("|") + " " + j.summary.suppressed + " " + j.files[0].diagnostics.length);' <<<"$out")
expect_eq "json: suppressed findings with their reason" "OSP104:2:checked on the machine|OSP108:4: 2 1" "$reasons"
run --format gcc --select OSP104,OSP108,OSP901,OSP902 "$work/S.MIN"
[[ "$out" != *OSP902* ]] && pass "used directives are not OSP902" || fail "used directives are not OSP902 ($out)"

if ((failures)); then
  echo "$failures check(s) failed"
  exit 1
fi
echo "all CI format checks passed"
