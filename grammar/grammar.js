/**
 * Tree-sitter grammar for Okuma OSP-M part programs (OSP5020M and later).
 *
 * The grammar is line oriented: every source line is one block, and the line
 * terminator (LF, CRLF or a lone CR) is a real token. Everything made of
 * letters (addresses, names, keywords, program and sequence names) is lexed by
 * the external scanner in src/scanner.c, because the right token depends on the
 * parse state and on what follows the letters (`G00X100` are two words, `GDIA`
 * is a local variable, `NAT00` is a sequence name at the start of a block and a
 * jump target after `G85`, `NCYL` is a command, `PT` is a local before `=` and
 * the DEF WORK contour command otherwise). See NODES.md for the node types.
 */

const PREC = {
  OR: 1, // OR EOR
  AND: 2, // AND
  COMPARE: 3, // EQ NE GT GE LT LE
  ADD: 4, // + -
  MUL: 5, // * /
  UNARY: 6, // - + NOT
};

module.exports = grammar({
  name: 'osp',

  externals: $ => [
    $.address,
    $.identifier,
    $.program_name,
    $.program_ref,
    $.sequence_name,
    $.label,
    $._kw_call,
    $._kw_modin,
    $._kw_modout,
    $._kw_rts,
    $._kw_goto,
    $._kw_if,
    $._kw_while,
    $._kw_do,
    $._kw_end,
    $._kw_ncyl,
    $._kw_noex,
    $._kw_empty,
    $._kw_not,
    $._kw_eq,
    $._kw_ne,
    $._kw_gt,
    $._kw_ge,
    $._kw_lt,
    $._kw_le,
    $._kw_and,
    $._kw_or,
    $._kw_eor,
    $.function_name,
    $.coordinate_keyword,
    $.mnemonic,
    $.command_keyword,
    $.offset_code,
    $.unexpected,
    $._error_sentinel,
  ],

  extras: $ => [/[ \t\f\v\uFEFF]/, $.comment],

  // Choices that only group other rules: inlined so that they add no nodes.
  inline: $ => [$._line, $._block_prefix, $._item, $._item_or_junk, $._tail_statement, $._argument, $._subscript],

  rules: {
    source_file: $ => seq(
      repeat(seq(optional($._line), $._newline)),
      optional($._line),
    ),

    _newline: _ => /\r\n|\r|\n/,

    _line: $ => choice($.tape_header, $.tape_mark, $.block),

    // `$NAME.EXT%` before a program on tape.
    tape_header: _ => token(seq('$', /[^\r\n]*/)),

    // `%` (end of a program on tape) and `%%` (end of communication).
    tape_mark: _ => token(choice('%', '%%')),

    // `( ... )` anywhere; an unclosed comment runs to the end of the line.
    comment: _ => token(seq('(', /[^)\r\n]*/, optional(')'))),

    // `unexpected` (text the scanner could not lex, see src/scanner.c) may follow
    // the first item of a block, so that the parser resumes after it on the same
    // line; it cannot start a block, so recovery never starts a new block (with a
    // program or sequence name) in the middle of a line.
    block: $ => choice(
      seq($._block_prefix, repeat($._item_or_junk), optional($._tail_statement)),
      seq($._item, repeat($._item_or_junk), optional($._tail_statement)),
      $._tail_statement,
    ),

    _item_or_junk: $ => choice($._item, $.unexpected),

    _block_prefix: $ => choice(
      seq(field('delete', $.block_delete), optional(field('sequence', $.sequence_name))),
      seq(field('sequence', $.sequence_name), optional(field('delete', $.block_delete))),
      field('program', $.program_name),
    ),

    block_delete: _ => '/',

    _item: $ => choice(
      $.word,
      $.assignment,
      $.label,
      $.ncyl_statement,
      $.noex_statement,
      $.modout_statement,
      $.rts_statement,
      $.goto_statement,
      $.if_statement,
      $.while_statement,
      $.do_statement,
      $.end_statement,
    ),

    // Statements that take the rest of the block as their operands.
    _tail_statement: $ => choice(
      $.call_statement,
      $.modin_statement,
      $.coordinate_statement,
      $.mnemonic_statement,
      $.command_statement,
    ),

    // `G00`, `X-.75`, `F.2`, `X3.` (number glued to the letter), `X=XPOS+8`,
    // and the offset codes `HA` `HC` `DA` `DC` (offset number taken from the tool).
    word: $ => choice(
      seq(field('address', $.address), field('value', alias($._word_number, $.number))),
      seq(field('address', $.address), '=', field('value', $._expression)),
      field('code', $.offset_code),
    ),

    _word_number: _ => token.immediate(/[+-]?([0-9]+\.?[0-9]*|\.[0-9]+)/),

    // `VC1=2`, `VTOFX[16]=VTOFX[6]`, and multi-letter addresses / locals
    // (`FA=200`, `PX=0`, `CNTR = PSRT`); the front end tells them apart.
    assignment: $ => seq(
      field('left', choice(alias($.identifier, $.variable), $.indexed_variable)),
      '=',
      field('right', $._expression),
    ),

    ncyl_statement: $ => alias($._kw_ncyl, 'NCYL'),
    noex_statement: $ => alias($._kw_noex, 'NOEX'),
    modout_statement: $ => alias($._kw_modout, 'MODOUT'),
    rts_statement: $ => alias($._kw_rts, 'RTS'),

    goto_statement: $ => seq(alias($._kw_goto, 'GOTO'), field('target', $.label)),

    if_statement: $ => seq(
      alias($._kw_if, 'IF'),
      '[', field('condition', $._expression), ']',
      optional(alias($._kw_goto, 'GOTO')),
      field('target', $.label),
    ),

    while_statement: $ => seq(
      alias($._kw_while, 'WHILE'),
      '[', field('condition', $._expression), ']',
      alias($._kw_do, 'DO'),
      field('loop', $.number),
    ),

    do_statement: $ => seq(alias($._kw_do, 'DO'), field('loop', $.number)),

    end_statement: $ => prec.right(seq(alias($._kw_end, 'END'), optional(field('loop', $.number)))),

    call_statement: $ => seq(
      alias($._kw_call, 'CALL'),
      field('name', $.program_ref),
      repeat(field('argument', $._argument)),
    ),

    modin_statement: $ => seq(
      alias($._kw_modin, 'MODIN'),
      field('name', $.program_ref),
      repeat(field('argument', $._argument)),
    ),

    _argument: $ => choice($.word, $.assignment, $.unexpected),

    // BHC LAA ARC GRDX GRDY DGRDX DGRDY SQRX SQRY OMIT RSTRT.
    coordinate_statement: $ => seq(
      field('keyword', $.coordinate_keyword),
      repeat(field('argument', $._argument)),
    ),

    // MSG NMSG COPY COPYE CHFC CHFR RTMCR RTMDI FMILR ... TLFON TLFOFF CLEAR DRAW ...
    mnemonic_statement: $ => seq(
      field('keyword', $.mnemonic),
      repeat(field('argument', choice($.word, $.assignment, $.label, $.unexpected))),
    ),

    // DEF PT PUT FWRITC WRITE CLOSE ...: free-form operands.
    command_statement: $ => seq(
      field('keyword', $.command_keyword),
      repeat(field('operand', choice($.operand, $.unexpected))),
    ),

    operand: _ => token(repeat1(choice(/[^ \t\f\v\r\n(']/, /'[^'\r\n]*'/))),

    // ---------------------------------------------------------------- expressions

    _expression: $ => choice(
      $.number,
      $.hex_constant,
      $.string,
      $.empty,
      alias($.identifier, $.variable),
      $.indexed_variable,
      $.function_call,
      $.bracket_expression,
      $.unary_expression,
      $.binary_expression,
    ),

    number: _ => /[0-9]+\.?[0-9]*|\.[0-9]+/,

    // `#81H`
    hex_constant: _ => /#[0-9A-Fa-f]+[Hh]/,

    // `'END OF BAR'`; an unclosed string runs to the end of the line.
    string: _ => token(seq("'", /[^'\r\n]*/, optional("'"))),

    empty: $ => alias($._kw_empty, 'EMPTY'),

    // `VC[CNTR]`, `VTOHT[[VTLCN],10001]`, `VORD[002C]`.
    indexed_variable: $ => seq(
      field('name', $.identifier),
      '[',
      field('index', $._subscript),
      optional(seq(',', field('index', $._subscript))),
      ']',
    ),

    _subscript: $ => choice($._expression, $.hex_subscript),

    // Hex digits with at least one letter digit (`002C`); `0024` is a number.
    hex_subscript: _ => /[0-9][0-9A-Fa-f]*[A-Fa-f][0-9A-Fa-f]*/,

    function_call: $ => seq(
      field('name', $.function_name),
      '[',
      field('argument', $._expression),
      repeat(seq(',', field('argument', $._expression))),
      ']',
    ),

    bracket_expression: $ => seq('[', field('expression', $._expression), ']'),

    unary_expression: $ => prec(PREC.UNARY, seq(
      field('operator', choice('-', '+', alias($._kw_not, 'NOT'))),
      field('operand', $._expression),
    )),

    binary_expression: $ => {
      const table = [
        [PREC.MUL, '*'],
        [PREC.MUL, '/'],
        [PREC.ADD, '+'],
        [PREC.ADD, '-'],
        [PREC.COMPARE, alias($._kw_eq, 'EQ')],
        [PREC.COMPARE, alias($._kw_ne, 'NE')],
        [PREC.COMPARE, alias($._kw_gt, 'GT')],
        [PREC.COMPARE, alias($._kw_ge, 'GE')],
        [PREC.COMPARE, alias($._kw_lt, 'LT')],
        [PREC.COMPARE, alias($._kw_le, 'LE')],
        [PREC.AND, alias($._kw_and, 'AND')],
        [PREC.OR, alias($._kw_or, 'OR')],
        [PREC.OR, alias($._kw_eor, 'EOR')],
      ];
      return choice(...table.map(([p, op]) => prec.left(p, seq(
        field('left', $._expression),
        field('operator', op),
        field('right', $._expression),
      ))));
    },
  },
});
