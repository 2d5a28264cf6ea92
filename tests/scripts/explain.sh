#!/usr/bin/env bash
# `osplint explain`: rule pages, macro cards by name and by code, fixed-cycle
# cards by G code (any case), and a clear error for anything else.
set -u
osplint=$(realpath "${1:?usage: explain.sh path/to/osplint}")
source "$(dirname "${BASH_SOURCE[0]}")/lib/common.bash"
cd "$tmp" || exit 2  # no osplint.toml around: the built-in catalog
expect "fixed cycle G81" 0 '^G81 ' -- explain G81
expect "fixed cycle, lower case" 0 '^G83 ' -- explain g83
expect "fixed cycle card has its format" 0 'G84' -- explain G84
expect "macro by code" 0 '^OG84L ' -- explain G114
expect "macro by name" 0 '^OZAGR ' -- explain ozagr
expect "rule page" 0 '^# OSP006 jump-to-duplicated-name' -- explain OSP006
expect "rule off by default says so" 0 'Off by default' -- explain OSP003
expect "rule page by name" 0 '^# OSP104 m52-on-call-line' -- explain m52-on-call-line
expect "rule page by name, capitals" 0 '^# OSP104 m52-on-call-line' -- explain M52-ON-CALL-LINE
expect "mistyped rule name" 2 "did you mean 'm52-on-call-line'\?" -- explain m52-on-cal-line
expect "unknown G code" 2 "'G999' is neither a rule ID" -- explain G999
expect "unknown name" 2 "'NOPE' is neither a rule ID" -- explain NOPE
exit $fail
