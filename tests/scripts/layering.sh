#!/usr/bin/env bash
# The layers of the source tree (docs/ARCHITECTURE.md): a file may include
# headers of its own layer and of the layers below it, never above. Checks
# every #include "..." of src/, rules/, cli/ and include/osplint/.
#
#   vocabulary  include/osplint/diagnostic.h (the diagnostic model, public)
#   support     src/support
#   syntax      src/syntax          catalog  src/catalog   (neither includes the other)
#   semantics   src/semantics
#   engine      src/engine
#   rules       rules/
#   api         src/api, include/osplint/osplint.h, include/osplint/osplint_c.h
# The public headers (include/osplint/) include nothing but each other and
# the standard library: they are installed alone.
#   output      src/output
#   lsp         src/lsp
#   cli         cli/
# $1 (the osplint binary) is not used.
set -u
cd "$(dirname "$0")/../.."

rank_of() {  # rank_of PATH -> the layer's rank; syntax and catalog share one
  case $1 in
    include/osplint/diagnostic.h) echo 0 ;;
    src/support/*) echo 1 ;;
    src/syntax/*) echo 2 ;;
    src/catalog/*) echo 2 ;;
    src/semantics/*) echo 3 ;;
    src/engine/*) echo 4 ;;
    rules/*) echo 5 ;;
    src/api/* | include/osplint/osplint.h | include/osplint/osplint_c.h) echo 6 ;;
    src/output/*) echo 7 ;;
    src/lsp/*) echo 8 ;;
    cli/*) echo 9 ;;
    *) echo "" ;;
  esac
}

# The file an include names: relative to src/, include/ or the top.
resolve() {
  local inc=$1
  for base in src include .; do
    if [[ -f $base/$inc ]]; then
      echo "${base#./}/$inc" | sed 's|^\./||; s|^\./||'
      return
    fi
  done
  echo ""
}

failures=0
checked=0
while IFS= read -r file; do
  from=$(rank_of "$file")
  [[ -n $from ]] || continue
  while IFS= read -r inc; do
    [[ $inc == rules_list.inc ]] && continue  # generated, for rules/registry.cpp
    target=$(resolve "$inc")
    if [[ -z $target ]]; then
      echo "not ok: $file includes \"$inc\", which is no file of the tree"
      failures=$((failures + 1))
      continue
    fi
    if [[ $file == include/osplint/* && $target != include/osplint/* ]]; then
      echo "not ok: public header $file includes $target, which is not installed"
      failures=$((failures + 1))
      continue
    fi
    to=$(rank_of "$target")
    [[ -n $to ]] || continue
    checked=$((checked + 1))
    if ((to > from)); then
      echo "not ok: $file (layer $from) includes $target (layer $to, above it)"
      failures=$((failures + 1))
    elif ((to == 2 && from == 2)) && [[ $(cut -d/ -f2 <<<"$file") != $(cut -d/ -f2 <<<"$target") ]]; then
      # syntax and catalog: same rank, separate layers.
      echo "not ok: $file includes $target: syntax and catalog do not include each other"
      failures=$((failures + 1))
    fi
  done < <(grep -oE '^#include "[^"]+"' "$file" | sed -E 's/#include "(.*)"/\1/')
done < <(find src rules cli include/osplint -type f \( -name '*.h' -o -name '*.cpp' \) | sort)

# Angle-bracket includes of the public headers: the standard library only
# (no path: <fmt/format.h>, <toml++/toml.hpp> would not be there).
while IFS=: read -r file inc; do
  echo "not ok: public header $file includes ${inc#\#include }, which is not the standard library"
  failures=$((failures + 1))
done < <(grep -HoE '^#include <[^>]*/[^>]*>' include/osplint/*.h)

if ((failures)); then
  echo "FAIL: $failures include(s) cross the layers"
  exit 1
fi
echo "ok: $checked includes follow the layers"
