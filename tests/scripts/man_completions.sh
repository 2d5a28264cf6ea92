#!/usr/bin/env bash
# The manual page and the shell completions agree with the command: the page
# renders without warnings, and every subcommand and every long option that
# `osplint --help` and `osplint SUBCOMMAND --help` list is in the page and in
# both completion files; the bash completion loads, the zsh one parses.
set -u
osplint=$(realpath "${1:?usage: man_completions.sh path/to/osplint}")
root=$(cd "$(dirname "${BASH_SOURCE[0]}")/../.." && pwd)
man_page=$root/docs/man/osplint.1
bash_comp=$root/completions/bash/osplint
zsh_comp=$root/completions/zsh/_osplint
fail=0
ok() { echo "ok: $1"; }
bad() { echo "FAIL: $1"; fail=1; }

# The page renders, without a warning.
if command -v groff >/dev/null 2>&1; then
  warnings=$(LC_ALL=C.UTF-8 groff -man -Tutf8 -ww -z "$man_page" 2>&1)
  if [[ -n $warnings ]]; then bad "groff warns:"; printf '%s\n' "$warnings" | head -10; else ok "groff renders the page without warnings"; fi
  text=$(LC_ALL=C.UTF-8 MANWIDTH=200 groff -man -Tutf8 -P-cbou "$man_page" 2>/dev/null)
elif command -v mandoc >/dev/null 2>&1; then
  warnings=$(mandoc -Tlint -Wwarning "$man_page" 2>&1)
  if [[ -n $warnings ]]; then bad "mandoc -Tlint warns:"; printf '%s\n' "$warnings" | head -10; else ok "mandoc -Tlint finds nothing"; fi
  text=$(mandoc -Tutf8 "$man_page" | col -b)
else
  echo "FAIL: neither groff (groff-base) nor mandoc is installed (scripts/deps.sh --test)"
  exit 1
fi
# Rendered text: "-" may come out as U+2010 or U+2212 depending on the device.
text=$(sed 's/\xe2\x80\x90/-/g; s/\xe2\x88\x92/-/g' <<<"$text")

# The version on the page is the command's.
version=$("$osplint" --version | awk '{ print $2 }')
if grep -q "^\.TH OSPLINT 1 .*\"osplint $version\"" "$man_page"; then ok "the page is of osplint $version"
else bad "the page's .TH line does not name osplint $version"; fi

# Subcommands, and the long options of the application and of each subcommand.
help=$("$osplint" --help)
mapfile -t commands < <(awk '/^Subcommands:/ { on = 1; next } on && NF { print $1 }' <<<"$help")
if ((${#commands[@]} < 6)); then bad "could not read the subcommands from --help"; fi
declare -A options_of
options_of[osplint]=$(grep -oE -- '--[a-z][a-z0-9-]*' <<<"$help" | sort -u)
for c in "${commands[@]}"; do
  options_of[$c]=$("$osplint" "$c" --help | grep -oE -- '(^|[ ,])--[a-z][a-z0-9-]*' | grep -oE -- '--[a-z][a-z0-9-]*' | sort -u)
done
if ! grep -q -- '--force-exclude' <<<"${options_of[check]}"; then bad "could not read the options of check from --help"; fi

for c in "${commands[@]}"; do
  grep -qE "^ +osplint $c\b" <<<"$text" || bad "man page: no synopsis for '$c'"
  grep -qw -- "$c" "$bash_comp" || bad "bash completion: no subcommand '$c'"
  grep -qE "^ +['\"]$c:" "$zsh_comp" || bad "zsh completion: no subcommand '$c'"
done
ok "the subcommands (${commands[*]}) are in the page and both completions"

for c in osplint "${commands[@]}"; do
  for o in ${options_of[$c]}; do
    grep -qE -- "(^|[^a-z-])$o([^a-z-]|$)" <<<"$text" || bad "man page: no $o (of $c)"
    grep -qE -- "(^|[^a-z-])$o([^a-z-]|$)" "$bash_comp" || bad "bash completion: no $o (of $c)"
    grep -qE -- "(^|[^a-z-])$o([^a-z-]|$)" "$zsh_comp" || bad "zsh completion: no $o (of $c)"
  done
  ok "the options of $c: $(tr '\n' ' ' <<<"${options_of[$c]}")"
done

# The values of the options that take one of a list (as --help shows them).
check_help=$("$osplint" check --help)
for o in format fail-on color; do
  values=$(grep -oE -- "--$o TEXT:\{[^}]*\}" <<<"$check_help" | sed 's/.*{//; s/}//; s/,/ /g')
  [[ -n $values ]] || bad "could not read the values of --$o"
  for v in $values; do
    grep -qw -- "$v" "$bash_comp" || bad "bash completion: no value '$v' of --$o"
    grep -qw -- "$v" "$zsh_comp" || bad "zsh completion: no value '$v' of --$o"
    grep -qw -- "$v" <<<"$text" || bad "man page: no value '$v' of --$o"
  done
done
ok "the values of --format, --fail-on and --color"

# The bash completion loads and completes.
if out=$(bash -c 'source "$1"; complete -p osplint' _ "$bash_comp" 2>&1) && grep -q -- '-F _osplint osplint' <<<"$out"; then
  ok "the bash completion loads: $out"
else
  bad "the bash completion does not load: $out"
fi
got=$(PATH=$(dirname "$osplint"):$PATH bash -c '
  source "$1"
  t() { COMP_WORDS=("$@"); COMP_CWORD=$((${#COMP_WORDS[@]} - 1)); COMPREPLY=(); _osplint; printf "%s\n" "${COMPREPLY[@]}"; }
  t osplint chec; t osplint check --format s; t osplint check --ignore OSP104,m52-on-ca; t osplint explain OSP10' _ "$bash_comp")
for want in check sarif OSP104,m52-on-call-line OSP104; do
  grep -qx -- "$want" <<<"$got" || bad "bash completion: no '$want' among: $(tr '\n' ' ' <<<"$got")"
done
ok "the bash completion completes subcommands, values and rule IDs and names"

if command -v zsh >/dev/null 2>&1; then
  if zsh -n "$zsh_comp"; then ok "the zsh completion parses"; else bad "the zsh completion does not parse"; fi
else
  echo "note: zsh is not installed: the zsh completion is checked by its text only"
fi
exit $fail
