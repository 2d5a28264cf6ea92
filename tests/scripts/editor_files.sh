#!/usr/bin/env bash
# Every editor setup under editors/ recognises the OSP program files (.MIN
# .SSB .SUB .SDF .LIB .MSB .NC) in any case, and nothing else. Neovim is run
# (headless, the shipped setup, filetype of each file opened); the Emacs
# regexp runs in Emacs when it is installed and is otherwise read as a
# POSIX-style regexp by Python; the Helix globs and the VS Code patterns are
# matched with Python's fnmatch (case-sensitive, as both editors' glob
# libraries). Usage: editor_files.sh path/to/osplint
set -uo pipefail
osplint=$(realpath "$1")
repo=$(pwd)
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT

yes_names=(PART.MIN part.min Part.Min SUBS.SSB subs.ssb X.SUB x.Sub T.SDF t.sdf TOOLS.LIB tools.lib Tools.Lib
  M.MSB m.msb A.NC a.nc a.Nc)
no_names=(NOTES.TXT PART.MINX MIN part.mi a.ncc)
fail=0
pass=0
ok() { echo "ok: $*"; pass=$((pass + 1)); }
bad() { echo "not ok: $*"; fail=$((fail + 1)); }

# --- Neovim ----------------------------------------------------------------
if command -v nvim >/dev/null 2>&1; then
  mkdir -p "$work/files"
  for n in "${yes_names[@]}" "${no_names[@]}"; do : >"$work/files/$n"; done
  cat >"$work/ft.lua" <<'LUA'
local osplint = dofile(os.getenv('OSPLINT_REPO') .. '/editors/neovim/osplint.lua')
osplint.setup({ cmd = { os.getenv('OSPLINT_BIN'), 'lsp' }, highlight = false })
local out = io.open(os.getenv('OSPLINT_OUT'), 'w')
for name in string.gmatch(os.getenv('OSPLINT_NAMES'), '%S+') do
  vim.cmd('edit ' .. vim.fn.fnameescape(os.getenv('OSPLINT_DIR') .. '/' .. name))
  out:write(name .. ' ' .. (vim.bo.filetype ~= '' and vim.bo.filetype or '-') .. '\n')
end
out:close()
vim.cmd('qall!')
LUA
  HOME="$work" XDG_CONFIG_HOME="$work/config" XDG_DATA_HOME="$work/data" XDG_STATE_HOME="$work/state" \
    XDG_CACHE_HOME="$work/cache" OSPLINT_BIN="$osplint" OSPLINT_REPO="$repo" OSPLINT_DIR="$work/files" \
    OSPLINT_OUT="$work/nvim.out" OSPLINT_NAMES="${yes_names[*]} ${no_names[*]}" \
    timeout 60 nvim --headless --clean -n -i NONE -c "luafile $work/ft.lua" >/dev/null 2>&1 </dev/null
  for n in "${yes_names[@]}"; do
    if grep -qx "$n osp" "$work/nvim.out" 2>/dev/null; then ok "neovim: $n is osp"; else bad "neovim: $n is not osp"; fi
  done
  for n in "${no_names[@]}"; do
    if grep -q "^$n " "$work/nvim.out" 2>/dev/null && ! grep -qx "$n osp" "$work/nvim.out"; then
      ok "neovim: $n is not osp"
    else
      bad "neovim: $n is osp (or was not opened)"
    fi
  done
else
  bad "neovim: nvim not found (scripts/deps.sh installs the neovim package)"
fi

# --- Emacs -----------------------------------------------------------------
if command -v emacs >/dev/null 2>&1; then
  for n in "${yes_names[@]}" "${no_names[@]}"; do
    mode=$(emacs --batch -Q -l "$repo/editors/emacs/osplint.el" \
      --eval "(let ((case-fold-search nil)) (princ (or (assoc-default \"/x/$n\" auto-mode-alist #'string-match) '-)))" 2>/dev/null)
    echo "$n $mode" >>"$work/emacs.out"
  done
else
  # The regexp of osplint.el as Python reads it: \\( \\| \\) \\' become ( | ) $.
  python3 - "$repo/editors/emacs/osplint.el" "${yes_names[@]}" "${no_names[@]}" >"$work/emacs.out" <<'PY'
import re, sys
src = open(sys.argv[1]).read()
m = re.search(r'\(defconst osplint-file-regexp\s+"((?:[^"\\]|\\.)*)"', src)
emacs = m.group(1).replace('\\\\', '\\')
py = emacs.replace('\\(', '(').replace('\\|', '|').replace('\\)', ')').replace("\\'", '$')
for name in sys.argv[2:]:
    print(name, 'osp-mode' if re.search(py, '/x/' + name) else '-')
PY
fi
for n in "${yes_names[@]}"; do
  if grep -qx "$n osp-mode" "$work/emacs.out"; then ok "emacs: $n is osp-mode"; else bad "emacs: $n is not osp-mode"; fi
done
for n in "${no_names[@]}"; do
  if grep -qx "$n -" "$work/emacs.out"; then ok "emacs: $n is not osp-mode"; else bad "emacs: $n is osp-mode"; fi
done

# --- Helix and VS Code -----------------------------------------------------
python3 - "$repo" "${yes_names[*]}" "${no_names[*]}" <<'PY' || fail=$((fail + 1))
import fnmatch, json, sys, tomllib
repo, yes, no = sys.argv[1], sys.argv[2].split(), sys.argv[3].split()
helix = tomllib.load(open(repo + '/editors/helix/languages.toml', 'rb'))
lang = next(l for l in helix['language'] if l['name'] == 'osp')
globs = [t['glob'] for t in lang['file-types'] if isinstance(t, dict)]
exts = [t for t in lang['file-types'] if isinstance(t, str)]
def helix_match(n):
    return any(fnmatch.fnmatchcase(n, g) for g in globs) or any(n.endswith('.' + e) for e in exts)
pkg = json.load(open(repo + '/editors/vscode/package.json'))
osp = next(l for l in pkg['contributes']['languages'] if l['id'] == 'osp')
def vscode_match(n):
    return any(fnmatch.fnmatchcase(n, g) for g in osp.get('filenamePatterns', [])) or \
        any(n.endswith(e) for e in osp.get('extensions', []))
failed = 0
for editor, match in (('helix', helix_match), ('vscode', vscode_match)):
    for n in yes:
        print(('ok: ' if match(n) else 'not ok: ') + f'{editor}: {n} is osp')
        failed += not match(n)
    for n in no:
        print(('ok: ' if not match(n) else 'not ok: ') + f'{editor}: {n} is not osp')
        failed += match(n)
sys.exit(1 if failed else 0)
PY

if ((fail)); then
  echo "$fail failed"
  exit 1
fi
echo "all editor setups recognise the OSP files"
