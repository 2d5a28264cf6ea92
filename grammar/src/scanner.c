// External scanner for the OSP grammar: every token that starts with a letter.
//
// Letters are case-insensitive. Which token a run of letters and digits becomes
// depends on the parse state (the `valid` array) and on the character after it:
//
//   letter + number     `G00`, `X-.75`, `F.2`   -> ADDRESS (the number is lexed by the grammar)
//   letter + `=`        `X=XPOS+8`              -> ADDRESS
//   two letters ...     `GDIA`, `VC12`, `PX`     -> IDENTIFIER (a variable or multi-letter address)
//   V + digits          `V12` (lathe common)     -> IDENTIFIER
//   O + name            at a block start         -> PROGRAM_NAME, after CALL/MODIN -> PROGRAM_REF
//                       (O is no address: `S15O0` inside a block is an error)
//   N + name            at a block start         -> SEQUENCE_NAME, elsewhere -> LABEL
//                       (N + digits stops at the first non-digit: `N10G0` is `N10` `G0`)
//   HA HC DA DC         not followed by `=`      -> OFFSET_CODE (`G56 HA`)
//   keywords            CALL IF EQ SIN BHC MSG DEF ... when the grammar expects them
//
// A name directly followed by `=` or `[` is never a command keyword, program name
// or sequence name: `PT=5` assigns the local PT while `PT LF,LC,...` is the DEF WORK
// contour command, and `NAT=1` is an assignment. The scanner keeps no state.

#include "tree_sitter/parser.h"

#include <stdbool.h>
#include <stdint.h>
#include <string.h>

enum TokenType {
    ADDRESS,
    IDENTIFIER,
    PROGRAM_NAME,
    PROGRAM_REF,
    SEQUENCE_NAME,
    LABEL,
    KW_CALL,
    KW_MODIN,
    KW_MODOUT,
    KW_RTS,
    KW_GOTO,
    KW_IF,
    KW_WHILE,
    KW_DO,
    KW_END,
    KW_NCYL,
    KW_NOEX,
    KW_EMPTY,
    KW_NOT,
    KW_EQ,
    KW_NE,
    KW_GT,
    KW_GE,
    KW_LT,
    KW_LE,
    KW_AND,
    KW_OR,
    KW_EOR,
    FUNCTION_NAME,
    COORDINATE_KEYWORD,
    MNEMONIC,
    COMMAND_KEYWORD,
    OFFSET_CODE,
    UNEXPECTED,
    ERROR_SENTINEL,
};

typedef struct {
    const char *text;
    enum TokenType token;
} Keyword;

// Keywords with a fixed place in the grammar.
static const Keyword kControl[] = {
    {"CALL", KW_CALL},   {"MODIN", KW_MODIN}, {"MODOUT", KW_MODOUT}, {"RTS", KW_RTS},
    {"GOTO", KW_GOTO},   {"IF", KW_IF},       {"WHILE", KW_WHILE},   {"DO", KW_DO},
    {"END", KW_END},     {"NCYL", KW_NCYL},   {"NOEX", KW_NOEX},     {"EMPTY", KW_EMPTY},
    {"NOT", KW_NOT},     {"EQ", KW_EQ},       {"NE", KW_NE},         {"GT", KW_GT},
    {"GE", KW_GE},       {"LT", KW_LT},       {"LE", KW_LE},         {"AND", KW_AND},
    {"OR", KW_OR},       {"EOR", KW_EOR},
};

static const char *const kFunctions[] = {
    "SIN", "COS", "TAN", "ATAN", "ATAN2", "SQRT", "ABS", "BIN", "BCD",
    "ROUND", "FIX", "FUP", "DROUND", "DFIX", "DFUP", "MOD",
};

// Coordinate calculation (hole patterns).
static const char *const kCoordinate[] = {
    "BHC", "LAA", "ARC", "GRDX", "GRDY", "DGRDX", "DGRDY", "SQRX", "SQRY", "OMIT", "RSTRT",
};

// Commands whose operands are ordinary words and assignments.
static const char *const kMnemonics[] = {
    "MSG",   "NMSG",  "COPY",  "COPYE", "CHFC",  "CHFR",   "RTMCR", "RTMDI",
    "FMILR", "FMILF", "PMIL",  "PMILR", "RMILO", "RMILI",  "TLFON", "TLFOFF",
    "TLID",  "CLEAR", "LCLEAR", "DRAW",
};

// Commands (mostly P-series user task / file I/O) with free-form operands.
static const char *const kCommands[] = {
    "DEF",   "PT",    "PUT",  "FWRITC", "FOPENA", "FOPENB", "WRITE", "READ",
    "CLOSE", "PRNT",  "SAVE", "EIN",    "DIN",    "RTI",    "CYLNDR", "DIREC",
};

#define COUNT(a) (sizeof(a) / sizeof((a)[0]))
#define NAME_MAX_LEN 32

static bool in_list(const char *const *list, size_t n, const char *s) {
    for (size_t i = 0; i < n; i++)
        if (strcmp(list[i], s) == 0) return true;
    return false;
}

static bool is_letter(int32_t c) { return (c >= 'A' && c <= 'Z') || (c >= 'a' && c <= 'z'); }
static bool is_digit(int32_t c) { return c >= '0' && c <= '9'; }
static bool is_alnum(int32_t c) { return is_letter(c) || is_digit(c); }
static char upper(int32_t c) { return (char)(c >= 'a' && c <= 'z' ? c - 'a' + 'A' : c); }
static bool is_blank(int32_t c) { return c == ' ' || c == '\t' || c == '\f' || c == '\v'; }

static int32_t peek(TSLexer *lexer) { return lexer->eof(lexer) ? 0 : lexer->lookahead; }

// Skips blanks after the token (the token end is already marked) and returns the
// next character.
static int32_t next_significant(TSLexer *lexer) {
    while (!lexer->eof(lexer) && is_blank(lexer->lookahead)) lexer->advance(lexer, false);
    return peek(lexer);
}

static bool emit(TSLexer *lexer, enum TokenType t) {
    lexer->result_symbol = t;
    return true;
}

// The keyword class of an upper-case name (0 when it is no keyword); shared with
// the front end, which checks lines with the same keyword lists.
int tree_sitter_osp_keyword_class(const char *name) {
    for (size_t i = 0; i < COUNT(kControl); i++)
        if (strcmp(kControl[i].text, name) == 0) return 1;
    if (in_list(kFunctions, COUNT(kFunctions), name)) return 2;
    if (in_list(kCoordinate, COUNT(kCoordinate), name)) return 3;
    if (in_list(kMnemonics, COUNT(kMnemonics), name)) return 4;
    if (in_list(kCommands, COUNT(kCommands), name)) return 5;
    return 0;
}

void *tree_sitter_osp_external_scanner_create(void) { return NULL; }
void tree_sitter_osp_external_scanner_destroy(void *payload) { (void)payload; }
unsigned tree_sitter_osp_external_scanner_serialize(void *payload, char *buffer) {
    (void)payload;
    (void)buffer;
    return 0;
}
void tree_sitter_osp_external_scanner_deserialize(void *payload, const char *buffer, unsigned length) {
    (void)payload;
    (void)buffer;
    (void)length;
}

bool tree_sitter_osp_external_scanner_scan(void *payload, TSLexer *lexer, const bool *valid_symbols) {
    (void)payload;
    const bool *valid = valid_symbols;

    while (!lexer->eof(lexer) && is_blank(lexer->lookahead)) lexer->advance(lexer, true);
    if (valid[ERROR_SENTINEL]) {
        // Error recovery (or a character no other token matches). Every character
        // up to the line end or a comment is one UNEXPECTED token. The grammar
        // accepts it only after the first item of a block, so the parser can
        // resume on the same line but cannot pull words of this line or the next
        // one into the broken construct. One token per character also makes
        // skipping a whole line cost more than giving up the broken block, which
        // keeps recovery on its line.
        if (lexer->eof(lexer) || lexer->lookahead == '\n' || lexer->lookahead == '\r' ||
            lexer->lookahead == '(')
            return false;
        lexer->advance(lexer, false);
        lexer->mark_end(lexer);
        return emit(lexer, UNEXPECTED);
    }
    if (lexer->eof(lexer) || !is_letter(lexer->lookahead)) return false;

    char first = upper(lexer->lookahead);
    lexer->advance(lexer, false);
    int32_t second = peek(lexer);

    if (!is_letter(second)) {
        // A single letter, possibly followed by digits.
        if (is_digit(second) && first == 'N' && (valid[SEQUENCE_NAME] || valid[LABEL])) {
            while (is_digit(peek(lexer))) lexer->advance(lexer, false);
            lexer->mark_end(lexer);
            return emit(lexer, valid[SEQUENCE_NAME] ? SEQUENCE_NAME : LABEL);
        }
        if (is_digit(second) && first == 'O' && (valid[PROGRAM_NAME] || valid[PROGRAM_REF])) {
            while (is_alnum(peek(lexer))) lexer->advance(lexer, false);
            lexer->mark_end(lexer);
            return emit(lexer, valid[PROGRAM_NAME] ? PROGRAM_NAME : PROGRAM_REF);
        }
        if (is_digit(second) && first == 'V' && valid[IDENTIFIER]) {
            // `V12`: a lathe common variable, never the address V.
            while (is_digit(peek(lexer))) lexer->advance(lexer, false);
            lexer->mark_end(lexer);
            return emit(lexer, IDENTIFIER);
        }
        lexer->mark_end(lexer);
        // O is never an address inside a block (`S15O0` is a typo for S1500).
        if (valid[ADDRESS] && first != 'O') return emit(lexer, ADDRESS);
        return false;
    }

    // A name: letters and digits.
    char name[NAME_MAX_LEN + 1];
    size_t len = 0;
    name[len++] = first;
    while (is_alnum(peek(lexer))) {
        if (len < NAME_MAX_LEN + 1) name[len] = upper(peek(lexer));
        len++;
        lexer->advance(lexer, false);
        // `DO1`, `END1`: the loop number may be glued to the keyword.
        if (is_digit(peek(lexer)) && len <= NAME_MAX_LEN) {
            if (len == 2 && name[0] == 'D' && name[1] == 'O' && valid[KW_DO]) {
                lexer->mark_end(lexer);
                return emit(lexer, KW_DO);
            }
            if (len == 3 && name[0] == 'E' && name[1] == 'N' && name[2] == 'D' && valid[KW_END]) {
                lexer->mark_end(lexer);
                return emit(lexer, KW_END);
            }
        }
    }
    lexer->mark_end(lexer);
    bool long_name = len > NAME_MAX_LEN;
    name[long_name ? NAME_MAX_LEN : len] = '\0';

    int32_t after = next_significant(lexer);
    bool operand_follows = after == '=' || after == '[';

    if (!long_name) {
        for (size_t i = 0; i < COUNT(kControl); i++) {
            if (strcmp(kControl[i].text, name) == 0) {
                if (valid[kControl[i].token]) return emit(lexer, kControl[i].token);
                break;
            }
        }
        if (valid[FUNCTION_NAME] && in_list(kFunctions, COUNT(kFunctions), name))
            return emit(lexer, FUNCTION_NAME);
        if (!operand_follows) {
            if (valid[COORDINATE_KEYWORD] && in_list(kCoordinate, COUNT(kCoordinate), name))
                return emit(lexer, COORDINATE_KEYWORD);
            if (valid[MNEMONIC] && in_list(kMnemonics, COUNT(kMnemonics), name))
                return emit(lexer, MNEMONIC);
            if (valid[COMMAND_KEYWORD] && in_list(kCommands, COUNT(kCommands), name))
                return emit(lexer, COMMAND_KEYWORD);
        }
    }
    // `G56 HA`, `G41 DA`: offset number = tool number.
    if (len == 2 && !operand_follows && valid[OFFSET_CODE] && (first == 'H' || first == 'D') &&
        (name[1] == 'A' || name[1] == 'C'))
        return emit(lexer, OFFSET_CODE);
    if (first == 'O' && !operand_follows && valid[PROGRAM_NAME]) return emit(lexer, PROGRAM_NAME);
    if (first == 'O' && valid[PROGRAM_REF]) return emit(lexer, PROGRAM_REF);
    if (first == 'N' && !operand_follows && valid[SEQUENCE_NAME]) return emit(lexer, SEQUENCE_NAME);
    if (first == 'N' && !operand_follows && valid[LABEL]) return emit(lexer, LABEL);
    if (valid[IDENTIFIER]) return emit(lexer, IDENTIFIER);
    return false;
}
