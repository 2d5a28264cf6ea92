#!/usr/bin/env bash
# osplint.toml's `extend`, `exclude` and `[[per-path]]`, `--exclude` and
# `--force-exclude`, rule names where rule IDs go, and what `osplint config`
# shows of them.
set -u
osplint=$(realpath "${1:?usage: config_paths.sh path/to/osplint}")
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
cd "$work" || exit 2
fail=0
expect() {  # expect NAME EXIT PATTERN [!] -- ARGS...   ("!": the output must not match)
  local name=$1 code=$2 pattern=$3 negate=
  shift 3
  if [[ $1 == '!' ]]; then negate=1; shift; fi
  shift
  local out rc
  out=$("$osplint" "$@" 2>&1)
  rc=$?
  if [[ $rc != "$code" ]]; then
    echo "FAIL: $name: exit $rc, expected $code"; printf '%s\n' "$out" | head -8; fail=1
  elif [[ -z $negate ]] && ! grep -Eq -- "$pattern" <<<"$out"; then
    echo "FAIL: $name: output lacks /$pattern/"; printf '%s\n' "$out" | head -8; fail=1
  elif [[ -n $negate ]] && grep -Eq -- "$pattern" <<<"$out"; then
    echo "FAIL: $name: output has /$pattern/"; printf '%s\n' "$out" | head -8; fail=1
  else
    echo "ok: $name"
  fi
}

m52='O1000
CALL OZAGR PR=5 PZ=-20 PI=12 M52 PF=100 PS=500
M30'
mkdir -p shop cell/old/deep cell/probe
cat > shop/osplint.toml <<'TOML'
exclude = ["*.BAK.MIN"]
[rules]
OSP004 = "off"
TOML
cat > cell/osplint.toml <<'TOML'
extend = "../shop/osplint.toml"
exclude = ["old/**"]
[[per-path]]
paths = ["probe/**"]
rules = { m52-on-call-line = "info" }
TOML
for f in cell/P1.MIN cell/old/P2.MIN cell/old/deep/P5.MIN cell/P3.BAK.MIN cell/probe/P4.MIN; do
  printf '%s\n' "$m52" > "$f"
done

expect "walk skips exclude of the file and of the one it extends" 1 "in 2 files" -- check cell
expect "walk: old/** skipped" 1 'old/' ! -- check cell --format gcc
expect "walk: *.BAK.MIN skipped" 1 'BAK' ! -- check cell --format gcc
expect "per-path: probe's OSP104 is info" 1 'probe/P4.MIN:2:30: note: .*\[OSP104\]' -- check cell --format gcc
expect "per-path: other files keep the error" 1 'cell/P1.MIN:2:30: error: .*\[OSP104\]' -- check cell --format gcc
expect "a file named is checked though excluded" 1 'old/P2.MIN:2:30: error' -- check cell/old/P2.MIN --format gcc
expect "--force-exclude: not even the file named" 0 'in 0 files' -- check --force-exclude cell/old/P2.MIN cell/P3.BAK.MIN
expect "--force-exclude: a directory named" 0 'in 0 files' -- check --force-exclude cell/old
out=$(printf '%s\n' "$m52" | "$osplint" check --force-exclude --stdin-filename cell/old/P9.MIN - 2>&1); rc=$?
if [[ $rc == 0 && $out == *"in 0 files"* ]]; then echo "ok: --force-exclude: stdin under an excluded --stdin-filename"
else echo "FAIL: --force-exclude with stdin: exit $rc: $out"; fail=1; fi
out=$(printf '%s\n' "$m52" | "$osplint" check --stdin-filename cell/old/P9.MIN - 2>&1); rc=$?
if [[ $rc == 1 && $out == *"cell/old/P9.MIN:2:30"* ]]; then echo "ok: stdin is checked without --force-exclude"
else echo "FAIL: stdin without --force-exclude: exit $rc: $out"; fail=1; fi
out=$(printf '%s\n' "$m52" | "$osplint" check --format gcc --stdin-filename cell/probe/P9.MIN - 2>&1)
if [[ $out == *"P9.MIN:2:30: note:"* ]]; then echo "ok: per-path applies to stdin by --stdin-filename"
else echo "FAIL: per-path with stdin: $out"; fail=1; fi
expect "--exclude adds to the file's patterns" 1 'in 1 file' -- check --exclude 'probe' cell
expect "--exclude with ./ and a folder" 1 'in 1 file' -- check --exclude ./cell/probe/ cell
expect "--exclude is repeatable" 0 'in 0 files' -- check --exclude probe --exclude 'P[0-9].MIN' cell
expect "--exclude with a bad pattern" 2 "--exclude 'P\[1': '\[' without its closing" -- check --exclude 'P[1' cell
expect "config shows the chain" 0 '^# extends .*shop/osplint.toml' -- config cell
expect "config shows each pattern's file" 0 "'\*\.BAK\.MIN',  # .*shop/osplint.toml" -- config cell
expect "config shows the per-path tables" 0 "^rules = \{ OSP104 = 'info' \}" -- config cell
expect "config: inherited [rules]" 0 "^OSP004 = 'off'" -- config cell

# Rule names wherever rule IDs go.
expect "--select by name" 1 '\[OSP104\]' -- check --format gcc --select m52-on-call-line -- cell/P1.MIN
expect "--ignore by name" 0 'in 1 file' -- check --ignore m52-on-call-line -- cell/P1.MIN
expect "--ignore with a mistyped name" 2 "no rule matches 'm52-on-cal-line' \(did you mean 'm52-on-call-line'\?\)" \
  -- check --ignore m52-on-cal-line -- cell/P1.MIN
expect "explain by name" 0 '^# OSP104 m52-on-call-line' -- explain m52-on-call-line
expect "explain a mistyped name" 2 "did you mean 'm52-on-call-line'" -- explain m52-on-cal-line

# Mistakes: exit 2, the file and the key.
mkdir -p bad1 bad2/a bad2/b bad3
printf 'extend = "../nowhere/osplint.toml"\n' > bad1/osplint.toml
cp cell/P1.MIN bad1/
expect "extend: missing file names both" 2 "bad1/osplint.toml:1: 'extend': the file it extends, .*nowhere/osplint.toml, does not exist" -- config bad1
expect "extend: missing file, check" 2 "configuration error: .*bad1/osplint.toml:1: 'extend'" -- check bad1
printf 'extend = "../b/osplint.toml"\n' > bad2/a/osplint.toml
printf '\nextend = "../a/osplint.toml"\n' > bad2/b/osplint.toml
expect "extend: a cycle" 2 "b/osplint.toml:2: 'extend': .*extend each other \(.*a/osplint.toml -> .*b/osplint.toml -> .*a/osplint.toml\)" -- config bad2/a
printf '[[per-path]]\npaths = ["probe/**"]\nrules = { OSP14 = "off" }\n' > bad3/osplint.toml
expect "per-path: unknown rule" 2 "bad3/osplint.toml:3: 'per-path.rules.OSP14': unknown rule ID or name \(did you mean" -- config bad3
printf 'exclude = "old"\n' > bad3/osplint.toml
expect "exclude: not a list" 2 "bad3/osplint.toml:1: 'exclude': expected an array" -- config bad3
printf '[rules]\nm52-on-cal-line = "off"\n' > bad3/osplint.toml
expect "[rules]: a mistyped name" 2 "'rules.m52-on-cal-line': unknown rule ID or name \(did you mean 'm52-on-call-line'\?\)" -- config bad3
exit $fail
