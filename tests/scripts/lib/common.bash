# What the test scripts share (sourced, not run: it is not a test of its own).
#   tmp       a scratch folder, removed when the script exits
#   fail      0 until a check fails; the script ends with `exit $fail`
#   ok MSG / not_ok MSG   report one check
#   expect NAME EXIT PATTERN -- ARGS...   runs osplint ARGS (the script's
#             $osplint) and checks its exit code and that its output matches
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
fail=0
ok() { echo "ok: $*"; }
not_ok() {
  echo "not ok: $*"
  fail=1
}
expect() {
  local name=$1 code=$2 pattern=$3
  shift 4
  local out rc
  out=$("$osplint" "$@" 2>&1)
  rc=$?
  if [[ $rc != "$code" ]]; then
    not_ok "$name: exit $rc, expected $code"
    printf '%s\n' "$out" | head -5
  elif ! grep -Eq -- "$pattern" <<<"$out"; then
    not_ok "$name: output lacks /$pattern/"
    printf '%s\n' "$out" | head -5
  else
    ok "$name"
  fi
}
