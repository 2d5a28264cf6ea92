// The analysis driver: control flow per program, modal state to a fixpoint,
// then one pass that hands every block to every enabled rule.
#include <algorithm>
#include <cctype>
#include <functional>
#include <queue>
#include <unordered_map>

#include <fmt/format.h>

#include "engine/analyzer.h"
#include "catalog/catalog.h"
#include "semantics/eval.h"
#include "rules/registry.h"

namespace osplint {

bool ends_program(const Block& b) {
    if (b.statement(StmtKind::Rts)) return true;
    for (const auto& w : b.words)
        if (w.address.size() == 1 && w.address[0] == 'M' && w.number && (*w.number == 2 || *w.number == 30))
            return true;
    return false;
}

bool file_is_subprogram_library(std::string_view path) {
    auto dot = path.rfind('.');
    if (dot == std::string_view::npos) return false;
    std::string ext;
    for (char c : path.substr(dot + 1)) ext += static_cast<char>(std::toupper(static_cast<unsigned char>(c)));
    return ext == "SSB" || ext == "SUB" || ext == "LIB" || ext == "MSB";
}

Labels labels_of(const Block* blocks, uint32_t n) {
    Labels labels;
    for (uint32_t i = 0; i < n; ++i)
        if (blocks[i].sequence) labels[blocks[i].sequence->name].push_back(i);
    return labels;
}

namespace {

// Successor edges of the blocks of one program.
struct Flow {
    std::vector<std::vector<uint32_t>> succ;  // indices relative to the program's first block
    std::vector<bool> exits;                  // the program ends after this block
};

Flow build_flow(const Block* blocks, uint32_t n, const Labels& labels) {
    Flow f;
    f.succ.resize(n);
    f.exits.assign(n, false);
    // Match DO/WHILE n with END n (innermost first, per loop number).
    std::unordered_map<int, std::vector<uint32_t>> open;
    std::vector<int64_t> loop_end(n, -1), loop_head(n, -1);
    for (uint32_t i = 0; i < n; ++i) {
        const Block& b = blocks[i];
        for (const auto& st : b.statements) {
            if ((st.kind == StmtKind::While || st.kind == StmtKind::Do) && st.loop >= 0) {
                open[st.loop].push_back(i);
            } else if (st.kind == StmtKind::End && st.loop >= 0) {
                auto& v = open[st.loop];
                if (!v.empty()) {
                    loop_head[i] = v.back();
                    loop_end[v.back()] = i;
                    v.pop_back();
                }
            }
        }
    }
    for (uint32_t i = 0; i < n; ++i) {
        const Block& b = blocks[i];
        auto& out = f.succ[i];
        bool falls_through = true;
        auto jump_to = [&](const std::string& label) {
            if (auto it = labels.find(label); it != labels.end())
                for (uint32_t t : it->second) out.push_back(t);
        };
        for (const auto& st : b.statements) {
            switch (st.kind) {
                case StmtKind::Goto:
                    jump_to(st.name);
                    if (!b.block_delete) falls_through = false;
                    break;
                case StmtKind::If:
                    jump_to(st.name);
                    break;
                case StmtKind::While:
                    if (loop_end[i] >= 0 && static_cast<uint32_t>(loop_end[i]) + 1 < n)
                        out.push_back(static_cast<uint32_t>(loop_end[i]) + 1);
                    else if (loop_end[i] >= 0)
                        f.exits[i] = true;  // the loop is the last thing in the program
                    break;
                case StmtKind::End:
                    if (loop_head[i] >= 0) {
                        out.push_back(static_cast<uint32_t>(loop_head[i]));
                        // A WHILE loop exits at its head; a bare DO loop only through a jump.
                        if (!b.block_delete) falls_through = false;
                        const Block& head = blocks[loop_head[i]];
                        if (head.statement(StmtKind::While)) falls_through = false;
                    }
                    break;
                default: break;
            }
        }
        if (ends_program(b)) {
            f.exits[i] = true;
            if (!b.block_delete) falls_through = false;
        }
        if (falls_through && i + 1 < n) out.push_back(i + 1);
        if (falls_through && i + 1 == n) f.exits[i] = true;
        std::sort(out.begin(), out.end());
        out.erase(std::unique(out.begin(), out.end()), out.end());
    }
    return f;
}

class Context final : public RuleContext {
public:
    Context(const ProgramFile& file, const Config& config, const ProgramNames* known)
        : file_(file), config_(config), known_(known) {}

    const Config& config() const override { return config_; }
    const Catalog& catalog() const override { return config_.catalog; }
    std::string_view text(ByteRange r) const override {
        const std::string& all = file_.source.text();
        return std::string_view(all).substr(std::min<size_t>(r.begin, all.size()), r.size());
    }
    SourceRange resolve(ByteRange r) const override {
        SourceRange out;
        out.bytes = r;
        out.start = file_.source.position(r.begin);
        out.end = file_.source.position(r.end);
        return out;
    }
    std::string_view path() const override { return file_.path; }
    bool has_label(std::string_view name) const override { return labels_ && labels_->count(std::string(name)); }
    bool has_program(std::string_view name) const override {
        for (const auto& p : file_.programs)
            if (p.name == name) return true;
        return known_ && known_->find(name) != known_->end();
    }
    std::optional<double> eval(const Block& block, ExprId e, const ModalState& state) const override {
        return evaluate(block, e, state);
    }
    Diagnostic& report(const RuleMeta& rule, ByteRange range, std::string message) override {
        const SourceRange where = resolve(range);
        Diagnostic d = make_diagnostic(rule, config_, std::move(message), where,
                                       file_.source.line_text(where.start.line));
        d.fingerprint = fingerprint_for(rule.id, range);
        diagnostics.push_back(std::move(d));
        return diagnostics.back();
    }

    void set_program(const Program* p, const std::unordered_map<std::string, std::vector<uint32_t>>* labels) {
        program_ = p;
        labels_ = labels;
    }

    std::vector<Diagnostic> diagnostics;

private:
    std::string fingerprint_for(std::string_view rule, ByteRange range) {
        const uint32_t line = file_.source.line_of(range.begin);
        const Block* block = nullptr;
        auto it = std::lower_bound(file_.blocks.begin(), file_.blocks.end(), line,
                                   [](const Block& b, uint32_t l) { return b.line < l; });
        if (it != file_.blocks.end() && it->line == line) block = &*it;
        const std::string norm = fingerprint_text(file_.source.line_text(line), file_.source.line_start(line),
                                                  block ? &block->comments : nullptr);
        std::string key = fmt::format("{}|{}|{}", rule, program_ ? program_->name : "", norm);
        int occurrence = ++occurrences_[key];
        return make_fingerprint(rule, program_ ? program_->name : "", norm, occurrence);
    }

    const ProgramFile& file_;
    const Config& config_;
    const ProgramNames* known_;
    const Program* program_ = nullptr;
    const std::unordered_map<std::string, std::vector<uint32_t>>* labels_ = nullptr;
    std::unordered_map<std::string, int> occurrences_;
};

}  // namespace

Diagnostic make_diagnostic(const RuleMeta& rule, const Config& config, std::string message, const SourceRange& range,
                           std::string_view line_text) {
    Diagnostic d;
    d.rule = std::string(rule.id);
    d.name = std::string(rule.name);
    d.severity = config.severity_of(rule.id, rule.severity, rule.enabled_by_default).value_or(rule.severity);
    d.message = std::move(message);
    d.range = range;
    d.line_text = std::string(line_text.substr(0, 1000));
    return d;
}

std::string fingerprint_text(std::string_view line, uint32_t line_start, const std::vector<Comment>* comments) {
    auto in_comment = [&](uint32_t offset) {
        if (!comments) return false;
        for (const auto& c : *comments)
            if (c.range.contains(offset)) return true;
        return false;
    };
    std::string norm;
    for (uint32_t i = 0; i < line.size(); ++i)
        if (!std::isspace(static_cast<unsigned char>(line[i])) && !in_comment(line_start + i)) norm += line[i];
    if (norm.empty())
        for (char c : line)
            if (!std::isspace(static_cast<unsigned char>(c))) norm += c;
    return norm;
}

std::string make_fingerprint(std::string_view rule, std::string_view program, std::string_view block_text,
                             int occurrence) {
    // FNV-1a 64, printed as hex: stable across platforms and runs.
    uint64_t h = 1469598103934665603ull;
    auto mix = [&](std::string_view s) {
        for (unsigned char c : s) {
            h ^= c;
            h *= 1099511628211ull;
        }
        h ^= 0xff;
        h *= 1099511628211ull;
    };
    mix(rule);
    mix(program);
    mix(block_text);
    mix(std::to_string(occurrence));
    return fmt::format("{:016x}", h);
}

void collect_program_names(std::string_view text, ProgramNames& out) {
    size_t i = 0;
    while (i < text.size()) {
        size_t e = text.find_first_of("\r\n", i);
        if (e == std::string_view::npos) e = text.size();
        std::string_view line = text.substr(i, e - i);
        size_t k = line.find_first_not_of(" \t");
        if (k != std::string_view::npos && (line[k] == 'O' || line[k] == 'o')) {
            std::string name = "O";
            for (size_t j = k + 1; j < line.size() && std::isalnum(static_cast<unsigned char>(line[j])); ++j)
                name += static_cast<char>(std::toupper(static_cast<unsigned char>(line[j])));
            if (name.size() > 1) out.insert(name);
        }
        i = e + 1;
    }
}

uint64_t analyze_program(const ProgramInput& input, const Config& config, RuleContext& ctx,
                         const std::vector<std::unique_ptr<Rule>>& rules, const std::function<void(uint32_t)>& before,
                         const BlockHook& after) {
    const uint32_t n = input.count;
    const Block* blocks = input.blocks;
    const Catalog& catalog = config.catalog;
    const Flow flow = build_flow(blocks, n, *input.labels);
    uint64_t transfers = 0;

    // Modal state at every block, to a fixpoint over the flow graph.
    std::vector<std::optional<ModalState>> in(n);
    if (n) in[0] = initial_state(config, input.subprogram);
    std::vector<std::optional<MacroCall>> calls(n);
    std::optional<ModalState> final_state;
    auto transfer = [&](uint32_t i, const ModalState& state) {
        ++transfers;
        const Block& b = blocks[i];
        calls[i] = resolve_call(b, state, catalog);
        ModalState out = state;
        apply_block(b, calls[i] ? &*calls[i] : nullptr, catalog, out);
        if (b.block_delete) out.merge(state);  // BLOCK SKIP may be on or off
        out.clear_one_shots();  // NCYL, NOEX, G100 belong to their block only
        return out;
    };
    auto flow_into = [&](uint32_t t, const ModalState& st) -> bool {
        if (!in[t]) {
            in[t] = st;
            return true;
        }
        ModalState merged = *in[t];
        merged.merge(st);
        if (merged == *in[t]) return false;
        in[t] = std::move(merged);
        return true;
    };
    if (n) {
        std::priority_queue<uint32_t, std::vector<uint32_t>, std::greater<>> work;
        std::vector<bool> queued(n, false);
        work.push(0);
        queued[0] = true;
        while (!work.empty()) {
            const uint32_t i = work.top();
            work.pop();
            queued[i] = false;
            ModalState out = transfer(i, *in[i]);
            if (flow.exits[i]) {
                if (!final_state) final_state = out;
                else final_state->merge(out);
            }
            for (uint32_t t : flow.succ[i])
                if (flow_into(t, out) && !queued[t]) {
                    queued[t] = true;
                    work.push(t);
                }
        }
    }

    // One pass over the blocks for the rules.
    ProgramView pv{*input.program, input.file_blocks, input.subprogram, final_state ? &*final_state : nullptr};
    for (auto& r : rules) r->begin_program(ctx, pv);
    const ModalState unknown_state;
    for (uint32_t i = 0; i < n; ++i) {
        const Block& b = blocks[i];
        const bool reachable = in[i].has_value();
        const ModalState& state = reachable ? *in[i] : unknown_state;
        if (!reachable) calls[i] = resolve_call(b, state, catalog);
        ModalState out = state;
        apply_block(b, calls[i] ? &*calls[i] : nullptr, catalog, out);
        if (before) before(i);
        const BlockView view{b, state, out, calls[i] ? &*calls[i] : nullptr, reachable};
        for (auto& r : rules) r->check_block(ctx, view);
        if (after) after(i, view, calls[i]);
    }
    for (auto& r : rules) r->end_program(ctx, pv);
    return transfers;
}

AnalysisResult analyze(const ProgramFile& file, const Config& config, const AnalysisOptions& options) {
    AnalysisResult result;
    Context ctx(file, config, options.known_programs);

    // The enabled rules for this run (fresh instances: rules may keep per-program state).
    std::vector<std::unique_ptr<Rule>> rules;
    for (auto& r : make_rules()) {
        const RuleMeta& m = r->meta();
        if (!options.only_rules.empty()) {
            if (std::find(options.only_rules.begin(), options.only_rules.end(), m.id) == options.only_rules.end())
                continue;
        } else if (!config.severity_of(m.id, m.severity, m.enabled_by_default)) {
            continue;
        }
        rules.push_back(std::move(r));
    }
    if (options.keep_states) result.blocks.resize(file.blocks.size());

    bool seen_main = false;
    for (const Program& p : file.programs) {
        const uint32_t n = p.end_block - p.first_block;
        const Labels labels = labels_of(file.blocks.data() + p.first_block, n);
        bool subprogram = file_is_subprogram_library(file.path);
        bool has_content = false;
        for (uint32_t i = 0; i < n; ++i) {
            const Block& b = file.blocks[p.first_block + i];
            if (b.statement(StmtKind::Rts)) subprogram = true;
            if (b.kind == LineKind::Block && !b.is_empty()) has_content = true;
        }
        // The first program of a main file is the main program; later ones are subprograms.
        if (has_content && !subprogram) {
            if (seen_main) subprogram = true;
            seen_main = true;
        }
        ctx.set_program(&p, &labels);
        ProgramInput input;
        input.blocks = file.blocks.data() + p.first_block;
        input.count = n;
        input.program = &p;
        input.file_blocks = &file.blocks;
        input.subprogram = subprogram;
        input.labels = &labels;
        BlockHook keep;
        if (options.keep_states)
            keep = [&](uint32_t i, const BlockView& view, const std::optional<MacroCall>& call) {
                auto& info = result.blocks[p.first_block + i];
                info.before = view.before;
                info.after = view.after;
                info.call = call;
                info.reachable = view.reachable;
            };
        result.transfer_count += analyze_program(input, config, ctx, rules, nullptr, keep);
        ctx.set_program(nullptr, nullptr);
    }
    result.diagnostics = std::move(ctx.diagnostics);
    std::stable_sort(result.diagnostics.begin(), result.diagnostics.end(), diagnostic_less);
    return result;
}

}  // namespace osplint
