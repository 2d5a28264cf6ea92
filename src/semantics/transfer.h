// The transfer function: what one block does to the modal state, and which
// macro or subprogram it runs. Shared by everything that needs modal state
// (the engine's walk, `osplint trace`, the language server, the tests).
#pragma once

#include <optional>

#include "semantics/calls.h"
#include "semantics/config.h"
#include "semantics/modal.h"
#include "syntax/frontend_fast.h"
#include "syntax/model.h"

namespace osplint {

class Catalog;
struct MacroEndMemo;

// The state at the start of a program (from the configuration's machine
// defaults); a subprogram starts with its caller's state, which is unknown.
ModalState initial_state(const Config& config, bool subprogram);

// The last plain CALL of a catalog macro apply_block applied (a CALL
// statement alone on its block, `Pname=value` words only, no subprogram
// summary): the macro, what the block reads of its arguments before the
// macro's end point (PS, and whether PF is given), the state before the
// block and the state before the end point was set. A call of the same macro
// that agrees on these, from the same state but for the position, leaves
// the same state but for the end point (macro_end works that out again).
struct CallTransferMemo {
    const MacroSpec* spec = nullptr;  // nullptr: none remembered
    ArgSeen ps;
    bool pf = false;
    ModalState before, partial;
    uint64_t hits = 0;  // the calls applied from it
    bool fresh = false;  // the last block apply_block applied was applied from it, or made it
};

// Whether apply_block, given a repeat (`repeat`) of the plain call of `spec`
// it applied last (the same line from the state that call left, but for
// the values of the plane's positioning arguments), leaves that state as it
// is: it applied that call from `calls` or made `calls` of it, and took or
// found its end point in `ends` (macro_end_repeats). It then sets the state
// to `calls.partial` and the end point to `ends.end` again: what it left
// after that call. The walk need neither parse nor apply such a line.
bool repeat_leaves_state(const MacroSpec& spec, const ModalState& before, const CallTransferMemo& calls,
                         const MacroEndMemo& ends);

// Whether apply_block, given a repeat of the block it applied last (the
// same line but for the values of the plane's position words, numbers both
// times) from the state that block left (`before`), leaves that state as it
// is. The engine has checked that the block left the state it found but for
// the position in the plane. Such a block is a hole of a modal cycle or a
// positioning block of a MODIN (for a CALL: repeat_leaves_state). It does
// when `before` holds the position in the plane unknown: the block left it
// unknown for a reason its values do not change (a macro's run, G90/G91 not
// known), and the values are read for that position alone (a modal cycle
// keeps no axis word); and when a catalog macro the block runs takes its end
// point from `ends` (macro_end_repeats).
bool repeat_keeps_state(const Block& b, const MacroCall* call, const ModalState& before, const MacroEndMemo& ends);

// Whether apply_block, given such a repeat of a block that runs no macro and
// calls nothing (a hole of a modal cycle, a move under one), from the state
// that block left (`before`), sets the position in the plane to the repeat's
// values and leaves the rest of that state as it is. It does in absolute
// mode, when the block commands nothing that keeps its axis words from
// moving the tool (G4, G71, G92, G50, G22, G23) and `before` holds each of
// its plane position words' values (the block moved the tool there). The
// cycle axis and the cycle's values do not depend on the position in the
// plane. The engine then sets that position from the repeat's text.
bool repeat_sets_plane(const Block& b, const MacroCall* call, const ModalState& before);

// Applies one block to the state. `ends`, when set, is the walk's memo of
// the last macro call's end point (macro_end); `calls`, of the last plain
// call (CallTransferMemo). Both are caches: the state is the same without.
void apply_block(const Block& block, const MacroCall* call, const Catalog& catalog, ModalState& state,
                 MacroEndMemo* ends = nullptr, CallTransferMemo* calls = nullptr);
// The same from `before` (the walk's state before the block, left as it
// is) into `state`, another object, which it overwrites: no copy of the
// state before is made, and none at all for a call CallTransferMemo knows.
// `repeat`: the block is the last one applied with these memos but for the
// values of the words that give the position in the plane, and `before` is
// the state before that one but for the position in the plane (the walk's
// repeated blocks, Rule::quiet_on_repeat); the memos then hold for it
// without comparing their keys again, where their keys read no such value.
void apply_block(const Block& block, const MacroCall* call, const Catalog& catalog, const ModalState& before,
                 ModalState& state, MacroEndMemo* ends = nullptr, CallTransferMemo* calls = nullptr,
                 bool repeat = false);

// Resolves the macro or subprogram a block invokes, with evaluated arguments
// (`links`: see link_arg_specs).
std::optional<MacroCall> resolve_call(const Block& block, const ModalState& before, const Catalog& catalog,
                                      ArgLinks* links = nullptr);
// The same into `call` (whose storage is kept from call to call); false when
// the block invokes nothing.
bool resolve_call(const Block& block, const ModalState& before, const Catalog& catalog, ArgLinks* links,
                  MacroCall& call);
// `call` made again for `block`, when it was resolved from that block and
// the block changed since only in the values and ranges of its words, as a
// CALL line that repeats the line before it changes it
// (FastLineParser::last_again): the arguments' values and the name's range.
void resolve_call_again(const Block& block, const ModalState& before, MacroCall& call);

// The state that flows from a block to its successors: `after` (apply_block's
// result), merged with `before` when the block may be skipped (BLOCK SKIP on
// a `/` block), and without the block's one-shot commands (NCYL, NOEX, G100).
void flow_out(const Block& block, const ModalState& before, ModalState& after);

// Whether a block ends its program where control reaches it (M02, M30, RTS).
bool ends_program(const Block& block);

// Plain moves. Most blocks of a CAM-posted program are `X.. Y.. Z..`, perhaps
// with a sequence name, G0..G3 and F. A block is a plain move when its words
// are only literal X, Y, Z, F and G0/G1/G2/G3 (no `=`, no expression), it has
// no program name, block delete, statement or assignment, and it runs while
// no fixed cycle and no MODIN is known to be modal (`plain_move_state`), and
// no G0..G3 is registered as a macro code (`plain_moves_possible`). On such a
// block resolve_call finds nothing, and apply_block only sets the motion mode,
// the feed (and that one was commanded) and the positions: `apply_plain_move` does just that, and the walk
// calls only the rules that look at such blocks (Rule::sees_plain_moves).
bool is_plain_move_block(const Block& block);
inline bool plain_move_state(const ModalState& s) {
    return s.cycle.known && !s.cycle.value && s.modin.known && !s.modin.value;
}
bool plain_moves_possible(const Catalog& catalog);

// Plain calls: a block that is only `CALL` or `MODIN` of a catalog macro
// (not a user subprogram) with arguments `Pname=value` (an address of two
// letters or more that starts with P: no M, Q, G or N word), or only a
// positioning block of an open MODIN of one with X, Y and Z words of
// numbers (`X56. Y10.`), with no sequence name, program name, block delete,
// comment, assignment or syntax error, reached by a path, while no fixed
// cycle is known to be modal before or after it. The walk hands such a block
// only to the rules that look at one (Rule::sees_plain_calls).
bool is_plain_call(const BlockView& v);
// apply_block(block, nullptr, catalog, state) for a plain move in a plain-move state.
void apply_plain_move(const Block& block, ModalState& state);
// The same for the words of such a block read without it (FastLineParser::plain_move) on line `line`.
void apply_plain_move(const PlainMove& move, uint32_t line, ModalState& state);

// The value of a word in `state`: its literal, or its expression when it can be evaluated.
std::optional<double> word_value(const Block& block, const Word& word, const ModalState& state);
// Integer code of a G/M word when it is a plain literal (G00 -> 0, M52 -> 52).
inline std::optional<int> code_of(const Word& word) {
    if (!word.number) return std::nullopt;
    const double v = *word.number;
    if (!(v >= 0 && v <= 100000)) return std::nullopt;
    // In range, the conversion is exact for a whole number (no call to floor).
    const int c = static_cast<int>(v);
    if (static_cast<double>(c) != v) return std::nullopt;
    return c;
}

}  // namespace osplint
