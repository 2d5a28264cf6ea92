#!/usr/bin/env bash
# The HTML report (`osplint check --format html`) of the examples, rendered by
# headless Chromium: the screenshot is made and is not blank, and the DOM the
# browser builds holds the summary, every finding, the inline side views, and
# the program text escaped (a comment with <script> in it shows as text).
# Skipped (exit 77) when chromium is not installed, unless
# OSPLINT_REQUIRE_CHROMIUM is set (scripts/deps.sh --test installs it).
# Usage: html_report.sh path/to/osplint
set -uo pipefail
osplint=$(realpath "$1")
browser=""
for b in chromium chromium-browser; do
  if command -v "$b" >/dev/null 2>&1; then browser=$b; break; fi
done
if [[ -z $browser ]]; then
  if [[ -n ${OSPLINT_REQUIRE_CHROMIUM:-} ]]; then
    echo "not ok: chromium not found and OSPLINT_REQUIRE_CHROMIUM is set (scripts/deps.sh --test installs it)"
    exit 1
  fi
  echo "skipped: chromium not found (scripts/deps.sh --test installs it)"
  exit 77
fi
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
failures=0
pass() { echo "ok: $1"; }
fail() { echo "not ok: $1"; failures=$((failures + 1)); }
check() {  # NAME COMMAND...
  local name=$1
  shift
  if "$@"; then pass "$name"; else fail "$name"; fi
}
# Chromium keeps its profile in the home directory: a fresh one, and no
# network.
export HOME="$work/home"
mkdir -p "$HOME"
chrome() {
  timeout 120 "$browser" --headless --disable-gpu --no-sandbox --no-first-run --disable-extensions \
    --user-data-dir="$work/profile" --proxy-server="http://0.0.0.0:9" "$@" 2>"$work/chromium.log"
}

# The examples, and one program whose comment holds markup.
cp -r examples "$work/examples"
cat >"$work/examples/mistakes/XSS.MIN" <<'PROG'
(<script>document.title='owned'</script> <img src=x onerror=alert(1)>)
O7000
G0 X50 Y30
CALL OZAGR PR=5 PZ=-20 PI=12 M52 (<script>alert(1)</script>)
M30
PROG
(cd "$work" && "$osplint" check --format html -o report.html examples/ >/dev/null 2>"$work/check.err")
rc=$?
check "the check exits 1 (the examples have findings)" test "$rc" -eq 1
check "the report is written" test -s "$work/report.html"
(cd "$work" && "$osplint" check --format json examples/ >report.json 2>/dev/null)

chrome --screenshot="$work/shot.png" --window-size=1280,2000 "file://$work/report.html" >/dev/null
check "the screenshot exists" test -s "$work/shot.png"
size=$(stat -c %s "$work/shot.png" 2>/dev/null || echo 0)
# A blank 1280x2000 page compresses to a few kilobytes; the report is far more.
check "the screenshot is not blank ($size bytes)" test "$size" -gt 60000

chrome --dump-dom "file://$work/report.html" >"$work/dom.html"
check "the DOM is dumped" test -s "$work/dom.html"
python3 - "$work/report.json" "$work/dom.html" <<'PY' || failures=$((failures + 1))
import html, json, re, sys
report = json.load(open(sys.argv[1]))
dom = open(sys.argv[2], encoding="utf-8").read()
bad = 0
def check(name, ok):
    global bad
    print(("ok: " if ok else "not ok: ") + name)
    bad += 0 if ok else 1
s = report["summary"]
check("the summary cards give the counts",
      all(re.search(r'<span class="n">%d</span>%s' % (s[k], w), dom)
          for k, w in (("error", "error"), ("warning", "warning"), ("info", "info"), ("files", "file"))))
findings = [(f["path"], d) for f in report["files"] for d in f["diagnostics"]]
check("there are findings to look for (%d)" % len(findings), len(findings) > 10)
messages = re.findall(r'<p class="msg">(.*?)</p>', dom, re.S)
check("the rendered DOM holds one message per finding (%d)" % len(messages), len(messages) == len(findings))
missing = [d["message"] for _, d in findings if html.escape(d["message"], quote=False) not in
           {html.escape(html.unescape(m), quote=False) for m in messages}]
check("every finding's message is in the DOM" + (": missing %r" % missing[:3] if missing else ""), not missing)
per_rule = {}
for _, d in findings:
    per_rule[d["rule"]] = per_rule.get(d["rule"], 0) + 1 + d.get("folded", {}).get("count", 0)
rows = dict(re.findall(r'>(OSP\d+)</a></td>.*?<td class="num">(\d+)</td></tr>', dom))
check("the rule table counts each rule's findings", {k: int(v) for k, v in rows.items()} == per_rule)
check("every file has its section", all(('<h2 class="path">%s</h2>' % html.escape(f["path"], quote=False)) in dom
                                        for f in report["files"]))
check("the side views are inline SVG", dom.count("<svg ") >= 8 and 'class="violation"' in dom)
check("no script element came from the program", "<script" not in dom and "<img" not in dom)
check("the page title is the report's", "<title>osplint report</title>" in dom)
check("the markup of the comment is shown as text", "&lt;script&gt;document.title=" in dom)
sys.exit(1 if bad else 0)
PY
if ((failures)); then
  echo "$failures failed"
  exit 1
fi
echo "all passed"
