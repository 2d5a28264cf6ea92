#include "reference.h"

#include <algorithm>
#include <map>
#include <optional>
#include <queue>
#include <unordered_map>
#include <unordered_set>

#include <fmt/format.h>

#include "engine/fingerprint.h"
#include "engine/flow.h"
#include "engine/fold.h"
#include "engine/suppress.h"
#include "rules/registry.h"
#include "semantics/eval.h"
#include "semantics/transfer.h"
#include "support/io.h"
#include "support/text.h"
#include "syntax/directive.h"
#include "syntax/frontend.h"

namespace osplint::testing {
namespace {

uint32_t next_line_start(const ProgramFile& f, const Block& b) {
    const uint32_t n = f.source.line_count();
    return b.line < n ? f.source.line_start(b.line + 1) : f.source.size();
}

class RefContext final : public RuleContext {
public:
    RefContext(const ProgramFile& file, const Config& config, const ProgramNames* known)
        : file_(file), config_(config), known_(known) {}

    const Config& config() const override { return config_; }
    const Catalog& catalog() const override { return config_.catalog; }
    std::string_view text(ByteRange r) const override {
        const std::string& all = file_.source.text();
        return std::string_view(all).substr(std::min<size_t>(r.begin, all.size()), r.size());
    }
    SourceRange resolve(ByteRange r) const override {
        return SourceRange{r, file_.source.position(r.begin), file_.source.position(r.end)};
    }
    std::string_view path() const override { return file_.path; }
    bool has_label(std::string_view name) const override {
        return labels_ && labels_->count(std::string(name)) > 0;
    }
    bool is_jump_target(std::string_view name) const override { return targets_.count(std::string(name)) > 0; }
    bool has_program(std::string_view name) const override {
        for (const auto& p : file_.programs)
            if (p.name == name) return true;
        return known_ && known_->find(name) != known_->end();
    }
    std::optional<double> eval(const Block& block, ExprId e, const ModalState& state) const override {
        return evaluate(block, e, state);
    }
    Diagnostic& report(const RuleMeta& rule, ByteRange range, std::string message) override {
        Diagnostic d;
        d.rule = std::string(rule.id);
        d.name = std::string(rule.name);
        d.severity = config_.severity_of(rule.id, rule.severity, rule.enabled_by_default).value_or(rule.severity);
        d.message = std::move(message);
        d.range = resolve(range);
        d.line_text = abbreviate(file_.source.line_text(d.range.start.line), 1000);
        const uint32_t line = d.range.start.line;
        const Block* block = line >= 1 && line <= file_.blocks.size() ? &file_.blocks[line - 1] : nullptr;
        const std::string norm =
            fingerprint_text(file_.source.line_text(line), file_.source.line_start(line), block ? &block->comments : nullptr);
        const std::string program = program_ ? program_->name : std::string();
        const int occurrence = ++occurrences_[fmt::format("{}|{}|{}", rule.id, program, norm)];
        d.fingerprint = make_fingerprint(rule.id, program, norm, occurrence);
        d.kind = message_kind(rule.id, d.message);
        diagnostics.push_back(std::move(d));
        return diagnostics.back();
    }
    bool folded(const RuleMeta&, std::string_view, ByteRange) override { return false; }  // never folds
    void set_program(const Program* p, const std::unordered_map<std::string, std::vector<uint32_t>>* labels) {
        program_ = p;
        labels_ = labels;
        targets_.clear();
        if (!p) return;
        for (uint32_t i = p->first_block; i < p->end_block && i < file_.blocks.size(); ++i) {
            const Block& b = file_.blocks[i];
            for (const auto& st : b.statements)
                if ((st.kind == StmtKind::Goto || st.kind == StmtKind::If) && !st.name.empty()) targets_.insert(st.name);
            for (const auto& w : b.words)
                if (w.address == "N" && !w.value_text.empty()) targets_.insert("N" + w.value_text);
        }
    }

    std::vector<Diagnostic> diagnostics;

private:
    const ProgramFile& file_;
    const Config& config_;
    const ProgramNames* known_;
    const Program* program_ = nullptr;
    const std::unordered_map<std::string, std::vector<uint32_t>>* labels_ = nullptr;
    std::unordered_set<std::string> targets_;  // names the program's jumps and N words reference
    std::map<std::string, int> occurrences_;
};

bool is_flow(StmtKind k) {
    return k == StmtKind::Goto || k == StmtKind::If || k == StmtKind::While || k == StmtKind::Do ||
           k == StmtKind::End;
}

}  // namespace

FileOutline reference_outline(const ProgramFile& file) {
    FileOutline o;
    o.size = file.source.size();
    o.lines = static_cast<uint32_t>(file.blocks.size());
    for (const Program& p : file.programs) {
        ProgramOutline po;
        const Block& first = file.blocks[p.first_block];
        po.line = first.line;
        po.offset = first.line_start;
        po.name = p.name;
        po.name_range = p.name_range;
        for (uint32_t i = p.first_block; i < p.end_block; ++i) {
            const Block& b = file.blocks[i];
            // A program name starts a program even on a line with a syntax
            // error, and makes it one with content.
            if (b.program_name || (b.kind == LineKind::Block && !b.is_empty())) po.has_content = true;
            FlowSite site;
            for (const auto& st : b.statements) {
                if (st.kind == StmtKind::Rts) po.has_rts = true;
                if (!is_flow(st.kind)) continue;
                site.statements.push_back({st.kind, st.name, st.loop});
                if ((st.kind == StmtKind::Goto || st.kind == StmtKind::If) && !st.name.empty())
                    po.references.push_back(st.name);
            }
            for (const auto& w : b.words)
                if (w.address == "N" && !w.value_text.empty()) po.references.push_back("N" + w.value_text);
            if (!site.statements.empty()) {
                site.line = b.line;
                site.offset = b.line_start;
                site.next = next_line_start(file, b);
                site.block_delete = b.block_delete;
                po.flow.push_back(std::move(site));
            }
        }
        std::sort(po.references.begin(), po.references.end());
        po.references.erase(std::unique(po.references.begin(), po.references.end()), po.references.end());
        o.programs.push_back(std::move(po));
    }
    // Directive lines, their program and the block a `disable` applies to.
    for (size_t pi = 0; pi < file.programs.size(); ++pi) {
        const Program& p = file.programs[pi];
        for (uint32_t i = p.first_block; i < p.end_block; ++i) {
            const Block& b = file.blocks[i];
            const std::string_view text = file.source.line_text(b.line);
            if (!has_directive(b, text)) continue;
            DirectiveSite d;
            d.line = b.line;
            d.offset = b.line_start;
            d.text.assign(text);
            for (const auto& c : b.comments) d.comments.push_back(c.range);
            d.program = pi;
            for (size_t j = i; j < file.blocks.size(); ++j)
                if (suppression_target(file.blocks[j])) {
                    d.target = file.blocks[j].line_start;
                    d.target_line = file.blocks[j].line;
                    break;
                }
            o.directives.push_back(std::move(d));
        }
    }
    return o;
}

FileResult reference_check(const std::string& path, std::string_view text, const Config& config,
                           const AnalysisOptions& options) {
    FileResult result;
    result.path = path;
    // A UTF-16 file is said to be one, not read as a program.
    if (text.size() >= 2 && ((text[0] == '\xFF' && text[1] == '\xFE') || (text[0] == '\xFE' && text[1] == '\xFF'))) {
        result.io_error = kUtf16Message;
        return result;
    }
    const ProgramFile file = parse_program_file(path, std::string(text));
    const FileOutline outline = reference_outline(file);
    RefContext ctx(file, config, options.known_programs);
    std::vector<std::unique_ptr<Rule>> rules = select_rules(builtin_rules(), config, options.only_rules);
    const Catalog& catalog = config.catalog;

    bool seen_main = false;
    for (size_t pi = 0; pi < file.programs.size(); ++pi) {
        const Program& p = file.programs[pi];
        const ProgramOutline& po = outline.programs[pi];
        const uint32_t n = p.end_block - p.first_block;
        const Block* blocks = file.blocks.data() + p.first_block;
        const uint64_t end = outline.program_end(pi);
        const ProgramFlow flow(po, end);
        std::unordered_map<std::string, std::vector<uint32_t>> labels;
        std::unordered_map<uint32_t, uint32_t> by_offset;
        for (uint32_t i = 0; i < n; ++i) {
            if (blocks[i].sequence) labels[blocks[i].sequence->name].push_back(i);
            by_offset[blocks[i].line_start] = i;
        }
        bool subprogram = is_subprogram_file(path) || po.has_rts;
        if (po.has_content && !subprogram) {
            subprogram = seen_main;
            seen_main = true;
        }

        // Successors of every block (whether the edge is a jump).
        std::vector<std::vector<std::pair<uint32_t, bool>>> succ(n);
        std::vector<bool> exits(n, false);
        for (uint32_t i = 0; i < n; ++i) {
            const Block& b = blocks[i];
            const BlockEdges e = block_edges(b, b.line_start, next_line_start(file, b), flow);
            for (std::string_view name : e.jumps)
                if (auto it = labels.find(std::string(name)); it != labels.end())
                    for (uint32_t t : it->second) succ[i].push_back({t, true});
            for (uint32_t off : e.targets) succ[i].push_back({by_offset.at(off), true});
            if (e.falls_through && i + 1 < n) succ[i].push_back({i + 1, false});
            exits[i] = e.exits;
        }

        // The modal state at every block, to a fixpoint.
        std::vector<std::optional<ModalState>> in(n);
        if (n) in[0] = initial_state(config, subprogram);
        std::optional<ModalState> final_state;
        std::priority_queue<uint32_t, std::vector<uint32_t>, std::greater<>> work;
        std::vector<bool> queued(n, false);
        if (n) {
            work.push(0);
            queued[0] = true;
        }
        while (!work.empty()) {
            const uint32_t i = work.top();
            work.pop();
            queued[i] = false;
            const Block& b = blocks[i];
            const std::optional<MacroCall> call = resolve_call(b, *in[i], catalog);
            ModalState out = *in[i];
            apply_block(b, call ? &*call : nullptr, catalog, out);
            flow_out(b, *in[i], out);
            if (exits[i]) {
                if (!final_state) final_state = out;
                else final_state->merge(out);
            }
            for (const auto& [t, jump] : succ[i]) {
                bool changed;
                if (!in[t]) {
                    in[t] = out;
                    if (jump) in[t]->jumped(b.line, jump_range(b));
                    changed = true;
                } else {
                    ModalState merged = *in[t];
                    if (jump) merged.merge_jump(out, b.line, jump_range(b));
                    else merged.merge(out);
                    changed = !(merged == *in[t]);
                    in[t] = std::move(merged);
                }
                if (changed && !queued[t]) {
                    queued[t] = true;
                    work.push(t);
                }
            }
        }

        // Every rule, every block, in order.
        ctx.set_program(&p, &labels);
        ProgramView pv{p, subprogram, nullptr};
        for (auto& r : rules) r->begin_program(ctx, pv);
        const ModalState unknown;
        for (uint32_t i = 0; i < n; ++i) {
            const Block& b = blocks[i];
            const bool reachable = in[i].has_value();
            const ModalState& state = reachable ? *in[i] : unknown;
            const std::optional<MacroCall> call = resolve_call(b, state, catalog);
            ModalState after = state;
            apply_block(b, call ? &*call : nullptr, catalog, after);
            const BlockView view{b, state, after, call ? &*call : nullptr, reachable};
            for (auto& r : rules) r->check_block(ctx, view);
        }
        pv.final_state = final_state ? &*final_state : nullptr;
        for (auto& r : rules) r->end_program(ctx, pv);
        ctx.set_program(nullptr, nullptr);
    }

    std::vector<Diagnostic> all = std::move(ctx.diagnostics);
    std::stable_sort(all.begin(), all.end(), diagnostic_less);
    SuppressionFilter filter(outline, builtin_rules(), config, options.only_rules);
    for (Diagnostic& d : all) {
        SuppressedDiagnostic s;
        if (filter.silence(d, s)) result.suppressed.push_back(std::move(s));
        else result.diagnostics.push_back(std::move(d));
    }
    for (Diagnostic& d : filter.finish()) result.diagnostics.push_back(std::move(d));
    std::stable_sort(result.diagnostics.begin(), result.diagnostics.end(), diagnostic_less);
    std::stable_sort(result.suppressed.begin(), result.suppressed.end(),
                     [](const SuppressedDiagnostic& a, const SuppressedDiagnostic& b) {
                         return diagnostic_less(a.diagnostic, b.diagnostic);
                     });
    return result;
}

namespace {

std::string dump_position(const Position& p) {
    return fmt::format("{}:{}/{}/{}", p.line, p.byte_col, p.cp_col, p.utf16_col);
}
std::string dump_range(const SourceRange& r) {
    return fmt::format("[{},{}) {}-{}", r.bytes.begin, r.bytes.end, dump_position(r.start), dump_position(r.end));
}
void dump_diagnostic(std::string& o, const Diagnostic& d) {
    o += fmt::format("{} {} {} {} '{}'\n", d.rule, d.name, severity_name(d.severity), dump_range(d.range), d.message);
    o += fmt::format("  line '{}' fingerprint {}\n", d.line_text, d.fingerprint);
    for (const auto& n : d.notes)
        o += fmt::format("  note '{}' {}\n", n.message, n.range ? dump_range(*n.range) : std::string("-"));
    for (const auto& f : d.fixes) {
        o += fmt::format("  fix '{}'\n", f.title);
        for (const auto& e : f.edits) o += fmt::format("    edit {} '{}'\n", dump_range(e.range), e.replacement);
    }
}

}  // namespace

std::string dump_result(const FileResult& r) {
    std::string o = "path " + r.path + "\n";
    if (!r.io_error.empty()) o += "io_error " + r.io_error + "\n";
    for (const auto& d : r.diagnostics) dump_diagnostic(o, d);
    for (const auto& s : r.suppressed) {
        o += fmt::format("suppressed kind {} reason '{}' file {} directive {}\n", static_cast<int>(s.kind), s.reason,
                         s.file_scope, s.directive ? dump_range(*s.directive) : std::string("-"));
        dump_diagnostic(o, s.diagnostic);
    }
    return o;
}

std::string dump_outline(const FileOutline& o) {
    std::string s = fmt::format("size {} lines {} error '{}'\n", o.size, o.lines, o.error);
    for (const auto& p : o.programs) {
        s += fmt::format("program line {} offset {} name '{}' [{},{}) rts {} content {}\n", p.line, p.offset, p.name,
                         p.name_range.begin, p.name_range.end, p.has_rts, p.has_content);
        for (const auto& f : p.flow) {
            s += fmt::format("  flow line {} offset {} next {} bd {}:", f.line, f.offset, f.next, f.block_delete);
            for (const auto& st : f.statements)
                s += fmt::format(" {}/{}/{}", static_cast<int>(st.kind), st.name, st.loop);
            s += "\n";
        }
        for (const auto& r : p.references) s += "  ref " + r + "\n";
    }
    for (const auto& d : o.directives) {
        s += fmt::format("directive line {} offset {} program {} target {} line {} '{}'", d.line, d.offset, d.program,
                         d.target ? std::to_string(*d.target) : std::string("-"), d.target_line, d.text);
        for (const auto& c : d.comments) s += fmt::format(" [{},{})", c.begin, c.end);
        s += "\n";
    }
    return s;
}

}  // namespace osplint::testing
