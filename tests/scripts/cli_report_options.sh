#!/usr/bin/env bash
# `osplint check --statistics`, `--output-file` and `--quiet` on the examples:
# the statistics count every finding of each rule (folded and limited ones
# too), the report file holds what standard output would, quiet output is the
# findings without the summary line, and the exit codes do not change.
set -u
osplint=${1:?usage: cli_report_options.sh path/to/osplint}
source "$(dirname "${BASH_SOURCE[0]}")/lib/common.bash"
export NO_COLOR=1

full=$("$osplint" check -j 1 --fold 0 examples/)
full_status=$?
# Every rule's count, from the findings themselves.
from_findings=$(grep -oE '^examples/[^ ]+: [a-z]+\[OSP[0-9]+\]' <<<"$full" | grep -oE 'OSP[0-9]+' | sort | uniq -c |
  awk '{print $2, $1}' | sort)

# --statistics, with a limit and folding that must not change the counts.
stats=$("$osplint" check -j 1 --statistics --max-findings 1 --fold 1 examples/)
status=$?
table=$(grep -E '^ +[0-9]+  OSP[0-9]+  [a-z0-9-]+$' <<<"$stats" | awk '{print $2, $1}' | sort)
[[ $status -eq $full_status ]] && ok "--statistics: exit code $status" || not_ok "--statistics: exit code $status, not $full_status"
if [[ -n $table && $table == "$from_findings" ]]; then
  ok "--statistics counts $(wc -l <<<"$table") rules as the findings do"
else
  not_ok "--statistics counts differ from the findings:"
  diff <(echo "$from_findings") <(echo "$table") | head -10
fi
grep -q 'OSP104  m52-on-call-line$' <<<"$stats" && ok "--statistics names the rules" || not_ok "no OSP104 row: $stats"
[[ $(tail -1 <<<"$stats") == "$(tail -1 <<<"$full")" ]] && ok "--statistics ends with the summary" ||
  not_ok "--statistics summary: $(tail -1 <<<"$stats")"
! grep -q '^examples/' <<<"$stats" && ok "--statistics lists no finding" || not_ok "--statistics lists findings"
"$osplint" check --statistics --format json examples/ >/dev/null 2>&1
[[ $? -eq 2 ]] && ok "--statistics with --format json is a usage error" || not_ok "--statistics --format json accepted"

# --output-file: the report in the file, nothing on standard output.
for fmt in text json; do
  expected=$("$osplint" check -j 1 --format $fmt examples/)
  out=$("$osplint" check -j 1 --format $fmt --output-file "$tmp/report.$fmt" examples/)
  status=$?
  if [[ -z $out && $(cat "$tmp/report.$fmt") == "$expected" && $status -eq $full_status ]]; then
    ok "--output-file ($fmt): the file holds the report, exit code $status"
  else
    not_ok "--output-file ($fmt): stdout '${out:0:80}', exit code $status, file differs:"
    diff <(echo "$expected") "$tmp/report.$fmt" | head -5
  fi
done
"$osplint" check --output-file "$tmp/missing/dir/report.txt" examples/ >/dev/null 2>"$tmp/err"
status=$?
[[ $status -eq 2 ]] && grep -q 'cannot write the report' "$tmp/err" && ok "an unwritable --output-file: exit code 2" ||
  not_ok "an unwritable --output-file: exit code $status, $(cat "$tmp/err")"

# --quiet: the findings without the summary line; nothing on standard error.
normal=$("$osplint" check -j 1 examples/mistakes/M52CALL.MIN examples/DRILL.MIN)
quiet=$("$osplint" check -j 1 --quiet examples/mistakes/M52CALL.MIN examples/DRILL.MIN 2>"$tmp/err")
status=$?
if [[ $status -eq 1 && $quiet == "$(head -n -1 <<<"$normal")" && -n $quiet && ! -s $tmp/err ]]; then
  ok "--quiet: the findings without the summary, exit code 1"
else
  not_ok "--quiet (exit code $status): $(tail -2 <<<"$quiet")"
fi
grep -q 'error\[OSP104\]' <<<"$quiet" || not_ok "--quiet lost the finding"
clean=$("$osplint" check --quiet examples/DRILL.MIN)
status=$?
[[ $status -eq 0 && -z $clean ]] && ok "--quiet on a clean program prints nothing" ||
  not_ok "--quiet on a clean program: exit code $status, '$clean'"
json=$("$osplint" check --quiet --format json examples/mistakes/M52CALL.MIN)
grep -q '"summary"' <<<"$json" && ok "--quiet keeps the JSON document whole" || not_ok "--quiet cut the JSON document"

# --engine-stats: what the walk did, per file, on standard error; the plain
# moves applied a run at a time, and, with a travel limit they may pass
# (Z-6. against a Z minimum of -5), checked one by one from their values.
{
  printf 'O100\nG15 H1\nG0 G90 X0 Y0\nG56 Z50. H1\nS1000 M3\nG1 F500\n'
  for i in $(seq 1 3000); do printf 'X%d. Y%d. Z-%d.\n' $((i % 50)) $((i % 40)) $((i % 7)); done
  printf 'M5\nM30\n'
} >"$tmp/MOVES.MIN"
printf '[machine]\nunits = "mm"\n[machine.travel]\nz = [-5.0, 150.0]\n' >"$tmp/travel.toml"
"$osplint" check --engine-stats "$tmp/MOVES.MIN" >/dev/null 2>"$tmp/stats"
runs=$(grep -oE '[0-9]+ plain moves a run at a time' "$tmp/stats" | grep -oE '^[0-9]+')
[[ ${runs:-0} -gt 2000 ]] && ok "--engine-stats: $runs plain moves applied a run at a time" ||
  not_ok "--engine-stats: $(cat "$tmp/stats")"
"$osplint" check --engine-stats --config "$tmp/travel.toml" "$tmp/MOVES.MIN" >/dev/null 2>"$tmp/stats"
values=$(grep -oE '[0-9]+ checked from their values' "$tmp/stats" | grep -oE '^[0-9]+')
[[ ${values:-0} -gt 2000 ]] && ok "--engine-stats: $values plain moves checked from their values with travel limits" ||
  not_ok "--engine-stats with travel limits: $(cat "$tmp/stats")"
exit $fail
