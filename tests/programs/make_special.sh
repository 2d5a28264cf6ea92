#!/bin/sh
# Generates the test programs that cannot be kept as plain LF / UTF-8 text
# (CR LF and lone-CR line ends, Shift-JIS comments, no final newline, binary
# junk) from the LF sources in special/. The output is deterministic; the
# generated files are committed next to the others.
#
#   sh make_special.sh          regenerate the files
#   sh make_special.sh --check  regenerate into a temporary directory and
#                               fail if a committed file differs
set -eu
LC_ALL=C
export LC_ALL
here=$(cd "$(dirname "$0")" && pwd)
src=$here/special

out=$here
if [ "${1:-}" = "--check" ]; then
    out=$(mktemp -d)
    trap 'rm -rf "$out"' EXIT
    mkdir -p "$out/errors"
fi

crlf() { awk '{ printf "%s\r\n", $0 }'; }               # LF -> CR LF
lonecr() { tr '\n' '\r'; }                              # LF -> CR
noeol() { awk 'NR > 1 { printf "\n" } { printf "%s", $0 }'; }        # drop the final LF
crlf_noeol() { awk 'NR > 1 { printf "\r\n" } { printf "%s", $0 }'; } # CR LF, no final one
sjis() { iconv -f UTF-8 -t SHIFT_JIS; }                 # UTF-8 -> Shift-JIS

# splice FILE MARKER FORMAT: FILE with the line that is exactly MARKER
# replaced by the bytes of `printf FORMAT` (octal escapes, may contain NUL).
splice() {
    awk -v m="$2" '$0 == m { exit } { print }' "$1"
    # shellcheck disable=SC2059
    printf "$3"
    awk -v m="$2" 'seen { print } $0 == m { seen = 1 }' "$1"
}

crlf < "$src/CRLF.MIN.lf" > "$out/CRLF.MIN"
lonecr < "$src/LONECR.SSB.lf" > "$out/LONECR.SSB"
sjis < "$src/SJIS.MIN.lf" | crlf > "$out/SJIS.MIN"
sjis < "$src/SJIS2.SSB.lf" | noeol > "$out/SJIS2.SSB"
noeol < "$src/NOEOL.SSB.lf" > "$out/NOEOL.SSB"
noeol < "$src/NOEOL2.NC.lf" > "$out/NOEOL2.NC"
crlf_noeol < "$src/CRLFNOEOL.LIB.lf" > "$out/CRLFNOEOL.LIB"
crlf < "$src/MPIP.NC.lf" > "$out/MPIP.NC"

crlf < "$src/errors/CRLFERR.MIN.lf" > "$out/errors/CRLFERR.MIN"
sjis < "$src/errors/SJISERR.MIN.lf" > "$out/errors/SJISERR.MIN"

tmp=$(mktemp)
splice "$src/errors/BINJUNK.NC.lf" '@@JUNKLINE@@' \
    '\001\002\033\177\377\376\200\237\300\301\021\n' > "$tmp"
splice "$tmp" '@@JUNKMID@@' 'G0 X10.\377\376\001\200 Y5.\n' > "$out/errors/BINJUNK.NC"
splice "$src/errors/BINNUL.NC.lf" '@@NULMID@@' 'G0 X10.\000\000 Y5.\n' > "$tmp"
splice "$tmp" '@@NULLINE@@' '\000\000\000\000\n' > "$out/errors/BINNUL.NC"
rm -f "$tmp"

if [ "$out" != "$here" ]; then
    status=0
    for f in CRLF.MIN LONECR.SSB SJIS.MIN SJIS2.SSB NOEOL.SSB NOEOL2.NC CRLFNOEOL.LIB MPIP.NC \
             errors/CRLFERR.MIN errors/SJISERR.MIN errors/BINJUNK.NC errors/BINNUL.NC; do
        if ! cmp -s "$out/$f" "$here/$f"; then
            echo "out of date: tests/programs/$f (run sh tests/programs/make_special.sh)" >&2
            status=1
        fi
    done
    exit $status
fi
