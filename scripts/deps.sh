#!/usr/bin/env bash
# Installs the Debian 12 packages osplint needs, if any is missing:
#   scripts/deps.sh          what building the osplint command and its libraries needs
#   scripts/deps.sh --test   that, and what the test suite needs (scripts/test)
# Further arguments are more packages to install.
set -euo pipefail
packages=(build-essential cmake ninja-build pkg-config libtree-sitter-dev libfmt-dev nlohmann-json3-dev
          libcli11-dev libtomlplusplus-dev)
if [[ ${1:-} == --test ]]; then
  shift
  packages+=(doctest-dev  # the unit tests
             neovim  # the language server's end-to-end test (tests/scripts/lsp_neovim.sh)
             emacs-nox elpa-eglot  # ... with Emacs and Eglot (tests/scripts/lsp_emacs.sh)
             clang libclang-rt-14-dev  # the differential fuzzer (tests/scripts/fuzz_short.sh)
             time  # peak RSS in bench/run.sh
             python3  # the Python example consumer (tests/scripts/install_consumers.sh)
             python3-jsonschema  # the schemas of osplint.toml and the catalog (tests/scripts/config_schema.sh)
             chromium  # renders the HTML report headless (tests/scripts/html_report.sh)
             groff-base  # the manual page renders without warnings (tests/scripts/man_completions.sh)
             zsh  # ... and the zsh completion parses
  )
  # npm and node for the SARIF validation test (tests/sarif/validate.sh installs
  # Microsoft's SARIF multitool from the npm registry), unless a node
  # installation already provides them.
  if ! command -v npm >/dev/null 2>&1 || ! command -v node >/dev/null 2>&1; then
    packages+=(nodejs npm)
  fi
fi
packages+=("$@")
missing=()
for p in "${packages[@]}"; do
  dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed" || missing+=("$p")
done
if ((${#missing[@]})); then
  echo "installing: ${missing[*]}"
  SUDO=""
  if [[ $(id -u) -ne 0 ]]; then SUDO="sudo"; fi
  export DEBIAN_FRONTEND=noninteractive
  $SUDO apt-get update -qq
  $SUDO apt-get install -y -qq "${missing[@]}" >/dev/null
fi
