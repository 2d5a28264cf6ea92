// Which macro or subprogram a block runs (resolve_call, see transfer.h): a
// CALL or MODIN statement, a registered G- or M-code macro, or a positioning
// block while a MODIN is open; with the arguments evaluated in the state
// before the block.
#include "semantics/transfer.h"

#include <algorithm>
#include <cmath>
#include <string>

#include "catalog/catalog.h"
#include "semantics/transfer_internal.h"

namespace osplint {

using transfer_detail::has_axis_word;
using transfer_detail::has_coord_calc;

std::string_view call_kind_name(CallKind k) {
    switch (k) {
        case CallKind::None: return "none";
        case CallKind::Call: return "CALL";
        case CallKind::Modin: return "MODIN";
        case CallKind::ModinPositioning: return "MODIN positioning";
        case CallKind::GCode: return "G-code macro";
        case CallKind::MCode: return "M-code macro";
    }
    return "?";
}

namespace {

// The names are short ("PR"): compared in line, not through memcmp.
bool same_name(std::string_view a, std::string_view b) {
    if (a.size() != b.size()) return false;
    for (size_t i = 0; i < a.size(); ++i)
        if (a[i] != b[i]) return false;
    return true;
}

std::vector<int> codes(const Block& b, char address) {
    std::vector<int> out;
    for (const auto& w : b.words)
        if (w.address.size() == 1 && w.address[0] == address)
            if (auto c = code_of(w)) out.push_back(*c);
    return out;
}

// Blocks whose X/Y/Z words are not a move of the tool tip in program coordinates.
bool non_motion_axes(const std::vector<int>& g) {
    for (int c : g)
        if (c == 71 || c == 4 || c == 11 || c == 10 || c == 30 || c == 50 || c == 92 || c == 20 ||
            c == 22 || c == 23)
            return true;
    return false;
}

// A CALL or MODIN statement: the words after the keyword are its arguments.
void statement_call(const Block& b, const Statement& st, const Catalog& catalog, ArgLinks* links, MacroCall& call) {
    call.kind = st.kind == StmtKind::Call ? CallKind::Call : CallKind::Modin;
    call.name = st.name;
    call.name_range = st.name_range;
    if (!links) {
        call.spec = catalog.find(st.name);
    } else {
        // A posted program calls the same macro line after line.
        ArgLinks::Found& f = links->found;
        if (f.catalog != &catalog || !same_name(f.name, st.name)) {
            f.catalog = &catalog;
            f.name = st.name;
            f.spec = catalog.find(st.name);
        }
        call.spec = f.spec;
    }
    call.args.reserve(b.words.size());
    for (const auto& w : b.words) {
        const char one = w.address.size() == 1 ? w.address[0] : '\0';  // an address of one letter
        if (one == 'M') {
            call.m_codes.push_back(&w);
        } else if (one == 'Q' && !call.repeat) {
            call.repeat = &w;
        } else if (w.range.begin > st.keyword_range.begin) {
            auto& a = call.args.emplace_back();  // built in place: no temporary to move
            a.name = w.address;
            a.word = &w;
        }
    }
}

// A registered G- or M-code macro (the first code of the block that is one);
// kind None when there is none.
void code_call(const Block& b, const Catalog& catalog, MacroCall& call) {
    for (const auto& w : b.words) {
        if (w.address != "G" && w.address != "M") continue;
        auto c = code_of(w);
        if (!c) continue;
        const MacroSpec* spec = catalog.find_by_code(w.address[0], *c);
        if (!spec) continue;
        call.kind = w.address == "G" ? CallKind::GCode : CallKind::MCode;
        call.name = spec->name;
        call.name_range = w.range;
        call.spec = spec;
        call.args.reserve(b.words.size());
        for (const auto& a : b.words) {
            if (&a == &w) continue;
            if (a.address == "M") {
                call.m_codes.push_back(&a);
                continue;
            }
            if (a.address == "G") continue;  // other G codes of the block (G90, G98 ...)
            const ArgSpec* as = spec->arg_for_address(a.address);
            call.args.push_back(MacroArg{as ? as->name : a.address, &a, {}});
        }
        break;
    }
}

// A positioning block while a MODIN is open runs the modal macro, with the
// arguments of the MODIN line: resolved and linked (link_arg_specs) here.
bool modin_positioning_call(const Block& b, const ModalState& before, const Catalog& catalog, ArgLinks* links,
                            MacroCall& call) {
    if (!before.modin.known || !before.modin.value) return false;
    if (b.statement(StmtKind::Modout) || b.statement(StmtKind::Modin)) return false;
    if (non_motion_axes(codes(b, 'G'))) return false;
    if (!has_axis_word(b) && !has_coord_calc(b)) return false;
    const ActiveModin& m = *before.modin.value;
    call.kind = CallKind::ModinPositioning;
    call.name = m.macro;
    call.modin_line = m.line;
    for (const auto& w : b.words)
        if (w.address == "M") call.m_codes.push_back(&w);
    std::shared_ptr<const ModinArgs> shared = m.shared_args();
    if (links && links->modin.valid && links->modin.modin_args == shared && links->modin.line == m.line &&
        links->modin.macro == m.macro) {
        // The same MODIN as the last positioning block: the same call.
        call.spec = links->modin.spec;
        call.args = links->modin.args;
        call.given_index = links->modin.given_index;
        return true;
    }
    call.spec = catalog.find(m.macro);
    call.args.reserve(m.given().size());
    for (const auto& name : m.given()) call.args.emplace_back().name = name;
    // The known values: one walk of the (small) map, not a search by name per argument.
    for (const auto& [name, value] : m.values())
        for (auto& a : call.args)
            if (same_name(a.name, name)) a.value = Val<double>::of(value);
    link_arg_specs(call, links);
    if (links) {
        ArgLinks::Modin& c = links->modin;
        c.modin_args = std::move(shared);
        c.macro = m.macro;
        c.line = m.line;
        c.spec = call.spec;
        c.args = call.args;
        c.given_index = call.given_index;
        c.valid = true;
    }
    return true;
}

// The positioning block after another of the same open MODIN, with no G or M
// word and no statement ("X14.5 Y-20."): `call` still holds the last one's
// call, which is this one's. False when it does not (the call is then
// resolved in full).
bool keeps_modin_call(const Block& b, const ModalState& before, const ArgLinks& links, MacroCall& call) {
    if (call.kind != CallKind::ModinPositioning || !links.modin.valid || !call.m_codes.empty()) return false;
    if (!b.statements.empty() || !before.modin.known || !before.modin.value) return false;
    const ActiveModin& m = *before.modin.value;
    if (m.line != links.modin.line || call.modin_line != m.line || call.spec != links.modin.spec ||
        m.shared_args() != links.modin.modin_args || m.macro != links.modin.macro || call.name != m.macro)
        return false;
    bool axis = false;
    for (const auto& w : b.words) {
        if (w.address.size() != 1) return false;
        const char a = w.address[0];
        if (a == 'G' || a == 'M') return false;
        axis = axis || transfer_detail::is_axis_address(w.address);
    }
    return axis;
}

}  // namespace

void link_arg_specs(MacroCall& call, ArgLinks* last) {
    if (last && call.spec && last->spec == call.spec && last->names.size() == call.args.size() &&
        std::equal(call.args.begin(), call.args.end(), last->names.begin(),
                   [](const MacroArg& a, const std::string& n) { return same_name(a.name, n); })) {
        for (size_t k = 0; k < call.args.size(); ++k) call.args[k].spec = last->specs[k];
        call.given_index = last->given_index;
        return;
    }
    call.given_index.clear();
    if (call.spec) call.given_index.assign(call.spec->args.size(), 0);
    // given_index holds uint16_t: a call of more arguments is looked up by name.
    if (call.args.size() >= MacroCall::kGivenTwice - 1) call.given_index.clear();
    for (size_t k = 0; k < call.args.size(); ++k) {
        MacroArg& m = call.args[k];
        m.spec = nullptr;
        if (!call.spec) continue;
        const ArgSpec* a = call.spec->arg(m.name);
        if (!a) continue;
        // given() compares names exactly: link only a name written as the spec has it.
        if (a->name != m.name && std::find(a->aliases.begin(), a->aliases.end(), m.name) == a->aliases.end())
            continue;
        m.spec = a;
        if (call.given_index.empty()) continue;
        uint16_t& slot = call.given_index[static_cast<size_t>(a - call.spec->args.data())];
        slot = slot ? MacroCall::kGivenTwice : static_cast<uint16_t>(k + 1);
    }
    if (!last || !call.spec) return;
    last->spec = call.spec;
    last->names.resize(call.args.size());
    last->specs.resize(call.args.size());
    for (size_t k = 0; k < call.args.size(); ++k) {
        last->names[k] = call.args[k].name;
        last->specs[k] = call.args[k].spec;
    }
    last->given_index = call.given_index;
}

const MacroArg* MacroCall::given_by_name(const ArgSpec& a) const {
    if (const MacroArg* m = arg(a.name)) return m;
    for (const auto& alias : a.aliases)
        if (const MacroArg* m = arg(alias)) return m;
    return nullptr;
}

void MacroCall::clear() {
    kind = CallKind::None;
    name.clear();
    name_range = {};
    spec = nullptr;
    summary = nullptr;
    args.clear();
    repeat = nullptr;
    m_codes.clear();
    modin_line = 0;
    given_index.clear();
}

bool resolve_call(const Block& b, const ModalState& before, const Catalog& catalog, ArgLinks* links,
                  MacroCall& call) {
    if (links && b.kind == LineKind::Block && keeps_modin_call(b, before, *links, call)) {
        ++links->modin.kept;
        return true;
    }
    call.clear();
    if (b.kind != LineKind::Block) return false;
    const Statement* st = b.statement(StmtKind::Call);
    if (!st) st = b.statement(StmtKind::Modin);
    if (st) statement_call(b, *st, catalog, links, call);
    else code_call(b, catalog, call);
    if (call.kind == CallKind::None) return modin_positioning_call(b, before, catalog, links, call);
    link_arg_specs(call, links);
    for (auto& a : call.args)
        if (a.word)
            if (auto v = word_value(b, *a.word, before)) a.value = Val<double>::of(*v);
    return true;
}

void resolve_call_again(const Block& b, const ModalState& before, MacroCall& call) {
    if (const Statement* st = b.statements.empty() ? nullptr : &b.statements[0]) call.name_range = st->name_range;
    for (auto& a : call.args) {
        a.value = {};
        if (a.word)
            if (auto v = word_value(b, *a.word, before)) a.value = Val<double>::of(*v);
    }
}

std::optional<MacroCall> resolve_call(const Block& b, const ModalState& before, const Catalog& catalog,
                                      ArgLinks* links) {
    MacroCall call;
    if (!resolve_call(b, before, catalog, links, call)) return std::nullopt;
    return call;
}

}  // namespace osplint
