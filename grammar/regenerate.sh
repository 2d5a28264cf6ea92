#!/usr/bin/env bash
# Regenerates the committed parser in grammar/src from grammar.js.
#
#   regenerate.sh            regenerate src/ (parser.c, grammar.json, node-types.json, tree_sitter/*.h)
#   regenerate.sh --test     run the corpus tests in test/corpus
#   regenerate.sh --check    regenerate into a temporary copy; exit 1 if the committed src/ differs
#
# Uses `tree-sitter` from PATH, else the CLI in ../../shared/tools (relative to this
# script). The parser is generated for ABI 14 because the runtime (0.20.x) reads
# ABI 13-14. src/scanner.c is written by hand and is never touched here.
set -euo pipefail

here="$(cd "$(dirname "$0")" && pwd)"
mode="${1:-generate}"

if command -v tree-sitter >/dev/null 2>&1; then
    cli="$(command -v tree-sitter)"
elif [[ -x "$here/../../shared/tools/tree-sitter" ]]; then
    cli="$here/../../shared/tools/tree-sitter"
else
    echo "no tree-sitter CLI, skipped"
    exit 0
fi

generated=(src/parser.c src/grammar.json src/node-types.json
           src/tree_sitter/parser.h src/tree_sitter/alloc.h src/tree_sitter/array.h)

generate_in() {
    (cd "$1" && "$cli" generate --abi 14 --no-bindings)
}

case "$mode" in
    generate|"")
        generate_in "$here"
        echo "regenerated $here/src with $("$cli" --version)"
        ;;
    --test)
        cd "$here"
        "$cli" test
        ;;
    --check)
        tmp="$(mktemp -d)"
        trap 'rm -rf "$tmp"' EXIT
        cp "$here/grammar.js" "$here/package.json" "$tmp/"
        mkdir -p "$tmp/src"
        cp "$here/src/scanner.c" "$tmp/src/"
        generate_in "$tmp" >/dev/null
        status=0
        for f in "${generated[@]}"; do
            if [[ ! -f "$here/$f" ]]; then
                echo "missing generated file: grammar/$f" >&2
                status=1
            elif ! cmp -s "$here/$f" "$tmp/$f"; then
                echo "out of date: grammar/$f (run grammar/regenerate.sh and commit the result)" >&2
                status=1
            fi
        done
        if [[ $status -ne 0 ]]; then
            echo "generated with $("$cli" --version)" >&2
            exit 1
        fi
        echo "grammar/src is up to date with grammar.js"
        ;;
    -h|--help)
        sed -n '2,10p' "$0"
        ;;
    *)
        echo "usage: $0 [--test|--check]" >&2
        exit 2
        ;;
esac
