#!/usr/bin/env bash
# Numbers too large for a double: the literal is reported (OSP001, "too large
# to be read as a value") and no report, in any format, says inf or nan.
set -u
osplint=$(realpath "${1:?usage: huge_numbers.sh path/to/osplint}")
source "$(dirname "${BASH_SOURCE[0]}")/lib/common.bash"
cd "$tmp" || exit 2
huge=$(printf '9%.0s' {1..400})
big=$(printf '9%.0s' {1..308})
printf 'O1000\nG0 X0 Z-%s\nG81 Z-%s R%s F0.1\nG80\nG91 G0 Z%s\nZ%s\nG90 G81 Z1 R%s F0.1\nG80\nM02\n' \
  "$huge" "$huge" "$huge" "$big" "$big" "$big" > HUGE.MIN
expect "the literal is an OSP001" 1 "OSP001.*the number 999999999999\.\.\.99999999 \(400 digits\) is too large" -- check HUGE.MIN
for fmt in text json sarif gcc github html; do
  out=$("$osplint" check --format $fmt HUGE.MIN 2>&1)
  if grep -Eiq '(^|[^a-z])(inf|nan)([^a-z]|$)' <<<"$out"; then
    not_ok "--format $fmt prints inf or nan: $(grep -Eio '.{0,40}(^|[^a-z])(inf|nan)([^a-z]|$).{0,20}' <<<"$out" | head -2)"
  else
    ok "--format $fmt: no inf, no nan"
  fi
done
out=$("$osplint" trace HUGE.MIN 2>&1)
grep -Eiq '(^|[^a-z])(inf|nan)([^a-z]|$)' <<<"$out" && not_ok "trace prints inf or nan" || ok "trace: no inf, no nan"
exit $fail
