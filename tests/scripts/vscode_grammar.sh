#!/usr/bin/env bash
# The TextMate grammar of the VS Code extension
# (editors/vscode/syntaxes/osp.tmLanguage.json), applied to sample lines the
# way a TextMate engine applies single-line `match` rules: at each place, the
# rule whose match starts first wins (the earlier rule on a tie), its
# captures name the scopes, and the scan goes on after it. Each expected
# token must get its scope. Also checks that package.json contributes the
# grammar for the language `osp`. Usage: vscode_grammar.sh path/to/osplint
set -uo pipefail
if ! command -v node >/dev/null 2>&1; then
  echo "not ok: node not found (scripts/deps.sh installs nodejs)"
  exit 1
fi
node - "$(pwd)/editors/vscode" <<'JS'
const fs = require('fs');
const dir = process.argv[2];
const grammar = JSON.parse(fs.readFileSync(dir + '/syntaxes/osp.tmLanguage.json', 'utf8'));
const pkg = JSON.parse(fs.readFileSync(dir + '/package.json', 'utf8'));
let failed = 0;
function check(ok, what) {
  console.log((ok ? 'ok: ' : 'not ok: ') + what);
  if (!ok) failed++;
}
const g = (pkg.contributes.grammars || []).find((x) => x.language === 'osp');
check(g && g.scopeName === grammar.scopeName && fs.existsSync(dir + '/' + g.path),
  'package.json contributes the grammar for osp');

// The rules in the order of the top-level patterns. Oniguruma's leading (?i)
// becomes JavaScript's i flag.
const rules = grammar.patterns.map((p) => {
  const r = grammar.repository[p.include.slice(1)];
  let src = r.match;
  let flags = 'gd';
  if (src.startsWith('(?i)')) {
    src = src.slice(4);
    flags += 'i';
  }
  return { re: new RegExp(src, flags), name: r.name, captures: r.captures || {} };
});

function tokenize(line) {
  const out = [];
  let pos = 0;
  while (pos < line.length) {
    let best = null;
    for (const r of rules) {
      r.re.lastIndex = pos;
      const m = r.re.exec(line);
      if (!m || m[0].length === 0) continue;
      if (!best || m.index < best.m.index) best = { r, m };
    }
    if (!best) break;
    const { r, m } = best;
    if (r.name) out.push({ text: m[0].trim(), scope: r.name });
    for (const [i, c] of Object.entries(r.captures))
      if (m[i] !== undefined) out.push({ text: m[i], scope: c.name });
    pos = m.index + m[0].length;
  }
  return out;
}

const cases = [
  ['OMAIN (BACK SPOTFACE)', [['OMAIN', 'entity.name.function.program.osp'], ['(BACK SPOTFACE)', 'comment.block.osp']]],
  ['N100 CALL OZAGR PX=70. PR=5. PZ=-29. (T31)', [
    ['N100', 'entity.name.label.osp'], ['CALL', 'keyword.control.call.osp'], ['OZAGR', 'entity.name.function.call.osp'],
    ['PX', 'variable.parameter.osp'], ['70.', 'constant.numeric.osp'], ['-29.', 'constant.numeric.osp'],
    ['(T31)', 'comment.block.osp']]],
  ['modin og87c pr=3', [['modin', 'keyword.control.call.osp'], ['og87c', 'entity.name.function.call.osp'],
    ['pr', 'variable.parameter.osp']]],
  ['IF [VC1 EQ EMPTY] NSKIP', [['IF', 'keyword.control.osp'], ['VC1', 'variable.other.osp'],
    ['EQ', 'keyword.operator.osp'], ['NSKIP', 'entity.name.label.osp']]],
  ['GOTO N10', [['GOTO', 'keyword.control.jump.osp'], ['N10', 'entity.name.label.osp']]],
  ['WHILE [VC[CNTR] LT 3] DO 1', [['WHILE', 'keyword.control.osp'], ['VC', 'variable.other.osp'],
    ['DO', 'keyword.control.osp']]],
  ['G0 G90 X10. Y-2.5 M8', [['G0', 'support.function.code.osp'], ['G90', 'support.function.code.osp'],
    ['10.', 'constant.numeric.osp'], ['-2.5', 'constant.numeric.osp'], ['M8', 'support.function.code.osp']]],
  ['/ N12 VTOFX[16]=VTOFX[6] (2ND OFFSET', [['N12', 'entity.name.label.osp'], ['VTOFX', 'variable.other.osp'],
    ['(2ND OFFSET', 'comment.block.osp']]],
  ['NCYL G81 Z-3.', [['NCYL', 'keyword.control.osp'], ['G81', 'support.function.code.osp']]],
  ["VUACM[1]='END OF BAR'", [['VUACM', 'variable.other.osp'], ["'END OF BAR'", 'string.quoted.single.osp']]],
  ['RTS', [['RTS', 'keyword.control.osp']]],
];
for (const [line, want] of cases) {
  const got = tokenize(line);
  for (const [text, scope] of want) {
    const hit = got.some((t) => t.text === text && t.scope === scope);
    check(hit, `${JSON.stringify(line)}: ${text} is ${scope}` +
      (hit ? '' : ' (got ' + JSON.stringify(got.filter((t) => t.text === text)) + ')'));
  }
}
// Nothing inside a comment is anything but the comment.
const inComment = tokenize('(CALL OSUB G81 VC1=2)');
check(inComment.length === 1 && inComment[0].scope === 'comment.block.osp', 'a comment hides what it holds');
process.exit(failed ? 1 : 0);
JS
