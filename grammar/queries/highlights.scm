; Syntax highlighting for OSP part programs.

(comment) @comment

; Tape framing
(tape_header) @preproc
(tape_mark) @preproc

; Program and sequence names, jump targets, called programs
(program_name) @label
(sequence_name) @label
(label) @label
(program_ref) @function

; G and M codes stand out from the other addresses
((word address: (address) @keyword)
  (#match? @keyword "^[GgMm]$"))

(word address: (address) @property)
(word code: (offset_code) @property)
(word value: (number) @number)
(block_delete) @punctuation.special

; Statements
[
  "CALL" "MODIN" "MODOUT" "RTS"
  "GOTO" "IF" "WHILE" "DO" "END"
  "NCYL" "NOEX"
] @keyword

(coordinate_keyword) @keyword
(mnemonic) @keyword
(command_keyword) @keyword
(command_statement operand: (operand) @string.special)

; Expressions
(number) @number
(hex_constant) @number
(hex_subscript) @number
(string) @string
(empty) @constant.builtin
(variable) @variable
(indexed_variable name: (identifier) @variable)
(assignment left: (variable) @variable)
(function_call name: (function_name) @function.builtin)

[
  "EQ" "NE" "GT" "GE" "LT" "LE"
  "AND" "OR" "EOR" "NOT"
] @keyword.operator

[ "+" "-" "*" "/" "=" ] @operator
[ "[" "]" ] @punctuation.bracket
"," @punctuation.delimiter

; Text the grammar could not read
(unexpected) @error
