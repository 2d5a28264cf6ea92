#include "lsp/hints.h"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>

#include "api/check.h"
#include "catalog/catalog.h"
#include "lsp/features.h"
#include "lsp/navigation.h"
#include "support/text.h"

namespace osplint::lsp {

namespace {

// Walks the document up to the last line asked for and keeps the hints of
// the blocks from the first one.
class HintCollector final : public BlockObserver {
public:
    HintCollector(const SourceText& src, const Config& config, uint32_t first, uint32_t last, Encoding enc)
        : src_(src), config_(config), first_(first), last_(last), enc_(enc) {}

    bool block(const BlockView& view, const LineRef& line) override {
        if (line.line < first_) return true;
        if (line.line > last_) return false;
        if (!view.reachable) return true;
        // An argument written as an expression: its value, when known.
        if (view.call)
            for (const auto& a : view.call->args) {
                if (!a.word || a.word->number || !a.value.known || a.word->value_range.empty()) continue;
                hints.push_back({{"position", to_lsp_position(src_, a.word->range.end, enc_)},
                                 {"label", "= " + motion_number(a.value.value)},
                                 {"paddingLeft", true}});
            }
        if (auto env = cycle_envelope(view, config_)) {
            const std::string label = envelope_label(*env);
            if (!label.empty()) {
                std::string tip = "**" + env->title() + "**\n";
                if (env->lowest) tip += "\n- deepest: " + env->points[env->lowest->point].describe();
                if (env->highest) tip += "\n- highest: " + env->points[env->highest->point].describe();
                for (const auto* p : env->unknown_points()) tip += "\n- not known: " + p->describe();
                const uint32_t end = line.start + static_cast<uint32_t>(line.text.size());
                hints.push_back({{"position", to_lsp_position(src_, end, enc_)},
                                 {"label", label},
                                 {"paddingLeft", true},
                                 {"tooltip", {{"kind", "markdown"}, {"value", tip}}}});
            }
        }
        return true;
    }
    json hints = json::array();

private:
    const SourceText& src_;
    const Config& config_;
    uint32_t first_, last_;
    Encoding enc_;
};

}  // namespace

std::string envelope_label(const Envelope& env) {
    if (!env.plane || !env.axis) return "";
    const std::string ax(1, env.axis);
    // An end the analysis cannot bound is shown by its known point, with the
    // side it may pass: the deepest point is at or below it, the highest at
    // or above it.
    auto low = [&]() -> std::string {
        if (!env.lowest) return "";
        return (env.bounded_low ? "" : "\u2264") + ax + motion_number(env.lowest->value);
    };
    auto high = [&]() -> std::string {
        if (env.limit_point && !env.points[*env.limit_point].value.known && env.bounded_high) return ax + "+limit";
        if (!env.highest) return "";
        return (env.bounded_high ? "" : "\u2265") + ax + motion_number(env.highest->value);
    };
    const std::string l = low(), h = high();
    if (l.empty() && h.empty()) return "";
    return "\u2913 " + (l.empty() ? ax + "?" : l) + " \u2912 " + (h.empty() ? ax + "?" : h);
}

json inlay_hints(const DocumentModel& doc, const Config& config, const ProgramNames* known,
                 SubprogramSummaries* summaries, uint32_t first, uint32_t last, Encoding enc,
                 const std::atomic<bool>* cancel) {
    HintCollector collect(doc.source(), config, first, last, enc);
    AnalysisOptions options;
    options.known_programs = known;
    options.summaries = summaries;
    options.observer = &collect;
    options.run_rules = false;
    options.cancel = cancel;
    MemorySource src(doc.text());
    DiscardFindings sink;  // no rules run; the directives' own findings are dropped too
    check_source(doc.path, src, config, options, sink);
    return std::move(collect.hints);
}

json signature_help(const DocumentModel& doc, const Config& config, uint32_t offset) {
    const SourceText& src = doc.source();
    if (src.line_count() == 0) return nullptr;
    const uint32_t line = src.line_of(offset);
    FastLineParser parser;
    Block b;
    parse_source_line(src, line, parser, b);
    const Statement* call = nullptr;
    for (const auto& st : b.statements)
        if ((st.kind == StmtKind::Call || st.kind == StmtKind::Modin) && !st.name.empty()) call = &st;
    if (!call || offset <= call->name_range.end) return nullptr;
    for (const auto& c : b.comments)
        if (c.range.contains(offset)) return nullptr;
    const MacroSpec* spec = config.catalog.find(call->name);
    if (!spec || spec->args.empty()) return nullptr;

    // "CALL OZAGR PX= PY= ...": each argument's place in the label.
    std::string label = (call->kind == StmtKind::Modin ? "MODIN " : "CALL ") + spec->name;
    json params = json::array();
    for (const auto& a : spec->args) {
        label += " ";
        const uint32_t begin = static_cast<uint32_t>(label.size());
        label += a.name + "=";
        params.push_back({{"label", json::array({begin, begin + static_cast<uint32_t>(a.name.size())})},
                          {"documentation", {{"kind", "markdown"}, {"value", argument_doc(*spec, a, 0, nullptr)}}}});
    }
    // The argument under the cursor (or being typed), else the first required
    // one not given yet, else the first not given.
    auto index_of = [&](std::string_view name) -> int {
        const std::string n = upper(name);
        for (size_t i = 0; i < spec->args.size(); ++i) {
            if (spec->args[i].name == n) return static_cast<int>(i);
            for (const auto& al : spec->args[i].aliases)
                if (upper(al) == n) return static_cast<int>(i);
        }
        return -1;
    };
    int active = -1;
    std::vector<bool> given(spec->args.size(), false);
    for (const auto& w : b.words) {
        if (w.range.begin < call->name_range.end) continue;
        const int i = index_of(w.address);
        if (i < 0) continue;
        given[i] = true;
        if (w.range.contains(offset) || w.range.end == offset) active = i;
    }
    if (active < 0) {
        // A name being typed: the letters before the cursor.
        const std::string& t = src.text();
        uint32_t a = offset;
        while (a > call->name_range.end && is_alnum(t[a - 1])) --a;
        if (a < offset) {
            const std::string typed = upper(std::string_view(t).substr(a, offset - a));
            for (size_t i = 0; i < spec->args.size() && active < 0; ++i)
                if (!given[i] && spec->args[i].name.compare(0, typed.size(), typed) == 0) active = static_cast<int>(i);
        }
    }
    for (size_t i = 0; i < spec->args.size() && active < 0; ++i)
        if (!given[i] && spec->args[i].required()) active = static_cast<int>(i);
    for (size_t i = 0; i < spec->args.size() && active < 0; ++i)
        if (!given[i]) active = static_cast<int>(i);
    if (active < 0) active = 0;
    json sig = {{"label", label},
                {"documentation", {{"kind", "markdown"}, {"value", spec->title}}},
                {"parameters", std::move(params)},
                {"activeParameter", active}};
    return json{{"signatures", json::array({std::move(sig)})}, {"activeSignature", 0}, {"activeParameter", active}};
}

}  // namespace osplint::lsp
