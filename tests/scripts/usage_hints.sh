#!/usr/bin/env bash
# Usage errors: a mistyped subcommand or long option gets the nearest one
# suggested ("did you mean"), and the exit code is 2 as for every usage error.
set -u
osplint=$(realpath "${1:?usage: usage_hints.sh path/to/osplint}")
source "$(dirname "${BASH_SOURCE[0]}")/lib/common.bash"
cd "$tmp" || exit 2
printf 'O1000\nG0 X0\nM30\n' > P.MIN
expect "subcommand" 2 "unknown command 'chek': did you mean 'check'\?" -- chek P.MIN
expect "subcommand, swapped letters" 2 "did you mean 'rules'\?" -- ruels
expect "subcommand, capitals" 2 "did you mean 'explain'\?" -- EXPLIAN OSP104
expect "subcommand, nothing near" 2 "unknown command 'frobnicate' \(see osplint --help\)" -- frobnicate
expect "long option of check" 2 "unknown option '--formt': did you mean '--format'\?" -- check --formt json P.MIN
expect "long option with =" 2 "unknown option '--fial-on': did you mean '--fail-on'\?" -- check --fial-on=error P.MIN
expect "long option of config" 2 "unknown option '--confg': did you mean '--config'\?" -- config --confg x.toml
expect "long option of the application" 2 "unknown option '--verison': did you mean '--version'\?" -- --verison
expect "long option of trace" 2 "did you mean '--svg'\?" -- trace --svgg out.svg P.MIN
expect "option nothing is near" 2 "unknown option '--xyzzy-plugh'" -- check --xyzzy-plugh P.MIN
expect "the parser's own message stays" 2 "not expected" -- check --formt json P.MIN
expect "a correct command is not touched" 0 "in 1 file" -- check --format text P.MIN
# A list option takes one value (comma-separated) and leaves the paths after it alone.
printf 'O1000\nCALL OZAGR PX=1 M52 PF=100 PS=500\nM30\n' > Q.MIN
expect "--select before two paths" 1 "in 2 files" -- check --select OSP104 P.MIN Q.MIN
expect "--select before two paths checks the first" 1 "^Q.MIN:.*OSP104" -- check --select OSP104 Q.MIN P.MIN
expect "--ignore before two paths" 0 "in 2 files" -- check --ignore OSP1 Q.MIN P.MIN
expect "--select, a comma-separated list" 1 "OSP104" -- check --select OSP207,OSP104 Q.MIN P.MIN
expect "--select repeated" 1 "OSP104" -- check --select OSP207 --select OSP104 Q.MIN P.MIN
expect "--ignore repeated" 0 "in 2 files" -- check --ignore OSP101 --ignore OSP104 Q.MIN P.MIN
exit $fail
