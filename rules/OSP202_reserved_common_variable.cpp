// OSP202 reserved-common-variable: VC120-VC128 used by a program that calls the
// macros which use them internally.
#include <algorithm>
#include <string>
#include <vector>

#include "semantics/eval.h"
#include "rules/macro_support.h"

namespace osplint {
namespace {

constexpr RuleMeta kMeta{
    .id = "OSP202",
    .name = "reserved-common-variable",
    .severity = Severity::Warning,
    .summary = "VC120-VC128 used in a program that calls macros which overwrite them",
    .category = RuleCategory::WrongMotion,
};

std::string clobber_source(const Catalog& catalog, const MacroSpec& s) {
    return macro::note_ref(catalog, s, "VC120");
}

struct Use {
    ByteRange range;
    int number = 0;
    bool write = false;
    friend bool operator==(const Use&, const Use&) = default;
};

struct Clobber {
    const MacroSpec* spec = nullptr;
    ByteRange range;
    uint32_t line = 0;
    std::string via;  // the user subprogram that runs the macro ("O100"), or empty: the call runs it
    friend bool operator==(const Clobber&, const Clobber&) = default;
};

class ReservedCommonVariable final : public RuleBase<ReservedCommonVariable> {
public:
    const RuleMeta& meta() const override { return kMeta; }
    // A repeat of a quiet block is quiet (Rule::quiet_on_repeat). Unless the macro overwrites VC120-VC128: each call is noted (the first three, where they are).
    bool quiet_on_repeat(const Config&, const MacroSpec* spec) const override {
        return !spec || !spec->has(Hazard::OverwritesVc120To128);
    }

    // Once the macro is named and the notes' calls are held, another call
    // of it with no variable in its line adds nothing; nor does a
    // positioning block of an open MODIN (the MODIN line was the call).
    bool quiet_on_repeat_of(const BlockView& v) const override {
        const MacroCall* c = v.call;
        if (!c || !c->spec || c->summary) return false;
        if (c->kind != CallKind::ModinPositioning &&
            (calls_.size() < kShownCalls || std::find(specs_.begin(), specs_.end(), c->spec) == specs_.end()))
            return false;
        return std::none_of(v.block.exprs.begin(), v.block.exprs.end(),
                            [](const ExprNode& n) { return n.kind == ExprKind::Variable; });
    }

    void begin_program(RuleContext&, const ProgramView&) override {
        uses_.clear();
        calls_.clear();
        specs_.clear();
        names_.clear();
        distinct_ = 0;
    }

    void check_block(RuleContext& ctx, const BlockView& v) override {
        const Block& b = v.block;
        if (const MacroCall* c = v.call; c && c->spec && c->spec->has(Hazard::OverwritesVc120To128) &&
                                         (c->kind == CallKind::Call || c->kind == CallKind::Modin ||
                                          c->kind == CallKind::GCode || c->kind == CallKind::MCode))
            add_call({c->spec, macro::call_range(*c, b), b.line, {}});
        // A user subprogram that runs such a macro overwrites them as well.
        if (const MacroCall* c = v.call; c && c->summary && !c->summary->clobbers_reserved.empty())
            if (const MacroSpec* spec = ctx.catalog().find(c->summary->clobbers_reserved))
                add_call({spec, c->name_range, b.line, c->summary->name});
        for (size_t i = 0; i < b.exprs.size(); ++i) {
            const ExprNode& n = b.exprs[i];
            if (n.kind != ExprKind::Variable) continue;
            auto key = variable_key(b, static_cast<ExprId>(i), v.before);
            if (!key) continue;
            auto num = common_variable_number(*key);
            if (!num || *num < 120 || *num > 128) continue;
            const bool written = std::any_of(b.assignments.begin(), b.assignments.end(), [&](const auto& a) {
                return a.target >= 0 && static_cast<size_t>(a.target) == i;
            });
            uses_.push_back({n.range, *num, written});
        }
    }

    void end_program(RuleContext& ctx, const ProgramView&) override {
        if (calls_.empty()) return;
        const Clobber& first = calls_.front();
        const std::string& names = names_;
        const int distinct = distinct_;
        for (const Use& u : uses_) {
            std::string var = "VC" + std::to_string(u.number);
            auto& d = ctx.report(
                kMeta, u.range,
                var + " is " + (u.write ? "written" : "read") + " here, but " + names +
                    (distinct == 1 ? " uses VC120-VC128 internally and overwrites them when it runs ("
                                   : " use VC120-VC128 internally and overwrite them when they run (") +
                    clobber_source(ctx.catalog(), *first.spec) +
                    "): a value kept there across the call is lost; use a common variable outside VC120-VC128");
            for (const auto& c : calls_) {
                d.notes.push_back({(c.via.empty() ? c.spec->name : c.via + " runs " + c.spec->name + ", which") +
                                       " overwrites " + var + " when it runs",
                                   ctx.resolve(c.range)});
            }
        }
    }

    bool same_as(const ReservedCommonVariable& o) const {
        return uses_ == o.uses_ && calls_ == o.calls_ && specs_ == o.specs_ && names_ == o.names_ &&
               distinct_ == o.distinct_;
    }
    template <class Move>
    bool each_range(Move&& move) {
        for (Use& u : uses_)
            if (!move(u.range)) return false;
        for (Clobber& c : calls_)
            if (!move(c.range)) return false;
        return true;
    }

private:
    // The first calls (the notes show three) and the names of the macros
    // called: bounded by the catalog, not by the number of calls.
    static constexpr size_t kShownCalls = 3;
    void add_call(Clobber c) {
        // By the whole name: one may be the start of another (OZAG, OZAGR).
        if (std::find(specs_.begin(), specs_.end(), c.spec) == specs_.end()) {
            specs_.push_back(c.spec);
            names_ += (names_.empty() ? "" : ", ") + c.spec->name;
            ++distinct_;
        }
        if (calls_.size() < kShownCalls) calls_.push_back(std::move(c));
    }
    std::vector<const MacroSpec*> specs_;  // those named in names_
    std::vector<Use> uses_;
    std::vector<Clobber> calls_;
    std::string names_;
    int distinct_ = 0;
};

}  // namespace

std::unique_ptr<Rule> make_rule_OSP202() { return std::make_unique<ReservedCommonVariable>(); }

}  // namespace osplint
