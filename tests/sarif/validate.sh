#!/usr/bin/env bash
# Validates osplint's SARIF output with Microsoft's SARIF multitool, using the
# GitHub code scanning ingestion rules (Gh, Ghas) and the SARIF rules (Sarif).
# Fails on any error or warning the validator reports.
#
#   tests/sarif/validate.sh BUILD_DIR/osplint      (run from the repository root)
#
# The multitool comes from the npm registry (@microsoft/sarif-multitool-linux,
# a self-contained .NET program) and is installed once into BUILD_DIR/sarif-multitool.
# It needs npm (scripts/deps.sh installs it) and reaches the registry only when
# the tool is not installed yet; without the registry the test fails, it never
# passes without validating. DOTNET_SYSTEM_GLOBALIZATION_INVARIANT=1 lets the
# tool run without libicu.
set -euo pipefail

osplint=$(realpath "$1")
repo=$(pwd)
build_dir=$(dirname "$osplint")
multitool_version=5.7.0
cache="$build_dir/sarif-multitool"
tool="$cache/node_modules/@microsoft/sarif-multitool-linux/Sarif.Multitool"

fail() {
  echo "FAIL: $*" >&2
  exit 1
}

export DOTNET_SYSTEM_GLOBALIZATION_INVARIANT=1
export DOTNET_CLI_TELEMETRY_OPTOUT=1
export DOTNET_NOLOGO=1
export DOTNET_BUNDLE_EXTRACT_BASE_DIR="$cache/dotnet-extract"

command -v node >/dev/null || fail "node is needed to read the validator's report (run scripts/deps.sh)"

# Install the multitool once (a lock keeps parallel test runs from racing).
mkdir -p "$cache"
(
  flock 9
  if [[ ! -f "$tool" ]]; then
    command -v npm >/dev/null ||
      fail "npm is needed to install the SARIF multitool (run scripts/deps.sh)"
    echo "installing @microsoft/sarif-multitool-linux@$multitool_version into $cache"
    if ! npm install --prefix "$cache" --no-audit --no-fund --no-save --fetch-retries=1 \
      --fetch-timeout=120000 "@microsoft/sarif-multitool-linux@$multitool_version" >"$cache/npm.log" 2>&1; then
      cat "$cache/npm.log" >&2
      fail "could not install @microsoft/sarif-multitool-linux@$multitool_version from the npm registry" \
           "(is the registry reachable?); SARIF output was NOT validated"
    fi
  fi
  [[ -f "$tool" ]] || fail "the npm package did not install $tool"
  chmod u+x "$tool"
) 9>"$cache/.lock"

work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT

# The node script that reads the validator's output log: every result at
# level error or warning (warning is the SARIF default level) is a failure.
cat >"$work/verdict.js" <<'EOF'
const fs = require('fs');
const [log, subject] = process.argv.slice(2);
const sarif = JSON.parse(fs.readFileSync(log, 'utf8'));
let bad = 0;
for (const run of sarif.runs || []) {
  for (const inv of run.invocations || []) {
    if (inv.executionSuccessful === false) { console.log(`${subject}: the validator did not run to completion`); bad++; }
    for (const n of inv.toolExecutionNotifications || []) {
      console.log(`${subject}: validator notification: ${n.message && n.message.text}`); bad++;
    }
  }
  for (const r of run.results || []) {
    const level = r.level || 'warning';
    if (level === 'error' || level === 'warning') {
      const args = (r.message && (r.message.text || (r.message.arguments || []).join(' | '))) || '';
      console.log(`${subject}: ${level} ${r.ruleId}: ${r.message && r.message.id || ''} ${args}`);
      bad++;
    }
  }
}
process.exit(bad ? 1 : 0);
EOF

# Checks the subject is a SARIF log with results (so validation is not vacuous).
cat >"$work/nonempty.js" <<'EOF'
const fs = require('fs');
const [file, min] = process.argv.slice(2);
const sarif = JSON.parse(fs.readFileSync(file, 'utf8'));
const n = sarif.runs[0].results.length;
if (n < Number(min)) { console.log(`${file}: ${n} results, expected at least ${min}`); process.exit(1); }
EOF

# validate SUBJECT NAME: runs the multitool, prints what it found; returns 1 on
# any error or warning.
validate() {
  local subject=$1 name=$2 out="$work/$2.validation.sarif"
  rm -f "$out"
  local console
  if ! console=$("$tool" validate --rule-kind "Sarif;Gh;Ghas" -o "$out" "$subject" 2>&1); then
    # The multitool's exit code is not reliable; its log decides below.
    :
  fi
  [[ -s "$out" ]] || { echo "$console"; fail "the validator wrote no log for $name"; }
  local status=0
  node "$work/verdict.js" "$out" "$name" || status=1
  if grep -Eq ': (error|warning) [A-Z]+[0-9]+:' <<<"$console"; then
    grep -E ': (error|warning) [A-Z]+[0-9]+:' <<<"$console"
    status=1
  fi
  return $status
}

select=OSP0,OSP1,OSP2,OSP3,OSP901,OSP902
failures=0
check() {  # check NAME MIN_RESULTS -- osplint arguments
  local name=$1 min=$2
  shift 3
  "$osplint" check --format sarif --fail-on never "$@" >"$work/$name.sarif" ||
    fail "osplint check --format sarif $* exited with $?"
  node "$work/nonempty.js" "$work/$name.sarif" "$min" || failures=$((failures + 1))
  if validate "$work/$name.sarif" "$name"; then
    echo "ok: $name"
  else
    echo "not ok: $name"
    failures=$((failures + 1))
  fi
}

# 1. The examples, every rule on.
check examples 10 -- examples/ --select "$select"
# 2. Every severity, notes, fixes, in-source suppressions, OSP901/OSP902, a
#    zero-length range, non-ASCII text before a finding.
check fixture 7 -- tests/sarif/fixtures/ --select "$select"
# 3. Baseline suppressions (kind "external").
"$osplint" check --fail-on never --write-baseline "$work/baseline.json" examples/mistakes/ >/dev/null 2>&1
check baselined 1 -- examples/mistakes/ --baseline "$work/baseline.json"
# 4. The program from standard input, and a file that cannot be read
#    (a tool execution notification, executionSuccessful false).
set +e
"$osplint" check --format sarif --fail-on never --stdin-filename "examples/mistakes/STDIN.MIN" - \
  examples/no-such-file.MIN <examples/mistakes/M52CALL.MIN >"$work/stdin.sarif" 2>/dev/null
set -e
if validate "$work/stdin.sarif" stdin; then echo "ok: stdin"; else echo "not ok: stdin"; failures=$((failures + 1)); fi
# 5. Paths that need percent-encoding (a blank, non-ASCII), checked from their directory.
mkdir -p "$work/tree/dir with blank"
cp examples/mistakes/M52CALL.MIN "$work/tree/dir with blank/Ärger #1.MIN"
(cd "$work/tree" && "$osplint" check --format sarif --fail-on never . >"$work/encoded.sarif")
grep -Eq '"uri": ?"dir%20with%20blank/%C3%84rger%20%231.MIN"' "$work/encoded.sarif" ||
  { echo "not ok: encoded (artifact URI not percent-encoded as expected)"; failures=$((failures + 1)); }
if validate "$work/encoded.sarif" encoded; then echo "ok: encoded"; else echo "not ok: encoded"; failures=$((failures + 1)); fi

# Negative control: a log with a broken ruleIndex and a rule without help must
# be rejected, or the validator is not checking anything.
node -e '
const fs = require("fs");
const s = JSON.parse(fs.readFileSync(process.argv[1], "utf8"));
delete s.runs[0].tool.driver.rules[0].help;
s.runs[0].results[0].ruleIndex = 999;
fs.writeFileSync(process.argv[2], JSON.stringify(s));
' "$work/fixture.sarif" "$work/broken.sarif"
if validate "$work/broken.sarif" broken >/dev/null; then
  echo "not ok: the validator accepted a log with a bad ruleIndex and a rule without help"
  failures=$((failures + 1))
else
  echo "ok: negative control rejected"
fi

if ((failures)); then
  fail "$failures SARIF check(s) failed"
fi
echo "SARIF validation: all logs pass (multitool $multitool_version, --rule-kind Sarif;Gh;Ghas)"
