#!/usr/bin/env bash
# End-to-end test of `osplint lsp` with Emacs 28 and Eglot (the Debian
# packages emacs-nox and elpa-eglot, installed by scripts/deps.sh): the setup
# editors/emacs/osplint.el opens a copy of an example in osp-mode with its
# highlighting, Eglot starts the server, a hover shows the macro card, an edit
# brings a diagnostic, its quick fix is applied as a code action, a sequence
# name is renamed, and the server shuts down. The steps are in
# tests/lsp/e2e.el. Usage: lsp_emacs.sh path/to/osplint
set -uo pipefail
osplint=$(realpath "$1")
repo=$(pwd)
if ! command -v emacs >/dev/null 2>&1; then
  echo "not ok: emacs not found (scripts/deps.sh installs emacs-nox and elpa-eglot)"
  exit 1
fi
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
cp examples/BACKBAR.MIN "$work/BACKBAR.MIN"
cp examples/osplint.toml "$work/osplint.toml"
HOME="$work" OSPLINT_BIN="$osplint" OSPLINT_FILE="$work/BACKBAR.MIN" OSPLINT_REPO="$repo" \
  timeout 120 emacs --batch -Q -l "$repo/tests/lsp/e2e.el" >"$work/out" 2>"$work/err" </dev/null
rc=$?
cat "$work/out"
if [[ $rc != 0 ]]; then
  echo "not ok: emacs exited with $rc"
  tail -20 "$work/err"
  exit 1
fi
if grep -q '^not ok' "$work/out" || ! grep -q '^ok: the server shuts down' "$work/out"; then
  exit 1
fi
echo "$(grep -c '^ok' "$work/out") passed, 0 failed"
