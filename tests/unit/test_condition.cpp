// The catalog's `when` conditions: parsing into typed atoms and three-valued
// evaluation.
#include <doctest/doctest.h>

#include <map>
#include <string>

#include "catalog/condition.h"
#include "semantics/conditions.h"

using namespace osplint;

namespace {

Condition parsed(const std::string& text) {
    std::string error;
    auto c = Condition::parse(text, error);
    REQUIRE_MESSAGE(c.has_value(), text << ": " << error);
    return *c;
}

std::string error_of(const std::string& text) {
    std::string error;
    auto c = Condition::parse(text, error);
    CHECK_FALSE(c.has_value());
    return error;
}

// Decides atoms from a table keyed by their spelling; others are Unknown.
struct World {
    int plane = 17;
    std::map<int, Tri> m;
    std::map<std::string, double> args;
    Tri operator()(const ConditionAtom& a) const {
        using K = ConditionAtom::Kind;
        switch (a.kind) {
            case K::Plane: return plane == a.number ? Tri::True : Tri::False;
            case K::Distance:
            case K::Spindle:
            case K::CutterComp: return Tri::Unknown;
            case K::MCode: {
                auto it = m.find(a.number);
                return it == m.end() ? Tri::Unknown : it->second;
            }
            case K::Given: return args.count(a.arg) ? Tri::True : Tri::False;
            case K::ArgEquals: {
                auto it = args.find(a.arg);
                return it == args.end() ? Tri::False : (it->second == a.value ? Tri::True : Tri::False);
            }
        }
        return Tri::Unknown;
    }
};

}  // namespace

TEST_CASE("conditions: atoms are typed when parsed") {
    Condition c = parsed("G17 and (PM=52 or m52)");
    auto atoms = c.atoms();
    REQUIRE(atoms.size() == 3);
    CHECK(atoms[0]->kind == ConditionAtom::Kind::Plane);
    CHECK(atoms[0]->number == 17);
    CHECK(atoms[1]->kind == ConditionAtom::Kind::ArgEquals);
    CHECK(atoms[1]->arg == "PM");
    CHECK(atoms[1]->value == 52);
    CHECK(atoms[2]->kind == ConditionAtom::Kind::MCode);
    CHECK(atoms[2]->number == 52);
    CHECK(c.text() == "G17 and (PM=52 or m52)");
    CHECK(c.required_plane() == 17);
    CHECK(c.mentions(ConditionAtom::Kind::MCode, 52));
    CHECK_FALSE(c.mentions(ConditionAtom::Kind::MCode, 53));
    CHECK(c.mentions_value("pm", 52));
    CHECK_FALSE(c.mentions_value("PM", 53));

    Condition g = parsed("given:pk");
    REQUIRE(g.atoms().size() == 1);
    CHECK(g.atoms()[0]->kind == ConditionAtom::Kind::Given);
    CHECK(g.atoms()[0]->arg == "PK");
    CHECK_FALSE(g.required_plane().has_value());
    // A plane under `or` or `not` is not required.
    CHECK_FALSE(parsed("G17 or M53").required_plane().has_value());
    CHECK_FALSE(parsed("not G17").required_plane().has_value());
    CHECK(parsed("M53 and (G90 and G18)").required_plane() == 18);
}

TEST_CASE("conditions: three-valued evaluation") {
    Condition c = parsed("G17 and (PM=52 or M52)");
    World w;
    w.m[52] = Tri::False;
    CHECK(c.eval(w) == Tri::False);
    w.args["PM"] = 52;
    CHECK(c.eval(w) == Tri::True);
    w.plane = 18;
    CHECK(c.eval(w) == Tri::False);  // false whatever M52 is
    w.plane = 17;
    w.args.clear();
    w.m.clear();  // M52 not known
    CHECK(c.eval(w) == Tri::Unknown);
    w.args["PM"] = 52;
    CHECK(c.eval(w) == Tri::True);  // true whatever M52 is

    CHECK(parsed("not M53").eval(w) == Tri::Unknown);
    w.m[53] = Tri::True;
    CHECK(parsed("not M53").eval(w) == Tri::False);
    CHECK(parsed("G90").eval(w) == Tri::Unknown);
    CHECK(parsed("G90 or G17").eval(w) == Tri::True);
    CHECK(parsed("G90 and G18").eval(w) == Tri::False);
    // No condition always holds.
    CHECK(Condition{}.empty());
    CHECK(Condition{}.eval(w) == Tri::True);
}

TEST_CASE("conditions: what is not a condition is said at once") {
    CHECK(error_of("G16").find("unknown condition \"G16\"") != std::string::npos);
    CHECK(error_of("").find("missing") != std::string::npos);
    CHECK(error_of("(M53").find("')' is missing") != std::string::npos);
    CHECK(error_of("M53)").find("unexpected \")\"") != std::string::npos);
    CHECK(error_of("M53 or").find("missing") != std::string::npos);
    CHECK(error_of("or M53").find("needs a condition before it") != std::string::npos);
    CHECK(error_of("given:").find("unknown condition") != std::string::npos);
    CHECK(error_of("PM=").find("unknown condition") != std::string::npos);
    CHECK(error_of("PM=inf").find("unknown condition") != std::string::npos);
    // Deep nesting is refused, not a stack overflow.
    CHECK(error_of(std::string(10000, '(') + "M53" + std::string(10000, ')')).find("nested too deeply") !=
          std::string::npos);
}

TEST_CASE("conditions: the spindle and cutter-compensation atoms read the modal state at the call") {
    Condition m4 = parsed("M4");
    REQUIRE(m4.atoms().size() == 1);
    CHECK(m4.atoms()[0]->kind == ConditionAtom::Kind::Spindle);
    CHECK(m4.atoms()[0]->number == 4);
    Condition g40 = parsed("g40 and not given:PD");
    CHECK(g40.atoms()[0]->kind == ConditionAtom::Kind::CutterComp);
    CHECK(g40.atoms()[0]->number == 40);

    ModalState s;
    auto decide = [&](const ConditionAtom& a) { return modal_atom(a, s); };
    // Not known (a subprogram, paths that disagree): Unknown, never a guess.
    CHECK(m4.eval(decide) == Tri::Unknown);
    CHECK(parsed("G40").eval(decide) == Tri::Unknown);
    s.spindle = Val<int>::of(4);
    s.cutter_comp = Val<int>::of(41);
    CHECK(m4.eval(decide) == Tri::True);
    CHECK(parsed("M3").eval(decide) == Tri::False);
    CHECK(parsed("G40").eval(decide) == Tri::False);
    CHECK(parsed("G41").eval(decide) == Tri::True);
    s.plane = Val<Plane>::of(Plane::G18);
    s.distance = Val<Distance>::of(Distance::Incremental);
    CHECK(parsed("G18 and G91").eval(decide) == Tri::True);
    CHECK(parsed("G17").eval(decide) == Tri::False);
    // Atoms about the call itself are left to the caller.
    CHECK(parsed("given:PK").eval(decide) == Tri::Unknown);
    CHECK(error_of("M6").find("M3, M4, M5, G40, G41, G42") != std::string::npos);
}
