#!/usr/bin/env bash
# End-to-end test of `osplint lsp` with a real editor: headless Neovim (the
# Debian package, installed by scripts/deps.sh) opens a copy of an example,
# receives its diagnostics, hovers over a macro name (by request and through
# the K mapping of the setup), introduces a mistake and receives the new
# diagnostic, applies the quick fix, renames a sequence name, and shuts the
# server down.
# The steps are in tests/lsp/e2e.lua. Usage: lsp_neovim.sh path/to/osplint
set -uo pipefail
osplint=$(realpath "$1")
repo=$(pwd)
if ! command -v nvim >/dev/null 2>&1; then
  echo "not ok: nvim not found (scripts/deps.sh installs the neovim package)"
  exit 1
fi
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
cp examples/BACKBAR.MIN "$work/BACKBAR.MIN"
cp examples/osplint.toml "$work/osplint.toml"

# The tree-sitter parser and highlight queries for the highlighting check
# (skipped when there is no C compiler).
ts_rtp=""
if command -v cc >/dev/null 2>&1 &&
  mkdir -p "$work/rtp/parser" "$work/rtp/queries/osp" &&
  cc -shared -fPIC -O1 -I grammar/src grammar/src/parser.c grammar/src/scanner.c -o "$work/rtp/parser/osp.so" &&
  cp grammar/queries/highlights.scm "$work/rtp/queries/osp/highlights.scm"; then
  ts_rtp="$work/rtp"
else
  echo "note: no C compiler, the highlighting check is skipped"
fi

# --clean: no user configuration, no plugins; HOME and XDG dirs point at the
# scratch directory so that nothing of the machine's setup is read or written.
HOME="$work" XDG_CONFIG_HOME="$work/config" XDG_DATA_HOME="$work/data" XDG_STATE_HOME="$work/state" \
  XDG_CACHE_HOME="$work/cache" OSPLINT_BIN="$osplint" OSPLINT_FILE="$work/BACKBAR.MIN" OSPLINT_REPO="$repo" \
  OSPLINT_TS_RTP="$ts_rtp" \
  timeout 120 nvim --headless --clean -n -i NONE -c "luafile $repo/tests/lsp/e2e.lua" >"$work/out" 2>&1 </dev/null
rc=$?
cat "$work/out"
if [[ $rc != 0 ]]; then
  echo "not ok: neovim exited with $rc"
  exit 1
fi
if grep -q '^not ok' "$work/out" || ! grep -q '^ok: the server shuts down' "$work/out"; then
  exit 1
fi
echo "$(grep -c '^ok' "$work/out") passed, 0 failed"
