#!/usr/bin/env bash
# Hostile input never crashes or hangs osplint: each case ends with exit code
# 0, 1 or 2 within the time limit, with no sanitizer report, and a clear
# message on stderr for I/O errors.
set -u
osplint=${1:?usage: hostile_input.sh path/to/osplint}
dir=$(mktemp -d)
trap 'rm -rf "$dir"' EXIT
fail=0

python3 - "$dir" <<'PY'
import os, random, sys
d = sys.argv[1]
random.seed(7)
def w(name, data):
    with open(os.path.join(d, name), "wb") as f:
        f.write(data)
w("BINARY.MIN", bytes(random.randrange(256) for _ in range(200000)))
w("NULS.MIN", b"O1000\nG0 X1\x00\x00Y2\n\x00\x00\x00\nM30\n")
w("EMPTY.MIN", b"")
w("COMMENT.MIN", b"O1000\n(" + b"A" * (2 * 1024 * 1024) + b")\nM30\n")
w("DIGITS.MIN", b"O1000\nG0 X" + b"9" * 400000 + b"\nM30\n")
w("NEST.MIN", b"O1000\nVC1=" + b"[" * 20000 + b"1" + b"]" * 20000 + b"\nM30\n")
w("NESTOPEN.MIN", b"O1000\nVC1=" + b"[" * 20000 + b"\nM30\n")
w("UTF8BAD.MIN", b"O1000\n(\xff\xfe\xc3\x28 \xe2\x82) G0 X1\n\xc0\xaf G1 Y2\nM30\n")
w("LONGLINE.MIN", b"O1000\n" + b"G1 X1 Y2 Z3 " * 100000 + b"\nM30\n")
w("CRONLY.MIN", b"O1000\rG0 X1\r\r\rM30")
w("MANYLINES.MIN", b"\n" * 300000)
PY
mkdir "$dir/ADIR.MIN"
ln -s "$dir/does-not-exist.MIN" "$dir/DANGLING.MIN"

run() {  # run ARGS... ; checks exit code and stderr
  local out err code
  out=$(timeout 120 "$osplint" "$@" 2>"$dir/stderr" >/dev/null; echo $?)
  code=$out
  err=$(cat "$dir/stderr")
  if [[ $code -gt 2 ]]; then
    echo "FAIL: osplint $* exited with $code"; echo "$err" | head -20; fail=1
  elif grep -q -E "Sanitizer|runtime error|AddressSanitizer|LeakSanitizer" "$dir/stderr"; then
    echo "FAIL: osplint $* produced a sanitizer report"; echo "$err" | head -20; fail=1
  else
    echo "ok: osplint $* -> exit $code"
  fi
  LAST_CODE=$code
  LAST_ERR=$err
}

for f in BINARY NULS EMPTY COMMENT DIGITS NEST NESTOPEN UTF8BAD LONGLINE CRONLY MANYLINES; do
  run check "$dir/$f.MIN"
  run check --format json "$dir/$f.MIN"
done
run check "$dir/ADIR.MIN"
[[ $LAST_CODE -eq 2 && $LAST_ERR == *"no program files"* ]] || { echo "FAIL: a directory without programs needs exit 2 and a message"; fail=1; }
run check "$dir/DANGLING.MIN"
[[ $LAST_CODE -eq 2 && $LAST_ERR == *"dangling"* ]] || { echo "FAIL: a dangling link needs exit 2 and a message"; fail=1; }
run check "$dir/MISSING.MIN"
[[ $LAST_CODE -eq 2 && $LAST_ERR == *"no such file"* ]] || { echo "FAIL: a missing file needs exit 2 and a message"; fail=1; }
run check "$dir"   # the directory itself: recursive, the bad entries are reported, nothing crashes
run check - < "$dir/BINARY.MIN"
run trace "$dir/NEST.MIN"

# The deep-nesting cases must be reported, not passed over.
"$osplint" check --format json "$dir/NESTOPEN.MIN" > "$dir/out.json" 2>/dev/null
grep -q '"OSP001"' "$dir/out.json" || { echo "FAIL: unclosed brackets give no OSP001"; fail=1; }

if [[ $fail -ne 0 ]]; then echo "hostile input: FAILED"; exit 1; fi
echo "hostile input: all cases ended cleanly"
