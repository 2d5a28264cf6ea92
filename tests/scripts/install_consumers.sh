#!/usr/bin/env bash
# A prefix install (cmake --install BUILD --prefix TMP) and the three example
# consumers of examples/consumers/ built and run against it: C++ with CMake's
# find_package (shared and static), C with pkg-config, Python through ctypes.
# Each must report exactly what `osplint check --format gcc` reports on a
# program with a known mistake (M52CALL.MIN, OSP104) and on one whose finding
# needs the nearest osplint.toml (ZTRAVEL.MIN, OSP301).
#
# In a sanitizer build (OSPLINT_SANITIZE=ON) the library carries the
# sanitizers' runtime references: the consumers are built with the same
# -fsanitize flags (and checked for leaks when ASAN_OPTIONS asks), and Python
# runs with the AddressSanitizer runtime preloaded.
set -euo pipefail
osplint=${1:?usage: install_consumers.sh path/to/build/osplint}
build=$(cd "$(dirname "$osplint")" && pwd)
src=$(pwd)
source "$(dirname "${BASH_SOURCE[0]}")/lib/common.bash"

sanitize=""
if grep -q '^OSPLINT_SANITIZE:BOOL=ON' "$build/CMakeCache.txt"; then
  sanitize="-fsanitize=address,undefined"
fi

prefix=$tmp/prefix
cmake --install "$build" --prefix "$prefix" >"$tmp/install.log"
libdir=$(dirname "$(find "$prefix" -name 'libosplint.so' | head -1)")
for f in bin/osplint include/osplint/osplint.h include/osplint/diagnostic.h include/osplint/osplint_c.h \
  share/doc/osplint/LICENSE share/doc/osplint/README.md share/man/man1/osplint.1 \
  share/bash-completion/completions/osplint share/zsh/vendor-completions/_osplint \
  share/osplint/schema/osplint.schema.json share/osplint/schema/catalog.schema.json; do
  [[ -e $prefix/$f ]] && ok "installed $f" || not_ok "$f is not installed"
done
for f in libosplint.so libosplint.a pkgconfig/osplint.pc cmake/osplint/osplintConfig.cmake \
  cmake/osplint/osplintConfigVersion.cmake; do
  [[ -e $libdir/$f ]] && ok "installed ${libdir#"$prefix"/}/$f" || not_ok "${libdir#"$prefix"/}/$f is not installed"
done

# The shared library: a versioned SONAME, and only the public interface exported.
soname=$(readelf -d "$libdir/libosplint.so" | sed -n 's/.*Library soname: \[\(.*\)\]/\1/p')
[[ $soname =~ ^libosplint\.so\.[0-9]+\.[0-9]+$ && -e $libdir/$soname ]] && ok "SONAME $soname" ||
  not_ok "SONAME is '$soname'"
exported=$(nm -DC --defined-only "$libdir/libosplint.so" | awk '$2 ~ /^[TWVDBR]$/ {$1=""; $2=""; print}')
for sym in osplint_check_file osplint_check_text osplint_config_load osplint_result_diagnostic \
  'osplint::check_text(' 'osplint::Configuration::load(' 'typeinfo for osplint::ConfigurationError'; do
  grep -qF -- "$sym" <<<"$exported" && ok "exports $sym" || not_ok "does not export $sym"
done
internal=$(grep -E 'osplint::(load_config|check_path|FastLineParser|Walk|outline_file)' <<<"$exported" || true)
[[ -z $internal ]] && ok "no internal symbol exported ($(wc -l <<<"$exported") symbols)" ||
  not_ok "internal symbols exported: $(head -3 <<<"$internal")"

# What the command line reports, the reference for every consumer.
programs=("$src/examples/mistakes/M52CALL.MIN" "$src/examples/mistakes/ZTRAVEL.MIN")
expected=$("$prefix/bin/osplint" check --format gcc -j 1 "${programs[@]}" | sed 's/: note: /: info: /' || true)
grep -q 'M52CALL.MIN:13:58: error: .* \[OSP104\]$' <<<"$expected" && grep -q 'ZTRAVEL.MIN:.*\[OSP301\]$' <<<"$expected" &&
  ok "the installed osplint finds OSP104 and OSP301" || not_ok "the installed osplint reports: $expected"

# Runs a consumer on the programs: exit code 1 (findings) and the CLI's findings.
check_consumer() {
  local name=$1
  shift
  local out status=0
  out=$("$@" "${programs[@]}" 2>"$tmp/$name.err") || status=$?
  if [[ $status -ne 1 ]]; then
    not_ok "$name: exit code $status (expected 1): $(head -5 "$tmp/$name.err")"
  elif [[ $out != "$expected" ]]; then
    not_ok "$name reports differently from osplint check:"
    diff <(echo "$expected") <(echo "$out") | head -10
  else
    ok "$name reports $(wc -l <<<"$out") findings, as osplint check does"
  fi
}

# C++, CMake find_package, shared library and static archive.
for kind in shared static; do
  static=OFF
  [[ $kind == static ]] && static=ON
  if cmake -S "$src/examples/consumers/cpp" -B "$tmp/cpp-$kind" -G Ninja -DCMAKE_BUILD_TYPE=Release \
    -DCMAKE_PREFIX_PATH="$prefix" -DOSPLINT_STATIC=$static -DCMAKE_CXX_FLAGS="$sanitize" \
    -DCMAKE_EXE_LINKER_FLAGS="$sanitize" >"$tmp/cpp-$kind.log" 2>&1 &&
    cmake --build "$tmp/cpp-$kind" >>"$tmp/cpp-$kind.log" 2>&1; then
    check_consumer "C++ ($kind, find_package)" "$tmp/cpp-$kind/check_programs"
  else
    not_ok "C++ ($kind): the consumer does not build"
    tail -20 "$tmp/cpp-$kind.log"
  fi
done
# The static build carries no reference to libosplint.so; the shared one does.
if readelf -d "$tmp/cpp-static/check_programs" 2>/dev/null | grep -q 'libosplint'; then
  not_ok "the static consumer needs libosplint.so"
else
  ok "the static consumer does not need libosplint.so"
fi
readelf -d "$tmp/cpp-shared/check_programs" 2>/dev/null | grep -q "\[$soname\]" &&
  ok "the shared consumer needs $soname" || not_ok "the shared consumer does not need $soname"

# C with pkg-config.
export PKG_CONFIG_PATH=$libdir/pkgconfig
cflags=$(pkg-config --cflags osplint)
libs=$(pkg-config --libs osplint)
[[ $(pkg-config --modversion osplint) == "$("$prefix/bin/osplint" --version | grep -oE '[0-9]+\.[0-9]+\.[0-9]+' | head -1)" ]] &&
  ok "osplint.pc has the version of osplint" || not_ok "osplint.pc's version is $(pkg-config --modversion osplint)"
# shellcheck disable=SC2086  # the flags are words
if cc -std=c99 -Wall -Wextra -Werror $sanitize $cflags "$src/examples/consumers/c/check_programs.c" $libs \
  -Wl,-rpath,"$libdir" -o "$tmp/c-check" 2>"$tmp/c.log"; then
  check_consumer "C (pkg-config)" "$tmp/c-check"
else
  not_ok "C: the consumer does not build"
  cat "$tmp/c.log"
fi

# C with the static archive: `pkg-config --static --libs` names what it needs.
private_libs=$(pkg-config --static --libs osplint | sed 's/-losplint\b//')
# shellcheck disable=SC2086
if cc -std=c99 -Wall -Wextra -Werror $sanitize $cflags "$src/examples/consumers/c/check_programs.c" \
  "$libdir/libosplint.a" $private_libs -o "$tmp/c-static" 2>"$tmp/c-static.log"; then
  check_consumer "C (pkg-config --static)" "$tmp/c-static"
else
  not_ok "C (static): the consumer does not link with pkg-config --static --libs: $private_libs"
  tail -20 "$tmp/c-static.log"
fi

# Python through ctypes.
if [[ -n $sanitize ]]; then
  preload="$(cc -print-file-name=libasan.so)"
  # The interpreter keeps memory to its exit: the leak check is for the C and C++ consumers.
  check_consumer "Python (ctypes)" env LD_PRELOAD="$preload" ASAN_OPTIONS=detect_leaks=0 \
    OSPLINT_LIBRARY="$libdir/libosplint.so" \
    python3 "$src/examples/consumers/python/check_programs.py"
else
  check_consumer "Python (ctypes)" env OSPLINT_LIBRARY="$libdir/libosplint.so" \
    python3 "$src/examples/consumers/python/check_programs.py"
fi

exit $fail
