// What a rule sees and how it reports.
//
// The engine walks each program once for the rules: it computes the modal
// state at every block (semantics/transfer.h, to a fixpoint where jumps and
// loops join paths), resolves which macro each block invokes (a CALL, a MODIN
// line, a block that triggers an open MODIN, a registered G-code macro),
// evaluates the arguments, and hands every block to every enabled rule in
// program order (a plain move only to the rules that ask for one, and to a
// rule that takes them so, read into its values without a block: see
// takes_plain_values). Rules never walk the program themselves.
#pragma once

#include <array>
#include <concepts>
#include <limits>
#include <memory>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "osplint/diagnostic.h"
#include "semantics/calls.h"
#include "semantics/config.h"
#include "semantics/modal.h"
#include "support/function_ref.h"
#include "syntax/model.h"

namespace osplint {

// The rules whose findings the engine itself makes, by role; each rule's
// metadata takes its ID from here, and nothing else names them by string.
// What does not parse: every other rule trusts the syntax it reads, so a file
// with its findings is never fixed.
inline constexpr std::string_view kSyntaxErrorRule = "OSP001";
// A suppression directive naming an unknown or unsuppressible rule, or malformed.
inline constexpr std::string_view kBadSuppressionRule = "OSP901";
// A suppression directive that silences nothing.
inline constexpr std::string_view kUnusedSuppressionRule = "OSP902";

class Catalog;
struct Config;

// Whether a rule's findings carry a fix, and of which kind (Fix::safe): the
// rule's doc page says the same in its header (the unit tests compare them).
enum class FixSafety { None, Safe, Unsafe };

// What a finding of the rule means on the machine, when it is right.
enum class RuleCategory {
    Alarm,        // the control stops the job with an alarm where the program reaches it
    WrongMotion,  // no alarm: the machine moves, cuts or returns other than the program says
    Suspicious,   // the program may not do what its author meant; the machine itself is not at risk
    Directive,    // about osplint's own directives in comments
};

// How settled a rule is. A preview rule is off until a configuration or
// `--select` turns it on, and its findings may still change.
enum class RuleStatus { Stable, Preview };

// Which blocks the engine hands to a rule's check_block.
enum class RuleBlocks {
    // Every block but a plain move (semantics/transfer.h: a G0/G1 block with
    // nothing else, in a state where it cannot matter to such a rule). Most
    // rules look only at these, and the engine walks a posted program of
    // plain moves without them.
    Statements,
    // Those, and the plain moves that carry a sequence name: a rule about
    // the names (OSP003), which no other plain move can matter to.
    Named,
    All,  // every block, plain moves included
};

// A rule, as data: `osplint rules`, the doc page's header (generated from it
// and checked by the unit tests), the configuration and the engine read it.
struct RuleMeta {
    std::string_view id;        // "OSP104", never reused
    std::string_view name;      // "m52-on-call-line"
    Severity severity;          // default severity
    std::string_view summary;   // one line for `osplint rules`
    RuleCategory category = RuleCategory::Suspicious;
    bool enabled_by_default = true;
    FixSafety fix = FixSafety::None;
    RuleBlocks blocks = RuleBlocks::Statements;
    // Whether a suppression directive may silence it (a block that does not
    // parse is never silenced: every other rule trusts the syntax it reads).
    bool suppressible = true;
    RuleStatus status = RuleStatus::Stable;
    std::string_view since = "0.1.0";  // the osplint version that introduced it
    // An [analysis] switch of osplint.toml that turns the rule on (at its
    // default severity) unless [rules] says otherwise: "explain-unknown".
    std::string_view analysis_switch;
    // Whether an ID prefix ("OSP0" in [rules]), `--select` and `--ignore`
    // reach it. false: only its own ID or name in [rules] turns it off (a
    // file that does not parse is never passed over by a broad selection).
    bool selected_by_prefix = true;
    // Whether it also reports what holds on some paths only (a mode that a
    // loop's jump or a branch may bring), at the severity of [analysis]
    // may-findings (report_may).
    bool reports_may = false;
};

// A rule ID that names no rule any more: IDs are never reused, and a
// configuration, a command line or a directive that still names it is told
// what became of it.
struct RetiredRule {
    std::string_view id;           // "OSP117"
    std::string_view name;         // its name then
    std::string_view replaced_by;  // the ID that took its place (a redirect), or empty: removed
    std::string_view since;        // the osplint version that retired it
};

std::string_view category_name(RuleCategory c);  // "alarm", "wrong-motion", ...
std::string_view status_name(RuleStatus s);      // "stable", "preview"

// The header paragraph of the rule's doc page (docs/rules/OSPnnn.md), made
// from its metadata: default severity, category, version, and whether it is
// off by default, in preview, fixable or unsuppressible. The unit tests hold
// every page to it (and write it with OSPLINT_UPDATE_SNAPSHOTS=1).
std::string rule_doc_header(const RuleMeta& meta);

// A plain move in a plain-move state, read without its block (PlainMove):
// what a rule that takes such moves so sees of it. Its sequence name, when it
// has one (move.sequence), is not one a jump or an N word names.
struct PlainMoveView {
    const PlainMove& move;
    ByteRange range;           // the line, as Block::range
    uint32_t line = 0;         // 1-based
    const ModalState& before;  // state in effect when the block starts
    const ModalState& after;   // state after the block
};

struct ProgramView {
    const Program& program;
    // A subprogram: it has an RTS, lives in a .SSB/.SUB/.LIB/.MSB file, or is not
    // the first program of a main file. Its state at entry is unknown.
    bool is_subprogram = false;
    const ModalState* final_state = nullptr;  // merged state where the program ends (end_program only)
};

class RuleContext {
public:
    virtual ~RuleContext() = default;
    virtual const Config& config() const = 0;
    // The travel limits of X, Y and Z of config(), looked up the first time
    // they are asked for (a context keeps its configuration for its lifetime):
    // a wrong work offset asks for them on every move.
    const AxisLimits& axis_limits() const {
        if (!axis_limits_ready_) {
            axis_limits_ = osplint::axis_limits(config().travel);
            axis_limits_ready_ = true;
        }
        return axis_limits_;
    }
    virtual const Catalog& catalog() const = 0;
    // The text of a range of the block being checked, its line terminator
    // included (a range that runs past the end of the file is cut there). The
    // engine holds only the lines in hand, never the whole file.
    virtual std::string_view text(ByteRange r) const = 0;
    virtual std::string_view path() const = 0;
    // Whether the current program defines the sequence name `name`. Exact in
    // end_program for the names its jumps and N words reference (the engine
    // learns a program's sequence names as it walks it, and keeps only those).
    virtual bool has_label(std::string_view name) const = 0;
    // Whether a GOTO, an IF or an N word of the current program names `name`
    // (known for the whole program from its begin_program on).
    virtual bool is_jump_target(std::string_view name) const = 0;
    // Whether a program of that name is defined in the checked files.
    virtual bool has_program(std::string_view name) const = 0;
    // Value of an expression of `block` in `state`, when it can be known.
    virtual std::optional<double> eval(const Block& block, ExprId e, const ModalState& state) const = 0;

    // Line and columns of a range anywhere in the file.
    virtual SourceRange resolve(ByteRange r) const = 0;
    // Reports a finding of `rule` at `range`; severity comes from configuration.
    // The reference stays valid until the rule returns.
    virtual Diagnostic& report(const RuleMeta& rule, ByteRange range, std::string message) = 0;
    // For rules that can report in bulk (a finding on every move): whether a
    // finding of `rule` of the kind `key` (findings of one kind differ only in
    // their numbers) at `range` is folded into another one and only counted
    // (engine/fold.h). When it is, the rule does not report it and need not
    // build its message; when it is not, the rule reports it next.
    virtual bool folded(const RuleMeta& rule, std::string_view key, ByteRange range) = 0;

private:
    mutable AxisLimits axis_limits_{};
    mutable bool axis_limits_ready_ = false;
};

// Reports a finding that holds on some paths only ("G91 may be in effect
// here"): at the severity [analysis] may-findings gives, never above the
// rule's own; nullptr when may-findings is "off" (the rule then adds nothing).
inline Diagnostic* report_may(RuleContext& ctx, const RuleMeta& rule, ByteRange range, std::string message) {
    const std::optional<Severity> may = ctx.config().may_severity;
    if (!may) return nullptr;
    Diagnostic& d = ctx.report(rule, range, std::move(message));
    if (static_cast<int>(*may) < static_cast<int>(d.severity)) d.severity = *may;
    return &d;
}

class Rule {
public:
    virtual ~Rule() = default;
    virtual const RuleMeta& meta() const = 0;
    virtual void begin_program(RuleContext&, const ProgramView&) {}
    virtual void check_block(RuleContext&, const BlockView&) {}
    // Whether check_block may do anything (report, or remember something) on a
    // plain move (semantics/transfer.h: is_plain_move_block in a
    // plain_move_state) under this configuration. Rules that return false are
    // not called for such blocks; the differential tests hold the engine to
    // the same findings as a walk that shows every rule every block.
    // The default is what the metadata declares (RuleMeta::blocks); a rule
    // overrides it only when the answer depends on the configuration.
    virtual bool sees_plain_moves(const Config&) const { return meta().blocks != RuleBlocks::Statements; }
    // Whether check_block may do anything (report, or remember something) on
    // a plain call line (semantics/transfer.h, is_plain_call: a CALL or MODIN
    // of a catalog macro with `Pname=value` arguments only, or a positioning
    // block of an open MODIN with X, Y and Z numbers only, while no fixed
    // cycle is modal). A posted program may be made of such lines, and most
    // rules are about something else (jumps, names, M and G codes, fixed
    // cycles): rules that return false are not called for them. As for plain
    // moves, the differential tests hold the engine to a walk that shows
    // every rule every block.
    virtual bool sees_plain_calls() const { return true; }
    // What a block must have for check_block to do anything on it: a rule
    // whose check_block returns at once on any other block, and keeps nothing
    // of it, says so, and the walk leaves it out of the other blocks (most
    // blocks of a program call no macro and hold no fixed cycle). Any of the
    // bits will do; kEveryBlock (the default): every block. As for plain
    // moves, the differential tests hold the engine to a walk that shows
    // every rule every block.
    enum BlockNeed : uint8_t {
        kEveryBlock = 0,
        kCall = 1,         // BlockView::call is set (a macro or a subprogram)
        kCycleBefore = 2,  // active_cycle(before): a fixed cycle is known to be modal before the block
        kCycleAfter = 4,   // active_cycle(after): and after it
        kMWord = 8,        // a word whose address is M
        kGWord = 16,       // a word whose address is G
        kStatement = 32,   // a statement (CALL, GOTO, IF, NCYL, MODIN, RTS, ...)
        kNamed = 64,       // a sequence name, or a word whose address is N
        kError = 128,      // a syntax error (Block::errors)
    };
    // The BlockNeed bits a block has, but for the three that the states and
    // the call give (the walk adds those).
    static uint8_t what_block_has(const Block& b) {
        uint8_t has = 0;
        for (const Word& w : b.words) {
            if (w.address.size() != 1) continue;
            switch (w.address[0]) {
                case 'M': has |= kMWord; break;
                case 'G': has |= kGWord; break;
                case 'N': has |= kNamed; break;
                default: break;
            }
        }
        if (!b.statements.empty()) has |= kStatement;
        if (b.sequence) has |= kNamed;
        if (!b.errors.empty()) has |= kError;
        return has;
    }
    virtual uint8_t block_needs() const { return kEveryBlock; }
    // Of a rule that sees plain calls: whether check_block may do anything
    // on a plain call of `spec` made as `kind` (Call, Modin or
    // ModinPositioning), in any state. Asked once per macro and kind in a
    // walk: a rule about some macros only (those with a tool shift, those
    // that plunge at rapid) says no for the others.
    virtual bool sees_plain_calls_of(const MacroSpec&, CallKind) const { return true; }
    // Whether check_block may be left out on a block that repeats the block
    // the rules saw just before it, when that one gave no finding at all
    // (Walk::check): the same text but for the values of the words that give
    // the position in the plane (X and Y under G17; on a CALL or MODIN line,
    // the arguments MacroSpec::position_arg gives for those axes), numbers
    // both times, with the state before and the state after each equal to
    // the other block's but for the position in the plane. A posted program
    // writes such blocks by the thousand: the same macro call or the same
    // hole, moved. `spec` is the catalog macro the block runs (nullptr:
    // none). A rule says yes when what check_block does on such a block reads
    // none of what differs (the plane's positions, those words' values and
    // ranges, the block's line and ranges), so that it would again report
    // nothing, and when doing it a second time changes nothing in the rule's
    // own state (no count, no "last block seen"). The differential tests
    // hold the engine to a walk that shows every rule every block.
    virtual bool quiet_on_repeat(const Config&, const MacroSpec* spec) const {
        (void)spec;
        return false;
    }
    // For a rule that is not quiet_on_repeat for the macro `v` runs: whether,
    // from what it has seen so far, check_block would now do nothing on a
    // repeat of `v`, the block it saw last (OSP202 once it holds the macro
    // and the calls its notes show). The walk asks after each block that may
    // be repeated, and leaves the rule out of the repeats that follow while
    // it sees nothing else.
    virtual bool quiet_on_repeat_of(const BlockView& v) const {
        (void)v;
        return false;
    }
    // The values of a position word for which a rule does nothing on a repeat
    // (repeat_values_decide): from lo to hi, both included.
    struct QuietRange {
        double lo = -std::numeric_limits<double>::infinity();
        double hi = std::numeric_limits<double>::infinity();
    };
    // For a rule that is not quiet_on_repeat_of(v): whether what check_block
    // would do on a repeat of `v` depends only on the values of the position
    // words the repeat changes (their plane axes in `axes`, in line order),
    // and is nothing for some of them (OSP301: the travel limits). Then
    // `quiet` holds, for each word, the values for which check_block would
    // do nothing on such a repeat nor change the rule's state: a repeat
    // whose values are all inside is told from its text, and any other is
    // parsed and shown to the rule. The walk asks after each block that may
    // be repeated.
    virtual bool repeat_values_decide(const Config& config, const BlockView& v, const std::array<char, 2>& axes,
                                      uint8_t count, std::array<QuietRange, 2>& quiet) {
        (void)config, (void)v, (void)axes, (void)count, (void)quiet;
        return false;
    }
    // A rule that sees plain moves may say, from what it has seen so far, that
    // the plain moves to come do not matter to it until its next call for
    // another block (OSP004 once it knows where the program's content starts).
    // A plain move where paths join (its sequence name is one a jump or an N
    // word names) reaches it regardless, and so do the other plain moves with
    // a sequence name if it is a RuleBlocks::Named rule.
    bool wants_plain_moves() const { return wants_plain_moves_; }
    // Whether check_plain_move does, for a plain move, all that check_block
    // would do for its block. While every rule that wants plain moves says so
    // (and, for a move with a sequence name, every RuleBlocks::Named rule), a
    // batch analysis reads such moves without building their blocks (the
    // differential tests hold the findings to a walk that shows every rule
    // every block).
    virtual bool takes_plain_values() const { return false; }
    virtual void check_plain_move(RuleContext&, const PlainMoveView&) {}
    // For X, Y and Z, a magnitude under which an axis word of a plain move
    // (without a sequence name, in absolute mode or an unknown one) does not
    // matter to the rule: a move whose every axis word is smaller than its
    // axis's bound makes check_plain_move do nothing at all. nullopt: any
    // plain move may matter. While every rule that wants plain moves gives
    // bounds, a batch analysis applies runs of such moves at once, as when
    // none wants them (Walk::skim_run); a move that may pass a bound is
    // shown to the rules one by one.
    virtual std::optional<std::array<double, 3>> quiet_below(const Config&) const { return std::nullopt; }
    virtual void end_program(RuleContext&, const ProgramView&) {}
    // A copy of the rule with its state (the engine's checkpoints, from which
    // the language server re-analyses a document after an edit).
    virtual std::unique_ptr<Rule> clone() const = 0;
    // For the language server's edits, which end a walk where its state is
    // again the previous analysis's (engine/checkpoints.cpp): whether this
    // rule's state equals `other`'s (a rule of the same class), and moving
    // each byte range the state holds to an edited text (`move` returns false
    // for a range it cannot move; so does this, then). A rule that keeps
    // state of its own compares all of it in `bool same_as(const Self&)
    // const` and lists its ranges in `bool each_range(move)`; without
    // same_as it never compares equal.
    virtual bool same_state(const Rule& other) const = 0;
    virtual bool move_ranges(FunctionRef<bool(ByteRange&)> move) = 0;
    // Whether same_state can hold: the rule keeps no state of its own, or compares it.
    virtual bool compares_state() const = 0;

protected:
    void set_wants_plain_moves(bool wanted) { wants_plain_moves_ = wanted; }

private:
    bool wants_plain_moves_ = true;
};

// The base of every rule: gives it clone() by copying the rule.
template <class Self>
class RuleBase : public Rule {
public:
    std::unique_ptr<Rule> clone() const override { return std::make_unique<Self>(static_cast<const Self&>(*this)); }
    bool same_state(const Rule& other) const override {
        if (wants_plain_moves() != other.wants_plain_moves()) return false;
        if constexpr (sizeof(Self) == sizeof(RuleBase<Self>)) return true;  // no state of its own
        else if constexpr (requires(const Self& a) { { a.same_as(a) } -> std::same_as<bool>; })
            return static_cast<const Self&>(*this).same_as(static_cast<const Self&>(other));
        else
            return false;
    }
    bool compares_state() const override {
        return sizeof(Self) == sizeof(RuleBase<Self>) ||
               requires(const Self& a) { { a.same_as(a) } -> std::same_as<bool>; };
    }
    bool move_ranges(FunctionRef<bool(ByteRange&)> move) override {
        if constexpr (requires(Self& s) { s.each_range(move); }) return static_cast<Self*>(this)->each_range(move);
        else return true;
    }
};

// The rules an engine runs: their metadata and fresh instances. The rules
// layer provides the built-in set (rules/registry.h).
class RuleRegistry {
public:
    virtual ~RuleRegistry() = default;
    // Every rule, in ID order.
    virtual const std::vector<RuleMeta>& all() const = 0;
    // Fresh instances of every rule, in ID order (rules keep state while a file is checked).
    virtual std::vector<std::unique_ptr<Rule>> make_all() const = 0;
    // Rule IDs retired since: renamed (redirected) or removed.
    virtual const std::vector<RetiredRule>& retired() const;
    const RuleMeta* find(std::string_view id) const {
        for (const auto& m : all())
            if (m.id == id) return &m;
        return nullptr;
    }
    // Whether `key` is a retired ID or name (resolve follows its redirect).
    bool is_retired(std::string_view key) const;
    // The rules as a configuration names them, retired IDs included.
    RuleIdentities identities() const;
    // The rule that `key` names, by ID or by name, in any case ("OSP104",
    // "m52-on-call-line"): what the command line, osplint.toml and the
    // suppression directives accept (semantics/config.h: resolve_rule).
    const RuleMeta* resolve(std::string_view key) const;
    // " (did you mean 'OSP104'?)" for a key that names no rule; empty when no
    // ID or name is near.
    std::string suggestion(std::string_view key) const;
};

// The rules that run under a configuration: every enabled rule, or exactly
// `only` when it is not empty (fixtures and `trace`). One definition for every
// entry point.
bool rule_runs(const RuleMeta& meta, const Config& config, const std::vector<std::string>& only);
std::vector<std::unique_ptr<Rule>> select_rules(const RuleRegistry& registry, const Config& config,
                                                const std::vector<std::string>& only);

// Whether an ID or prefix ("OSP2", "OSP104") selects the rule `id`.
bool rule_matches(std::string_view id, std::string_view pattern);

}  // namespace osplint
