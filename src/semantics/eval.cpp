#include "semantics/eval.h"

#include <cmath>
#include <numbers>

namespace osplint {
namespace {

constexpr int kMaxDepth = 256;

std::optional<double> eval_rec(const Block& b, ExprId id, const ModalState& s, int depth);

std::optional<double> number_of(const Block& b, ExprId id, const ModalState& s, int depth) {
    return eval_rec(b, id, s, depth + 1);
}

double deg2rad(double d) { return d * std::numbers::pi / 180.0; }
double rad2deg(double r) { return r * 180.0 / std::numbers::pi; }

std::optional<double> apply_function(const std::string& f, const std::vector<double>& a) {
    auto one = [&]() -> std::optional<double> { return a.size() == 1 ? std::optional(a[0]) : std::nullopt; };
    if (f == "SIN") { if (auto v = one()) return std::sin(deg2rad(*v)); return {}; }
    if (f == "COS") { if (auto v = one()) return std::cos(deg2rad(*v)); return {}; }
    if (f == "TAN") { if (auto v = one()) return std::tan(deg2rad(*v)); return {}; }
    if (f == "ATAN") { if (auto v = one()) return rad2deg(std::atan(*v)); return {}; }
    if (f == "ATAN2") { if (a.size() == 2) return rad2deg(std::atan2(a[0], a[1])); return {}; }
    if (f == "SQRT") { if (auto v = one(); v && *v >= 0) return std::sqrt(*v); return {}; }
    if (f == "ABS") { if (auto v = one()) return std::fabs(*v); return {}; }
    if (f == "ROUND" || f == "DROUND") { if (auto v = one()) return std::round(*v); return {}; }
    if (f == "FIX" || f == "DFIX") { if (auto v = one()) return std::trunc(*v); return {}; }
    if (f == "FUP" || f == "DFUP") {
        if (auto v = one()) return *v >= 0 ? std::ceil(*v) : std::floor(*v);
        return {};
    }
    if (f == "MOD") { if (a.size() == 2 && a[1] != 0) return std::fmod(a[0], a[1]); return {}; }
    return {};  // BIN, BCD and anything else: not evaluated
}

std::optional<double> eval_node(const Block& b, ExprId id, const ModalState& s, int depth);

// Every value, the parts' as well as the whole's, is finite or unknown: a sum or
// a product too large for a double (`VC1=[A*B]`) is unknown, never an
// infinity that a comparison would turn back into 0 or 1.
std::optional<double> eval_rec(const Block& b, ExprId id, const ModalState& s, int depth) {
    const std::optional<double> v = eval_node(b, id, s, depth);
    if (v && !std::isfinite(*v)) return {};
    return v;
}

std::optional<double> eval_node(const Block& b, ExprId id, const ModalState& s, int depth) {
    if (depth > kMaxDepth) return {};
    const ExprNode* n = b.expr(id);
    if (!n) return {};
    switch (n->kind) {
        case ExprKind::Number:
        case ExprKind::HexConst:
            return n->number;
        case ExprKind::Bracket:
            return n->children.size() == 1 ? number_of(b, n->children[0], s, depth) : std::nullopt;
        case ExprKind::Variable: {
            auto key = variable_key(b, id, s);
            if (!key) return {};
            auto it = s.vars.find(*key);
            if (it == s.vars.end()) return {};
            return it->second;
        }
        case ExprKind::Unary: {
            if (n->children.size() != 1) return {};
            auto v = number_of(b, n->children[0], s, depth);
            if (!v) return {};
            if (n->op == "-") return -*v;
            if (n->op == "+") return *v;
            return {};  // NOT: bitwise on integers, not needed statically
        }
        case ExprKind::Binary: {
            if (n->children.size() != 2) return {};
            auto l = number_of(b, n->children[0], s, depth);
            if (!l) return {};
            auto r = number_of(b, n->children[1], s, depth);
            if (!r) return {};
            const std::string& op = n->op;
            if (op == "+") return *l + *r;
            if (op == "-") return *l - *r;
            if (op == "*") return *l * *r;
            if (op == "/") return *r == 0 ? std::nullopt : std::optional(*l / *r);
            if (op == "EQ") return *l == *r ? 1.0 : 0.0;
            if (op == "NE") return *l != *r ? 1.0 : 0.0;
            if (op == "GT") return *l > *r ? 1.0 : 0.0;
            if (op == "GE") return *l >= *r ? 1.0 : 0.0;
            if (op == "LT") return *l < *r ? 1.0 : 0.0;
            if (op == "LE") return *l <= *r ? 1.0 : 0.0;
            return {};
        }
        case ExprKind::Function: {
            std::vector<double> args;
            for (ExprId c : n->children) {
                auto v = number_of(b, c, s, depth);
                if (!v) return {};
                args.push_back(*v);
            }
            return apply_function(n->text, args);
        }
        case ExprKind::String:
        case ExprKind::Empty:
        case ExprKind::Error:
            return {};
    }
    return {};
}

std::string format_index(double v) {
    long long i = static_cast<long long>(v);
    return std::to_string(i);
}

}  // namespace

std::optional<std::string> variable_key(const Block& b, ExprId id, const ModalState& s) {
    const ExprNode* n = b.expr(id);
    if (!n || n->kind != ExprKind::Variable) return {};
    if (n->children.empty()) return n->text;
    std::vector<double> subs;
    for (ExprId c : n->children) {
        auto v = eval_rec(b, c, s, 1);
        if (!v || *v != std::floor(*v) || std::fabs(*v) > 1e9) return {};
        subs.push_back(*v);
    }
    // Common variables: VC[12] is VC12 (and V[12] is V12 on lathes).
    if ((n->text == "VC" || n->text == "V") && subs.size() == 1) return n->text + format_index(subs[0]);
    std::string key = n->text + "[";
    for (size_t i = 0; i < subs.size(); ++i) {
        if (i) key += ",";
        key += format_index(subs[i]);
    }
    return key + "]";
}

std::optional<double> evaluate(const Block& block, ExprId e, const ModalState& state) {
    return eval_rec(block, e, state, 0);
}

std::optional<int> common_variable_number(std::string_view key) {
    if (key.size() < 3 || key[0] != 'V' || key[1] != 'C') return {};
    int n = 0;
    for (size_t i = 2; i < key.size(); ++i) {
        if (key[i] < '0' || key[i] > '9') return {};
        n = n * 10 + (key[i] - '0');
        if (n > 100000) return {};
    }
    return n;
}

}  // namespace osplint
