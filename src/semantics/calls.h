// What a block invokes (a subprogram, a macro of the catalog, a positioning
// block of an open MODIN) and the view of a block every consumer of the
// analysis reads: the block, the modal state before and after it, its call.
#pragma once

#include <cstdint>
#include <string>
#include <string_view>
#include <vector>

#include "catalog/catalog.h"
#include "semantics/modal.h"
#include "syntax/model.h"

namespace osplint {

struct ArgSpec;
struct MacroSpec;
struct SubprogramSummary;

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
    // The catalog's argument this is, by its name or an alias written exactly
    // so (link_arg_specs); nullptr when there is none or it was not looked up.
    const ArgSpec* spec = nullptr;
};

struct MacroCall {
    CallKind kind = CallKind::None;
    std::string name;                 // "OZAGR" (the macro, after resolving a G/M code)
    ByteRange name_range;             // the name after CALL/MODIN, or the G/M word
    const MacroSpec* spec = nullptr;  // nullptr: not in the catalog
    // What the user subprogram leaves behind (semantics/summary.h), when the
    // engine analysed it; nullptr: taken to leave the modes as they were.
    const SubprogramSummary* summary = nullptr;
    std::vector<MacroArg> args;       // in the order written
    const Word* repeat = nullptr;     // Q repeat count on CALL/MODIN (not the PQ argument)
    std::vector<const Word*> m_codes; // M words written on the call block
    uint32_t modin_line = 0;          // for ModinPositioning: the MODIN block's line

    // Set by link_arg_specs: for each argument of `spec`, 1 + the index in
    // `args` of the one given for it, 0 when none is, kGivenTwice when two are.
    std::vector<uint16_t> given_index;
    static constexpr uint16_t kGivenTwice = 0xFFFF;

    const MacroArg* arg(std::string_view n) const {
        for (const auto& a : args)
            if (a.name == n) return &a;
        return nullptr;
    }
    // The argument given for `a` (an argument of any spec): by its name, else
    // by its aliases in order; nullptr when not given. Inline: it runs for
    // every argument of the spec, on every call, in several rules.
    const MacroArg* given(const ArgSpec& a) const {
        if (spec && !given_index.empty() && given_index.size() == spec->args.size()) {
            // Names and aliases are distinct within a spec, so each argument links
            // to one ArgSpec at most; one given twice (by its name and an alias)
            // takes the order of the names.
            const auto at = reinterpret_cast<std::uintptr_t>(&a);
            const auto first = reinterpret_cast<std::uintptr_t>(spec->args.data());
            if (at >= first && at < first + given_index.size() * sizeof(ArgSpec)) {
                const uint16_t slot = given_index[(at - first) / sizeof(ArgSpec)];
                if (slot != kGivenTwice) return slot ? &args[slot - 1] : nullptr;
            }
        }
        return given_by_name(a);
    }
    // As given, by comparing the names: an argument of another spec, a call
    // not linked, or one giving the argument twice.
    const MacroArg* given_by_name(const ArgSpec& a) const;
    // Back to a call of nothing, keeping the storage for the next one (the
    // walk reuses one call for every block): a member added above must be
    // reset there too.
    void clear();
};

// What a check reads of one argument of a call: whether it is given, and
// its value when known. Two calls that agree on it for every argument a check
// reads get the same answer from it (the memos of OSP301 and OSP302).
struct ArgSeen {
    bool given = false, known = false;
    double value = 0;
    static ArgSeen of(const MacroArg* m) {
        return m ? ArgSeen{true, m->value.known, m->value.known ? m->value.value : 0} : ArgSeen{};
    }
    friend bool operator==(const ArgSeen&, const ArgSeen&) = default;
};

// What link_arg_specs found for the argument names of the last call it
// linked. A posted program writes the same call (macro and argument names,
// in the same order) thousands of times: the next such call takes the links
// without looking its names up. Valid while the catalog is (one per walk).
struct ArgLinks {
    // The catalog's macro of the last name a CALL or MODIN named.
    struct Found {
        const Catalog* catalog = nullptr;
        std::string name;
        const MacroSpec* spec = nullptr;
    } found;
    const MacroSpec* spec = nullptr;
    std::vector<std::string> names;
    std::vector<const ArgSpec*> specs;
    std::vector<uint16_t> given_index;
    // The macro and arguments of the last positioning block of an open MODIN,
    // resolved and linked: the next block of the same MODIN takes them as they
    // are. `modin_args` holds the MODIN's arguments (ActiveModin::shared_args),
    // which are never changed while shared: the same pointer, macro and line
    // are the same MODIN.
    struct Modin {
        std::shared_ptr<const ModinArgs> modin_args;
        std::string macro;
        uint32_t line = 0;
        const MacroSpec* spec = nullptr;
        std::vector<MacroArg> args;
        std::vector<uint16_t> given_index;
        bool valid = false;
        uint64_t kept = 0;  // positioning blocks that kept the call before as it was
    } modin;
};

// Looks up the catalog's argument of each of `call`'s arguments, so that
// MacroCall::given compares pointers instead of names (it runs for every
// argument of the spec, on every call, in several rules). `last`, when set,
// is the previous call's links, and becomes this one's.
void link_arg_specs(MacroCall& call, ArgLinks* last = nullptr);

// One block as the analysis sees it.
struct BlockView {
    const Block& block;
    const ModalState& before;  // state in effect when the block starts
    const ModalState& after;   // state after the block
    const MacroCall* call;     // nullptr when the block invokes no subprogram or macro
    bool reachable = true;     // false for blocks no path from the program start reaches
    // A plain move in a plain-move state (semantics/transfer.h), as the engine
    // knows it: a hint that spares a rule its own checks; what a rule finds
    // must not depend on it (the differential tests leave it unset).
    bool plain_move = false;
};

}  // namespace osplint
