// What a rule sees and how it reports.
//
// The analyzer walks each program once: it computes the modal state at every
// block (analyzer/modal.h), resolves which macro each block invokes (a CALL, a
// MODIN line, a block that triggers an open MODIN, a registered G-code macro),
// evaluates the arguments, and then hands every block to every enabled rule
// in program order. Rules never walk the program themselves.
#pragma once

#include <memory>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "support/diagnostic.h"
#include "semantics/modal.h"
#include "syntax/model.h"
#include "syntax/source.h"

namespace osplint {

class Catalog;
struct MacroSpec;
struct Config;

struct RuleMeta {
    std::string_view id;        // "OSP104", never reused
    std::string_view name;      // "m52-on-call-line"
    Severity severity;          // default severity
    std::string_view summary;   // one line for `osplint rules`
    bool enabled_by_default = true;
};

enum class CallKind {
    None,
    Call,              // CALL Oname ... on this block
    Modin,             // MODIN Oname ... on this block (declares the modal call)
    ModinPositioning,  // a positioning block while a MODIN is open: the macro runs here
    GCode,             // a registered G-code macro (G114 ...) on this block
    MCode,             // a registered M-code macro (M204 ...) on this block
};
std::string_view call_kind_name(CallKind k);  // "CALL", "MODIN", ...

struct MacroArg {
    std::string name;             // argument name as the macro sees it ("PR"; G-code "R" -> "PR")
    const Word* word = nullptr;   // the word on the block (nullptr for MODIN-carried args)
    Val<double> value;            // evaluated in the state before the block
};

struct MacroCall {
    CallKind kind = CallKind::None;
    std::string name;                 // "OZAGR" (the macro, after resolving a G/M code)
    ByteRange name_range;             // the name after CALL/MODIN, or the G/M word
    const MacroSpec* spec = nullptr;  // nullptr: not in the catalog
    bool defined_in_files = false;    // a program of that name exists in the checked files
    std::vector<MacroArg> args;       // in the order written
    const Word* repeat = nullptr;     // Q repeat count on CALL/MODIN (not the PQ argument)
    std::vector<const Word*> m_codes; // M words written on the call block
    uint32_t modin_line = 0;          // for ModinPositioning: the MODIN block's line

    const MacroArg* arg(std::string_view n) const {
        for (const auto& a : args)
            if (a.name == n) return &a;
        return nullptr;
    }
};

struct BlockView {
    const Block& block;
    const ModalState& before;  // state in effect when the block starts
    const ModalState& after;   // state after the block
    const MacroCall* call;     // nullptr when the block invokes no subprogram or macro
    bool reachable = true;     // false for blocks no path from the program start reaches
};

struct ProgramView {
    const Program& program;
    const std::vector<Block>* blocks = nullptr;  // the file's blocks (null when streaming)
    // A subprogram: it has an RTS, lives in a .SSB/.SUB/.LIB/.MSB file, or is not
    // the first program of a main file. Its state at entry is unknown.
    bool is_subprogram = false;
    const ModalState* final_state = nullptr;     // merged state where the program ends
};

class RuleContext {
public:
    virtual ~RuleContext() = default;
    virtual const Config& config() const = 0;
    virtual const Catalog& catalog() const = 0;
    // The text of a range of the block being checked, its line terminator
    // included (a range that runs past the end of the file is cut there). The
    // streaming check holds only the lines in hand, never the whole file.
    virtual std::string_view text(ByteRange r) const = 0;
    virtual std::string_view path() const = 0;
    // Sequence names defined in the current program.
    virtual bool has_label(std::string_view name) const = 0;
    // Whether a program of that name is defined in the checked files.
    virtual bool has_program(std::string_view name) const = 0;
    // Value of an expression of `block` in `state`, when it can be known.
    virtual std::optional<double> eval(const Block& block, ExprId e, const ModalState& state) const = 0;

    // Line and columns of a range anywhere in the file.
    virtual SourceRange resolve(ByteRange r) const = 0;
    // Reports a finding of `rule` at `range`; severity comes from configuration.
    virtual Diagnostic& report(const RuleMeta& rule, ByteRange range, std::string message) = 0;
};

class Rule {
public:
    virtual ~Rule() = default;
    virtual const RuleMeta& meta() const = 0;
    virtual void begin_program(RuleContext&, const ProgramView&) {}
    virtual void check_block(RuleContext&, const BlockView&) {}
    // Whether check_block may do anything (report, or remember something) on a
    // plain move (analyzer.h: is_plain_move_block in a plain_move_state) under
    // this configuration. Rules that return false are not called for such
    // blocks by the streaming check; the differential tests hold it to the
    // same findings as the full analysis.
    virtual bool sees_plain_moves(const Config&) const { return true; }
    // A rule that sees plain moves may say, from what it has seen so far, that
    // the plain moves to come do not matter to it until its next call for
    // another block (OSP004 once it knows where the program's content starts).
    // Plain moves with a sequence name reach it regardless.
    bool wants_plain_moves() const { return wants_plain_moves_; }
    virtual void end_program(RuleContext&, const ProgramView&) {}

protected:
    void set_wants_plain_moves(bool wanted) { wants_plain_moves_ = wanted; }

private:
    bool wants_plain_moves_ = true;
};

}  // namespace osplint
