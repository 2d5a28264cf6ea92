// The catalog's `when` conditions: a small recursive-descent parser (or of
// ands of primaries) into a node array, and their three-valued evaluation.
#include "catalog/condition.h"

#include <cctype>
#include <charconv>
#include <cmath>

#include "support/text.h"

namespace osplint {

namespace {

bool is_name(std::string_view s) {
    if (s.empty() || !std::isalpha(static_cast<unsigned char>(s[0]))) return false;
    for (char c : s)
        if (!std::isalnum(static_cast<unsigned char>(c))) return false;
    return true;
}

std::optional<double> number(std::string_view s) {
    double v = 0;
    auto [end, ec] = std::from_chars(s.data(), s.data() + s.size(), v);
    if (ec != std::errc() || end != s.data() + s.size() || !std::isfinite(v)) return std::nullopt;
    return v;
}

// One atom as written; nullopt when it is none of the forms of condition.h.
std::optional<ConditionAtom> read_atom(std::string_view word) {
    using K = ConditionAtom::Kind;
    const std::string w = upper(word);
    ConditionAtom a;
    if (w == "G17" || w == "G18" || w == "G19") {
        a.kind = K::Plane;
        a.number = std::stoi(w.substr(1));
        return a;
    }
    if (w == "G90" || w == "G91") {
        a.kind = K::Distance;
        a.number = std::stoi(w.substr(1));
        return a;
    }
    if (w == "M52" || w == "M53" || w == "M54") {
        a.kind = K::MCode;
        a.number = std::stoi(w.substr(1));
        return a;
    }
    if (w == "M3" || w == "M4" || w == "M5") {
        a.kind = K::Spindle;
        a.number = w[1] - '0';
        return a;
    }
    if (w == "G40" || w == "G41" || w == "G42") {
        a.kind = K::CutterComp;
        a.number = std::stoi(w.substr(1));
        return a;
    }
    if (w.rfind("GIVEN:", 0) == 0 && is_name(std::string_view(w).substr(6))) {
        a.kind = K::Given;
        a.arg = w.substr(6);
        return a;
    }
    if (auto eq = w.find('='); eq != std::string::npos && is_name(std::string_view(w).substr(0, eq))) {
        if (auto v = number(std::string_view(w).substr(eq + 1))) {
            a.kind = K::ArgEquals;
            a.arg = w.substr(0, eq);
            a.value = *v;
            return a;
        }
    }
    return std::nullopt;
}

Tri tri_not(Tri a) { return a == Tri::Unknown ? a : (a == Tri::True ? Tri::False : Tri::True); }
Tri tri_and(Tri a, Tri b) {
    if (a == Tri::False || b == Tri::False) return Tri::False;
    if (a == Tri::True && b == Tri::True) return Tri::True;
    return Tri::Unknown;
}
Tri tri_or(Tri a, Tri b) {
    if (a == Tri::True || b == Tri::True) return Tri::True;
    if (a == Tri::False && b == Tri::False) return Tri::False;
    return Tri::Unknown;
}

}  // namespace

class ConditionParser {
public:
    ConditionParser(std::string_view s, Condition& c) : s_(s), c_(c) {}

    bool run(std::string& error) {
        root_ = parse_or();
        if (root_ < 0) {
            error = error_;
            return false;
        }
        if (!token().empty()) {
            error = "unexpected \"" + std::string(token()) + "\"";
            return false;
        }
        c_.root_ = root_;
        return true;
    }

private:
    void skip() {
        while (i_ < s_.size() && (s_[i_] == ' ' || s_[i_] == '\t')) ++i_;
    }
    std::string_view token() {
        skip();
        if (i_ >= s_.size()) return {};
        if (s_[i_] == '(' || s_[i_] == ')') return s_.substr(i_, 1);
        size_t j = i_;
        while (j < s_.size() && s_[j] != ' ' && s_[j] != '\t' && s_[j] != '(' && s_[j] != ')') ++j;
        return s_.substr(i_, j - i_);
    }
    int add(Condition::Node n) {
        c_.nodes_.push_back(std::move(n));
        return static_cast<int>(c_.nodes_.size()) - 1;
    }
    int binary(Condition::Node::Op op, int l, int r) {
        Condition::Node n;
        n.op = op;
        n.left = l;
        n.right = r;
        return add(std::move(n));
    }
    int parse_or() {
        int l = parse_and();
        while (l >= 0 && upper(token()) == "OR") {
            i_ += 2;
            int r = parse_and();
            if (r < 0) return -1;
            l = binary(Condition::Node::Op::Or, l, r);
        }
        return l;
    }
    int parse_and() {
        int l = parse_primary();
        while (l >= 0 && upper(token()) == "AND") {
            i_ += 3;
            int r = parse_primary();
            if (r < 0) return -1;
            l = binary(Condition::Node::Op::And, l, r);
        }
        return l;
    }
    int parse_primary() {
        if (++depth_ > 64) return fail("nested too deeply");
        std::string_view t = token();
        int out = -1;
        if (t.empty()) {
            out = fail("a condition is missing");
        } else if (t == "(") {
            ++i_;
            out = parse_or();
            if (out >= 0) {
                if (token() == ")") ++i_;
                else out = fail("a ')' is missing");
            }
        } else if (t == ")") {
            out = fail("unexpected ')'");
        } else if (upper(t) == "NOT") {
            i_ += 3;
            int inner = parse_primary();
            if (inner >= 0) {
                Condition::Node n;
                n.op = Condition::Node::Op::Not;
                n.left = inner;
                out = add(std::move(n));
            }
        } else if (upper(t) == "AND" || upper(t) == "OR") {
            out = fail("\"" + std::string(t) + "\" needs a condition before it");
        } else if (auto a = read_atom(t)) {
            i_ += t.size();
            Condition::Node n;
            n.atom = std::move(*a);
            out = add(std::move(n));
        } else {
            out = fail("unknown condition \"" + std::string(t) +
                       "\"; expected G17, G18, G19, G90, G91, M52, M53, M54, M3, M4, M5, G40, G41, G42, given:NAME or NAME=number");
        }
        --depth_;
        return out;
    }
    int fail(std::string msg) {
        if (error_.empty()) error_ = std::move(msg);
        return -1;
    }

    std::string_view s_;
    Condition& c_;
    size_t i_ = 0;
    int depth_ = 0;
    int root_ = -1;
    std::string error_;
};

std::optional<Condition> Condition::parse(std::string_view text, std::string& error) {
    Condition c;
    c.text_ = std::string(text);
    ConditionParser p(text, c);
    if (!p.run(error)) return std::nullopt;
    return c;
}

Tri Condition::eval(FunctionRef<Tri(const ConditionAtom&)> decide) const {
    return root_ < 0 ? Tri::True : eval_node(root_, decide);
}

Tri Condition::eval_node(int i, FunctionRef<Tri(const ConditionAtom&)> decide) const {
    const Node& n = nodes_[static_cast<size_t>(i)];
    switch (n.op) {
        case Node::Op::Atom: return decide(n.atom);
        case Node::Op::Not: return tri_not(eval_node(n.left, decide));
        case Node::Op::And: return tri_and(eval_node(n.left, decide), eval_node(n.right, decide));
        case Node::Op::Or: return tri_or(eval_node(n.left, decide), eval_node(n.right, decide));
    }
    return Tri::Unknown;
}

std::vector<const ConditionAtom*> Condition::atoms() const {
    std::vector<const ConditionAtom*> out;
    for (const auto& n : nodes_)
        if (n.op == Node::Op::Atom) out.push_back(&n.atom);
    return out;
}

std::optional<int> Condition::required_plane() const {
    std::vector<int> todo;
    if (root_ >= 0) todo.push_back(root_);
    while (!todo.empty()) {
        const Node& n = nodes_[static_cast<size_t>(todo.back())];
        todo.pop_back();
        if (n.op == Node::Op::And) {
            todo.push_back(n.left);
            todo.push_back(n.right);
        } else if (n.op == Node::Op::Atom && n.atom.kind == ConditionAtom::Kind::Plane) {
            return n.atom.number;
        }
    }
    return std::nullopt;
}

bool Condition::mentions(ConditionAtom::Kind kind, int number) const {
    for (const auto* a : atoms())
        if (a->kind == kind && a->number == number) return true;
    return false;
}

bool Condition::mentions_value(std::string_view arg, double value) const {
    const std::string name = upper(arg);
    for (const auto* a : atoms())
        if (a->kind == ConditionAtom::Kind::ArgEquals && a->arg == name && a->value == value) return true;
    return false;
}

}  // namespace osplint
