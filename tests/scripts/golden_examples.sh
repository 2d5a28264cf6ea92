#!/usr/bin/env bash
# Golden output of `osplint check` on the bundled examples, in the text and
# JSON formats. Regenerate after an intended change with:
#   UPDATE=1 bash tests/scripts/golden_examples.sh build/osplint
set -u
osplint=${1:?usage: golden_examples.sh path/to/osplint}
fail=0
for fmt in text json; do
  golden=tests/golden/examples.$fmt
  actual=$(NO_COLOR=1 "$osplint" check --format "$fmt" -j 1 examples/ 2>&1; echo "exit=$?")
  if [[ ${UPDATE:-0} == 1 ]]; then
    printf '%s\n' "$actual" > "$golden"
    echo "updated $golden"
    continue
  fi
  if ! diff -u "$golden" <(printf '%s\n' "$actual") > /tmp/golden.diff.$$; then
    echo "FAIL: osplint check --format $fmt examples/ differs from $golden:"
    head -60 /tmp/golden.diff.$$
    fail=1
  else
    echo "ok: $fmt output matches $golden"
  fi
  rm -f /tmp/golden.diff.$$
done
exit $fail
