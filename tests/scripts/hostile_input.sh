#!/usr/bin/env bash
# Hostile input never crashes or hangs osplint: each case ends with exit code
# 0, 1 or 2 within the time limit, with no sanitizer report, and a clear
# message on stderr for I/O errors.
set -u
osplint=${1:?usage: hostile_input.sh path/to/osplint}
dir=$(mktemp -d)
trap 'rm -rf "$dir"' EXIT
fail=0
# Time limits are for a release build; a sanitizer build (unoptimised, every
# access checked) is given OSPLINT_TIME_SCALE times as long (scripts/test).
scale=${OSPLINT_TIME_SCALE:-1}

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
w("UTF16.MIN", "O1000\nG0 X1\nM30\n".encode("utf-16"))
# Tree-sitter fails on some 65,000 nested brackets, and its error recovery
# grows with the square of the tokens it skips.
w("DEEP.MIN", b"O1000\nVC1=" + b"[" * 70000 + b"\nM30\n")
w("DEEPIF.MIN", b"O1000\nIF " + b"[" * 70000 + b"\nM30\n")
w("SIGNS.MIN", b"O1000\nVC1=" + b"-" * 70000 + b"\nM30\n")
w("RUNBRACKET.MIN", b"O1000\nVC1=1" + b"]" * 64000 + b"\nM30\n")
w("RUNCOMMA.MIN", b"O1000\nVC1=1" + b"," * 64000 + b"\nM30\n")
w("RUNEQUALS.MIN", b"O1000\nVC1=1" + b"=" * 64000 + b"\nM30\n")
# Many findings on one line: each must cost the same, not more as they grow.
w("MANYARGS.MIN", b"O1000\nMODIN OZAGR " + b" ".join(b"PX%d=1" % i for i in range(100000)) + b"\nM30\n")
w("MANYCOMMENTS.MIN", b"O1000\nMODIN OZAGR " + b" ".join(b"PX%d=1(C)" % i for i in range(50000)) + b"\nM30\n")
w("MANYRUNS.MIN", b"O1000\n" + (b"VC1=1" + b"]" * 2000 + b"\n") * 2000 + b"M30\n")
PY
mkdir "$dir/ADIR.MIN"
ln -s "$dir/does-not-exist.MIN" "$dir/DANGLING.MIN"

run() {  # run ARGS... ; checks exit code and stderr (time limit: $LIMIT seconds)
  local out err code
  out=$(timeout "$(( ${LIMIT:-120} * scale ))" "$osplint" "$@" 2>"$dir/stderr" >"${OUT:-/dev/null}"; echo $?)
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

# Lines tree-sitter cannot take whole: each is one finding, found within seconds.
for f in DEEP DEEPIF SIGNS RUNBRACKET RUNCOMMA RUNEQUALS MANYRUNS; do
  LIMIT=30 run check --format json "$dir/$f.MIN"
  LIMIT=30 run trace "$dir/$f.MIN"
  timeout $(( 30 * scale )) "$osplint" check --format json "$dir/$f.MIN" > "$dir/out.json" 2>/dev/null
  grep -q '"OSP001"' "$dir/out.json" || { echo "FAIL: $f.MIN gives no OSP001"; fail=1; }
done
grep -q 'expression nested too deeply' <(timeout $(( 30 * scale )) "$osplint" check "$dir/DEEP.MIN" 2>&1) ||
  { echo "FAIL: 70,000 open brackets are not reported as nested too deeply"; fail=1; }
grep -q 'not read further' <(timeout $(( 30 * scale )) "$osplint" check "$dir/RUNBRACKET.MIN" 2>&1) ||
  { echo "FAIL: a long run after an error does not say the line was not read further"; fail=1; }

# Many findings on one line, in every format, folded or not.
for f in MANYARGS MANYCOMMENTS; do
  LIMIT=60 run check "$dir/$f.MIN"
  [[ $LAST_CODE -eq 1 ]] || { echo "FAIL: $f.MIN needs exit 1"; fail=1; }
  LIMIT=60 run check --fold 0 --format sarif "$dir/$f.MIN"
  [[ $LAST_CODE -eq 1 ]] || { echo "FAIL: $f.MIN in SARIF needs exit 1"; fail=1; }
done

# The language server: such a document gets its diagnostics, so does another
# one opened beside it, and the server shuts down cleanly.
cat > "$dir/lsp_case.py" <<'PY'
import json, subprocess, sys, time, os, select
osplint, path = sys.argv[1], sys.argv[2]
text = open(path, "rb").read().decode("utf-8", "replace")
p = subprocess.Popen([osplint, "lsp"], stdin=subprocess.PIPE, stdout=subprocess.PIPE, stderr=subprocess.DEVNULL)
def send(msg):
    body = json.dumps(msg).encode()
    p.stdin.write(b"Content-Length: %d\r\n\r\n" % len(body) + body)
    p.stdin.flush()
buf = b""
def read_msg(deadline):
    global buf
    while True:
        if b"\r\n\r\n" in buf:
            head, rest = buf.split(b"\r\n\r\n", 1)
            n = int([l for l in head.split(b"\r\n") if l.lower().startswith(b"content-length")][0].split(b":")[1])
            if len(rest) >= n:
                buf = rest[n:]
                return json.loads(rest[:n])
        left = deadline - time.time()
        if left <= 0: return None
        r, _, _ = select.select([p.stdout], [], [], left)
        if not r: return None
        chunk = os.read(p.stdout.fileno(), 65536)
        if not chunk: return None
        buf += chunk
deadline = time.time() + 30
send({"jsonrpc": "2.0", "id": 1, "method": "initialize", "params": {"capabilities": {}}})
send({"jsonrpc": "2.0", "method": "initialized", "params": {}})
uri = "file:///tmp/HOSTILE.MIN"
send({"jsonrpc": "2.0", "method": "textDocument/didOpen", "params": {"textDocument": {"uri": uri, "languageId": "osp", "version": 1, "text": text}}})
send({"jsonrpc": "2.0", "method": "textDocument/didOpen", "params": {"textDocument": {"uri": "file:///tmp/OTHER.MIN", "languageId": "osp", "version": 1, "text": "O1000\nG0 X1\nVC1=1]\nM30\n"}}})
got = set()
while len(got) < 2:
    m = read_msg(deadline)
    if m is None: print("no diagnostics for", {uri, "file:///tmp/OTHER.MIN"} - got); sys.exit(1)
    if m.get("method") == "textDocument/publishDiagnostics" and m["params"]["diagnostics"]:
        got.add(m["params"]["uri"])
send({"jsonrpc": "2.0", "id": 2, "method": "shutdown"})
while True:
    m = read_msg(deadline)
    if m is None: print("no answer to shutdown"); sys.exit(1)
    if m.get("id") == 2: break
send({"jsonrpc": "2.0", "method": "exit"})
try:
    code = p.wait(timeout=max(1, deadline - time.time()))
except subprocess.TimeoutExpired:
    p.kill(); print("the server did not exit"); sys.exit(1)
if code != 0: print("the server exited with", code); sys.exit(1)
PY
for f in DEEP DEEPIF SIGNS RUNBRACKET; do
  if timeout $(( 60 * scale )) python3 "$dir/lsp_case.py" "$osplint" "$dir/$f.MIN"; then echo "ok: osplint lsp with $f.MIN"
  else echo "FAIL: osplint lsp with $f.MIN"; fail=1; fi
done

# The deep-nesting cases must be reported, not passed over.
"$osplint" check --format json "$dir/NESTOPEN.MIN" > "$dir/out.json" 2>/dev/null
grep -q '"OSP001"' "$dir/out.json" || { echo "FAIL: unclosed brackets give no OSP001"; fail=1; }

LIMIT=30 run check "$dir/UTF16.MIN"
[[ $LAST_CODE -eq 2 && $LAST_ERR == *"the file is UTF-16"* ]] || { echo "FAIL: a UTF-16 file needs exit 2 and a message"; fail=1; }

# Endless input without a line end: stopped at the first line longer than
# 1 MiB, with a message, in memory and on the disk.
LIMIT=30 run check /dev/zero
[[ $LAST_CODE -eq 2 && $LAST_ERR == *"line 1 is longer than"* ]] || { echo "FAIL: check /dev/zero needs exit 2 and a message"; fail=1; }
LIMIT=30 run check - < /dev/zero
[[ $LAST_CODE -eq 2 && $LAST_ERR == *"line 1 is longer than"* ]] || { echo "FAIL: check - < /dev/zero needs exit 2 and a message"; fail=1; }
[[ $(grep -c "longer than" "$dir/stderr") -eq 1 ]] || { echo "FAIL: check - < /dev/zero must say it once"; fail=1; }
LIMIT=30 run trace /dev/zero
[[ $LAST_CODE -eq 2 ]] || { echo "FAIL: trace /dev/zero needs exit 2"; fail=1; }

# Output that cannot be written: a message on stderr and exit code 2.
mkdir "$dir/progs"
printf 'O1000\nCALL OZAGR PX=-70. PY=0 PR=5. PZ=-29. PI=6. PF=50 PS=600 M52\nM30\n' > "$dir/progs/A.MIN"
printf 'O2000\nG0 X1\nM30\n' > "$dir/progs/B.MIN"
for fmt in text json sarif; do
  OUT=/dev/full LIMIT=30 run check --format $fmt "$dir/progs"
  [[ $LAST_CODE -eq 2 && $LAST_ERR == *"could not be written"* ]] || { echo "FAIL: $fmt to /dev/full needs exit 2 and a message"; fail=1; }
done
code=$(timeout $(( 30 * scale )) "$osplint" check "$dir/progs" 2>"$dir/stderr" >&-; echo $?)
[[ $code -eq 2 ]] && grep -q "standard output is closed" "$dir/stderr" || { echo "FAIL: a closed stdout needs exit 2 and a message"; fail=1; }
OUT=/dev/full LIMIT=30 run rules
[[ $LAST_CODE -eq 2 ]] || { echo "FAIL: rules to /dev/full needs exit 2"; fail=1; }
code=$( (ulimit -f 1 && timeout $(( 30 * scale )) "$osplint" check --format sarif "$dir/progs" "$dir/progs" "$dir/BINARY.MIN" > "$dir/out.sarif" 2>"$dir/stderr"); echo $?)
[[ $code -eq 2 ]] && grep -q "could not be written" "$dir/stderr" || { echo "FAIL: SARIF past the file size limit needs exit 2 and a message (got $code)"; fail=1; }

# The baseline: written atomically, never after an input error, never through a planted link.
base="$dir/progs/base.json"
"$osplint" check --write-baseline "$base" "$dir/progs" >/dev/null 2>&1
cp "$base" "$dir/base.orig"
[[ $(grep -c '"fingerprint"' "$base") -ge 1 ]] || { echo "FAIL: the baseline records nothing"; fail=1; }
LIMIT=30 run check --write-baseline "$base" "$dir/progs" "$dir/MISSING.MIN"
[[ $LAST_CODE -eq 2 && $LAST_ERR == *"was not written"* ]] && cmp -s "$base" "$dir/base.orig" ||
  { echo "FAIL: the baseline was rewritten after an input error"; fail=1; }
ln -s "$dir/victim" "$base.tmp"
for i in $(seq 1 20); do  # a baseline longer than the 1 KiB limit below
  printf 'O3%03d\nCALL OZAGR PX=-70. PY=0 PR=5. PZ=-29. PI=6. PF=50 PS=600 M52\nM30\n' "$i" > "$dir/progs/C$i.MIN"
done
code=$( (ulimit -f 1 && timeout $(( 30 * scale )) "$osplint" check --write-baseline "$base" "$dir/progs" >/dev/null 2>"$dir/stderr"); echo $?)
[[ $code -eq 2 ]] && grep -q "not written" "$dir/stderr" && cmp -s "$base" "$dir/base.orig" ||
  { echo "FAIL: a baseline write that fails must leave the old one (got $code)"; fail=1; }
LIMIT=30 run check --write-baseline "$base" "$dir/progs"
[[ $LAST_CODE -eq 0 && ! -e "$dir/victim" ]] || { echo "FAIL: the baseline write followed a planted link"; fail=1; }
[[ $(ls -A "$dir/progs" | grep -c base.json) -eq 2 ]] || { echo "FAIL: a temporary baseline file was left behind"; ls -A "$dir/progs"; fail=1; }
printf '{"version": 4294967297, "entries": []}' > "$dir/v.json"
LIMIT=30 run check --baseline "$dir/v.json" "$dir/progs"
[[ $LAST_CODE -eq 2 && $LAST_ERR == *"unsupported version 4294967297"* ]] || { echo "FAIL: baseline version 4294967297 must be rejected"; fail=1; }

# Configurations: a directory or a missing path is an error; a broken
# osplint.toml stops only the files it applies to.
mkdir -p "$dir/cfg/good" "$dir/cfg/bad/deeper"
for f in good/A bad/B bad/deeper/C; do cp "$dir/progs/A.MIN" "$dir/cfg/$f.MIN"; done
printf '[machine\nunits = "mm"\n' > "$dir/cfg/bad/osplint.toml"
LIMIT=30 run check "$dir/cfg"
[[ $LAST_CODE -eq 2 && $LAST_ERR == *"bad/osplint.toml"* && $LAST_ERR == *"bad/deeper/C.MIN: not checked"* &&
   $LAST_ERR != *"good/A.MIN"* ]] || { echo "FAIL: a broken osplint.toml must stop only its own files"; fail=1; }
grep -q "OSP104" <(timeout $(( 30 * scale )) "$osplint" check "$dir/cfg" 2>/dev/null) || { echo "FAIL: the other files were not checked"; fail=1; }
LIMIT=30 run check --config "$dir/cfg" "$dir/cfg/good"
[[ $LAST_CODE -eq 2 && $LAST_ERR == *"is a directory"* ]] || { echo "FAIL: --config DIR needs exit 2 and a message"; fail=1; }
LIMIT=30 run config "$dir/nonexistent"
[[ $LAST_CODE -eq 2 && $LAST_ERR == *"no such directory"* ]] || { echo "FAIL: config /nonexistent needs exit 2"; fail=1; }
for t in '[codes]\nG0 = "OZAGR"' '[codes]\nM30 = "OZAGR"' '[machine.travel]\nz = [-inf, inf]' \
         '[macro.OZAGR.arg.PM]\nallowed = [nan]'; do
  printf "$t\n" > "$dir/c.toml"
  LIMIT=30 run config --config "$dir/c.toml"
  [[ $LAST_CODE -eq 2 && $LAST_ERR == *"configuration error"* ]] || { echo "FAIL: $t must be rejected"; fail=1; }
done
python3 -c "print('[machine]\n' + 'k' * 1000000 + ' = 1')" > "$dir/c.toml"
LIMIT=30 run config --config "$dir/c.toml"
[[ $LAST_CODE -eq 2 && ${#LAST_ERR} -lt 3000 ]] || { echo "FAIL: a 1 MB key must be abbreviated in the message"; fail=1; }

# Worker threads that cannot be started (-j 1000 under a memory limit): the
# files are checked by those that started.
mkdir "$dir/many"
for i in $(seq 1 40); do printf 'O%d\nG0 X1\nM30\n' "$i" > "$dir/many/P$i.MIN"; done
if (ulimit -v 400000 && "$osplint" --version) >/dev/null 2>&1; then
  out=$( (ulimit -v 400000 && timeout $(( 60 * scale )) "$osplint" check -j 1000 "$dir/many") 2>"$dir/stderr")
  code=$?
  # Every file checked, or out of memory said plainly: never an abort.
  if [[ ($code -eq 0 && $out == *"in 40 files"*) || ($code -eq 2 && $(cat "$dir/stderr") == *"out of memory"*) ]]; then
    echo "ok: check -j 1000 under a memory limit -> exit $code"
  else echo "FAIL: check -j 1000 under a memory limit exited with $code"; head -5 "$dir/stderr"; fail=1; fi
else
  echo "note: this build cannot run under a memory limit (a sanitizer); the unit tests cover the threads"
fi

if [[ $fail -ne 0 ]]; then echo "hostile input: FAILED"; exit 1; fi
echo "hostile input: all cases ended cleanly"
