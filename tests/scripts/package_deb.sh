#!/usr/bin/env bash
# The Debian package: cpack -G DEB builds osplint_VERSION_ARCH.deb from the
# build; dpkg-deb lists it and reads its control fields; every library the
# packaged binary and libosplint.so need comes from a package the .deb
# depends on; the package extracted with dpkg-deb -x holds a working osplint
# that checks the examples as the built one does.
set -euo pipefail
osplint=${1:?usage: package_deb.sh path/to/build/osplint}
build=$(cd "$(dirname "$osplint")" && pwd)
src=$(pwd)
source "$(dirname "${BASH_SOURCE[0]}")/lib/common.bash"

if ! (cd "$build" && cpack -G DEB -B "$tmp/out" >"$tmp/cpack.log" 2>&1); then
  echo "not ok: cpack fails"
  tail -30 "$tmp/cpack.log"
  exit 1
fi
version=$("$osplint" --version | grep -oE '[0-9]+\.[0-9]+\.[0-9]+' | head -1)
deb=$tmp/out/osplint_${version}_$(dpkg --print-architecture).deb
[[ -f $deb ]] || {
  echo "not ok: no $(basename "$deb") in: $(ls "$tmp/out")"
  exit 1
}
ok "built $(basename "$deb")"

contents=$(dpkg-deb --contents "$deb" | awk '{print $6}')
for f in ./usr/bin/osplint ./usr/include/osplint/osplint.h ./usr/include/osplint/osplint_c.h \
  ./usr/share/doc/osplint/LICENSE ./usr/share/osplint/schema/osplint.schema.json; do
  grep -qxF "$f" <<<"$contents" && ok "contains $f" || not_ok "does not contain $f"
done
for pattern in '/libosplint\.so\.[0-9.]+$' '/libosplint\.a$' '/pkgconfig/osplint\.pc$' '/cmake/osplint/osplintConfig\.cmake$' \
  '/usr/share/man/man1/osplint\.1(\.gz)?$' '/usr/share/bash-completion/completions/osplint$' \
  '/usr/share/zsh/vendor-completions/_osplint$'; do
  grep -qE "$pattern" <<<"$contents" && ok "contains $pattern" || not_ok "contains nothing like $pattern"
done
[[ $(dpkg-deb -f "$deb" Package) == osplint && $(dpkg-deb -f "$deb" Version) == "$version" ]] &&
  ok "Package osplint, Version $version" || not_ok "control: $(dpkg-deb -f "$deb" Package Version)"

# Every package named in Depends exists in this Debian (it is installed: the
# build linked against it), and every library the ELF files need is in one.
depends=$(dpkg-deb -f "$deb" Depends)
mapfile -t depended < <(tr ',' '\n' <<<"$depends" | sed -E 's/^ *([^ (]+).*/\1/')
for p in "${depended[@]}"; do
  # grep reads a string, not a pipe: under pipefail a writer that grep -q
  # leaves behind (SIGPIPE) would fail the check now and then.
  grep -q "install ok installed" <<<"$(dpkg-query -W -f='${Status}' "$p" 2>/dev/null || true)" &&
    ok "depends on $p, a Debian package" || not_ok "depends on $p, which is no installed package"
done
root=$tmp/root
dpkg-deb -x "$deb" "$root"
# The package that owns a library file (dpkg may know it under /lib or /usr/lib).
owner_of() {
  local f o candidates=()
  for f in "$1" "$(readlink -f "$1")"; do
    candidates+=("$f" "${f#/usr}" "/usr$f")
  done
  for f in "${candidates[@]}"; do
    o=$(dpkg -S "$f" 2>/dev/null | head -1 | cut -d: -f1 || true)
    if [[ -n $o ]]; then
      echo "$o"
      return
    fi
  done
}
for elf in "$root/usr/bin/osplint" "$root"/usr/lib*/libosplint.so.*.*.*; do
  resolved=$(ldd "$elf")
  while IFS= read -r lib; do
    # "name => /path (addr)", or "/path (addr)" for the dynamic loader.
    path=$(awk -v l="$lib" '
      $1 == l && $2 == "=>" {print $3; exit}
      $1 ~ /^\// && substr($1, length($1) - length(l)) == "/" l {print $1; exit}' <<<"$resolved")
    owner=$([[ -n $path ]] && owner_of "$path" || true)
    if [[ -z $owner ]]; then
      not_ok "$(basename "$elf") needs $lib ($path), which no package provides"
    elif grep -qxF "$owner" <<<"$(printf '%s\n' "${depended[@]}")"; then
      ok "$(basename "$elf") needs $lib, from $owner"
    else
      not_ok "$(basename "$elf") needs $lib from $owner, which Depends does not name"
    fi
  done < <(readelf -d "$elf" | sed -n 's/.*Shared library: \[\(.*\)\]/\1/p')
done

# The extracted command checks the examples as the built one does.
expected=$(cd "$src" && NO_COLOR=1 "$osplint" check -j 1 examples/ 2>&1; echo "exit=$?")
actual=$(cd "$src" && NO_COLOR=1 "$root/usr/bin/osplint" check -j 1 examples/ 2>&1; echo "exit=$?")
if [[ $actual == "$expected" ]] && grep -q 'error\[OSP104\]' <<<"$actual"; then
  ok "the packaged osplint checks examples/ as the built one does ($(grep -c '^examples/' <<<"$actual") findings)"
else
  not_ok "the packaged osplint reports differently:"
  diff <(echo "$expected") <(echo "$actual") | head -20
fi
"$root/usr/bin/osplint" explain OSP104 | grep -q 'M52' && ok "the packaged osplint explains OSP104" ||
  not_ok "the packaged osplint cannot explain OSP104"
exit $fail
