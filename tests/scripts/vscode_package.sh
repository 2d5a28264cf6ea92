#!/usr/bin/env bash
# Packages the VS Code extension (editors/vscode) into a .vsix with
# @vscode/vsce, its runtime dependency (vscode-languageclient) installed from
# the npm registry, and checks what the package holds: the manifest with the
# language `osp`, its extensions and grammar, the client code, the TextMate
# grammar, the language client, and nothing .vscodeignore leaves out.
#
#   tests/scripts/vscode_package.sh BUILD_DIR/osplint   (from the repository root)
#
# vsce is installed once into BUILD_DIR/vscode-vsce; the registry is reached
# only then and for the extension's dependencies (npm's cache serves later
# runs). Without the registry the test fails; it never passes without
# packaging. The project has no licence file yet, so vsce runs with
# --skip-license.
set -uo pipefail
osplint=$(realpath "$1")
repo=$(pwd)
build_dir=$(dirname "$osplint")
vsce_version=2.24.0
cache="$build_dir/vscode-vsce"
vsce="$cache/node_modules/.bin/vsce"

fail() {
  echo "not ok: $*"
  exit 1
}
command -v npm >/dev/null 2>&1 || fail "npm is needed (scripts/deps.sh installs it)"
command -v python3 >/dev/null 2>&1 || fail "python3 is needed to read the package"

mkdir -p "$cache"
(
  flock 9
  if [[ ! -x "$vsce" ]]; then
    echo "installing @vscode/vsce@$vsce_version into $cache"
    npm install --prefix "$cache" --no-audit --no-fund --no-save --fetch-retries=1 --fetch-timeout=120000 \
      "@vscode/vsce@$vsce_version" >"$cache/npm.log" 2>&1 || { cat "$cache/npm.log"; exit 1; }
  fi
) 9>"$cache/.lock" || fail "could not install @vscode/vsce@$vsce_version from the npm registry"

work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
cp -r "$repo/editors/vscode" "$work/ext"
mkdir -p "$work/ext/.vscode"
echo '{}' >"$work/ext/.vscode/settings.json" # left out by .vscodeignore
cd "$work/ext" || fail "no copy of the extension"
npm install --omit=dev --no-audit --no-fund --fetch-retries=1 --fetch-timeout=120000 >"$work/npm.log" 2>&1 ||
  { cat "$work/npm.log"; fail "could not install the extension's dependencies"; }
"$vsce" package --skip-license -o "$work/osplint.vsix" >"$work/vsce.log" 2>&1 ||
  { cat "$work/vsce.log"; fail "vsce could not package the extension"; }
echo "ok: vsce packaged the extension"

python3 - "$work/osplint.vsix" "$repo/editors/vscode/package.json" <<'PY'
import json, re, sys, zipfile
vsix, package = sys.argv[1], sys.argv[2]
names = set(zipfile.ZipFile(vsix).namelist())
z = zipfile.ZipFile(vsix)
failed = 0
def check(ok, what):
    global failed
    print(('ok: ' if ok else 'not ok: ') + what)
    failed += not ok
for f in ['extension/package.json', 'extension/extension.js', 'extension/language-configuration.json',
          'extension/syntaxes/osp.tmLanguage.json', 'extension/node_modules/vscode-languageclient/package.json',
          'extension.vsixmanifest']:
    check(f in names, f'the package holds {f}')
check(not any(n.startswith('extension/.vscode/') for n in names), '.vscodeignore leaves .vscode/ out')
packed = json.loads(z.read('extension/package.json'))
source = json.load(open(package))
check(packed['contributes'] == source['contributes'], 'the packed package.json contributes what the source does')
lang = next(l for l in packed['contributes']['languages'] if l['id'] == 'osp')
check({'.MIN', '.min', '.NC', '.nc'} <= set(lang['extensions']), 'the language osp has the OSP extensions')
grammar = next(g for g in packed['contributes']['grammars'] if g['language'] == 'osp')
check('extension/' + grammar['path'].lstrip('./') in names, 'the grammar the manifest names is packed')
manifest = z.read('extension.vsixmanifest').decode()
check(re.search(r'<Identity[^>]*Id="osplint"[^>]*Publisher="osplint"', manifest) is not None,
      'the manifest names the extension and its publisher')
check('github.com/osplint/osplint' in manifest, 'the manifest links the repository')
sys.exit(1 if failed else 0)
PY
