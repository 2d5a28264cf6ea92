// What a block invokes (a subprogram, a macro of the catalog, a positioning
// block of an open MODIN) and the view of a block every consumer of the
// analysis reads: the block, the modal state before and after it, its call.
#pragma once

#include <cstdint>
#include <string>
#include <string_view>
#include <vector>

#include "semantics/modal.h"
#include "syntax/model.h"

namespace osplint {

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
};

struct MacroCall {
    CallKind kind = CallKind::None;
    std::string name;                 // "OZAGR" (the macro, after resolving a G/M code)
    ByteRange name_range;             // the name after CALL/MODIN, or the G/M word
    const MacroSpec* spec = nullptr;  // nullptr: not in the catalog
    bool defined_in_files = false;    // a program of that name exists in the checked files
    // What the user subprogram leaves behind (semantics/summary.h), when the
    // engine analysed it; nullptr: taken to leave the modes as they were.
    const SubprogramSummary* summary = nullptr;
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

// One block as the analysis sees it.
struct BlockView {
    const Block& block;
    const ModalState& before;  // state in effect when the block starts
    const ModalState& after;   // state after the block
    const MacroCall* call;     // nullptr when the block invokes no subprogram or macro
    bool reachable = true;     // false for blocks no path from the program start reaches
};

}  // namespace osplint
