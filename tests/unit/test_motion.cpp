// Cycle-axis envelopes (src/semantics/motion.h), the travel rule OSP301, the order
// rule OSP302, the unbounded notes OSP303 and the picture of `osplint trace --svg`.
//
// Every expected envelope below is worked out by hand from the action sequence
// of the manual (MACROS.md §2, §3); the comments cite the step.
#include <doctest/doctest.h>

#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <map>
#include <random>
#include <regex>
#include <set>
#include <sstream>

#include <unistd.h>

#include "analysis.h"
#include "expectations.h"
#include "programs.h"
#include "output/svg.h"
#include "semantics/motion.h"
#include "semantics/motion_internal.h"

namespace fs = std::filesystem;
using namespace osplint;

namespace {

struct Traced {
    osplint::testing::Analysis analysis;
    std::vector<Envelope> envelopes;  // of every reachable block that runs a macro or a hole, in order
};

Traced trace_text(const std::string& text, const Config& config = Config{}, const std::string& path = "T.MIN") {
    Traced t;
    t.analysis = osplint::testing::analyze_text(path, text, config);
    for (const auto& b : t.analysis.blocks)
        if (b.reachable)
            if (auto env = cycle_envelope(b.view(), config)) t.envelopes.push_back(std::move(*env));
    return t;
}

// The envelope of the block on `line`; fails the test when there is none.
const Envelope& at_line(const Traced& t, uint32_t line) {
    for (const auto& e : t.envelopes)
        if (e.line == line) return e;
    FAIL("no envelope on line " << line);
    static Envelope none;
    return none;
}

bool has_envelope(const Traced& t, uint32_t line) {
    for (const auto& e : t.envelopes)
        if (e.line == line) return true;
    return false;
}

const MotionPoint& low_point(const Envelope& e) {
    REQUIRE(e.lowest.has_value());
    return e.points[e.lowest->point];
}
const MotionPoint& high_point(const Envelope& e) {
    REQUIRE(e.highest.has_value());
    return e.points[e.highest->point];
}

const MotionPoint* point(const Envelope& e, const std::string& step) {
    for (const auto& p : e.points)
        if (p.step == step) return &p;
    return nullptr;
}

std::vector<Diagnostic> run_rule(const std::string& rule, const std::string& text, const Config& config,
                                 const std::string& path = "T.MIN") {
    AnalysisOptions options;
    options.only_rules = {rule};
    return check_text(path, text, config, options).diagnostics;
}

Config travel_z(double lo, double hi) {
    Config c;
    c.travel['Z'] = {lo, hi};
    return c;
}

// Every number and flag of two envelopes' points, in order (not their text).
void check_same_points(const std::vector<MotionPoint>& a, const std::vector<MotionPoint>& b) {
    REQUIRE(a.size() == b.size());
    for (size_t i = 0; i < a.size(); ++i) {
        const MotionPoint& p = a[i];
        const MotionPoint& q = b[i];
        CHECK(p.value == q.value);
        CHECK(p.reach.has_value() == q.reach.has_value());
        if (p.reach && q.reach) CHECK((p.reach->lo == q.reach->lo && p.reach->hi == q.reach->hi));
        CHECK((p.possible == q.possible && p.inferred == q.inferred && p.limit == q.limit && p.start == q.start));
    }
}

// `compare(name, text, config)` on every program of the corpus, with no
// configuration and with `travel`.
template <class Compare>
void on_corpus(const Config& travel, Compare&& compare) {
    for (const auto& f : osplint::testing::corpus_files()) {
        const std::string text = osplint::testing::read_all(f);
        compare(f.string(), text, Config{});
        compare(f.string(), text, travel);
    }
}

const std::string kHead = "O1000\nG15 H1\nG0 G90 X0 Y0\nG56 Z50. H3\n";  // lines 1-4; Z at 50

}  // namespace

// ---------------------------------------------------------------------------
// Macros (their action sequences through the catalog)

TEST_CASE("contains_ci finds what a search ignoring letter case finds") {
    using osplint::motion_detail::contains_ci;
    const auto naive = [](std::string_view hay, std::string_view needle) {
        std::string h(hay), n(needle);
        for (auto* t : {&h, &n})
            for (char& c : *t) c = static_cast<char>(std::toupper(static_cast<unsigned char>(c)));
        return h.find(n) != std::string::npos;
    };
    CHECK(contains_ci("return to the Z+ LIMIT", "+ limit"));
    CHECK(contains_ci("up to the + Limit", "+ limit"));
    CHECK_FALSE(contains_ci("up to the +limit", "+ limit"));
    CHECK(contains_ci("", ""));
    CHECK_FALSE(contains_ci("+ lim", "+ limit"));
    std::mt19937 rng(77);
    const std::string alphabet = "aAbB+ -";
    int found = 0;
    for (int i = 0; i < 20000; ++i) {
        std::string hay, needle;
        for (size_t k = rng() % 12; k > 0; --k) hay += alphabet[rng() % alphabet.size()];
        for (size_t k = rng() % 4; k > 0; --k) needle += alphabet[rng() % alphabet.size()];
        const bool expected = naive(hay, needle);
        found += expected;
        CHECK_MESSAGE(contains_ci(hay, needle) == expected, "'" << hay << "' '" << needle << "'");
    }
    CHECK(found > 2000);
}

TEST_CASE("motion_number writes what four-decimal formatting writes, trailing zeros dropped") {
    // The reference: the value rounded to 1/10000, printed with four decimals
    // by the standard library, then trimmed.
    const auto reference = [](double v) {
        if (!std::isfinite(v)) return std::string("?");
        double r = std::fabs(v) < 1e15 ? std::round(v * 10000.0) / 10000.0 : v;
        if (r == 0) r = 0;
        char buf[64];
        std::snprintf(buf, sizeof buf, "%.4f", r);
        std::string s = buf;
        while (!s.empty() && s.back() == '0') s.pop_back();
        if (!s.empty() && s.back() == '.') s.pop_back();
        return s;
    };
    CHECK(motion_number(-37) == "-37");
    CHECK(motion_number(0.005) == "0.005");
    CHECK(motion_number(-0.00004) == "0");
    CHECK(motion_number(-0.00005) == "-0.0001");
    CHECK(motion_number(12.34567) == "12.3457");
    CHECK(motion_number(1e12) == "1000000000000");
    CHECK(motion_number(NAN) == "?");
    // Values of every magnitude a program writes, and the edges of the
    // rounding: the same text as the reference, value by value.
    uint64_t x = 0x9E3779B97F4A7C15ull;
    const auto next = [&] {
        x ^= x << 13;
        x ^= x >> 7;
        x ^= x << 17;
        return x;
    };
    int differ = 0;
    for (int i = 0; i < 200000; ++i) {
        const double unit = static_cast<double>(next() % 2000001) / 1000000.0 - 1.0;  // [-1, 1]
        const double scale = std::pow(10.0, static_cast<double>(next() % 15) - 5);   // 1e-5 .. 1e9
        double v = unit * scale;
        if (i % 3 == 0) v = std::round(v * 20000.0) / 20000.0;  // on a half of the last digit
        if (i % 5 == 0) v = static_cast<double>(static_cast<long long>(v * 1000)) / 1000;  // what posts write
        if (motion_number(v) != reference(v) && ++differ < 5) CHECK(motion_number(v) == reference(v));
    }
    CHECK(differ == 0);
}

TEST_CASE("OZAGR: down to PZ-PI-PL (step 3c), up to PR (step 2)") {
    auto t = trace_text(kHead + "CALL OZAGR PX=10. PY=0 PR=5. PZ=-20. PI=12.\nM30\n");
    const Envelope& e = at_line(t, 5);
    CHECK(e.axis == 'Z');
    // OZAGR step 3c: PZ-PI-PL = -20-12-5 = -37 (PL omitted: the table's default 5, 000:L582)
    CHECK(e.lowest->value == doctest::Approx(-37));
    CHECK(low_point(e).step == "3c");
    CHECK(low_point(e).describe().find("step 3c: PZ-PI-PL = -20-12-5 = -37") == 0);
    CHECK(low_point(e).describe().find("PL not given: default 5") != std::string::npos);
    // OZAGR step 2: positioning to the R point, PR = 5
    CHECK(e.highest->value == doctest::Approx(5));
    CHECK(high_point(e).step == "2");
    // step 3a: PR-PJ = 5-0 = 5 (PJ default 0); step 5: PZ = -20; step 10: PR
    REQUIRE(point(e, "3a"));
    CHECK(point(e, "3a")->value.value == doctest::Approx(5));
    CHECK(point(e, "3a")->inferred);
    CHECK(point(e, "5")->value.value == doctest::Approx(-20));
    CHECK(point(e, "7")->value.value == doctest::Approx(-21));  // step 7: PZ-1 (1 mm escape, inferred)
    CHECK(point(e, "9")->value.value == doctest::Approx(-18));  // step 9: PZ+2 (3 mm retreat, inferred)
    // step 3b advances by PD, which the manual never defines: not given, not guessed
    CHECK(point(e, "3b") == nullptr);
    REQUIRE(!e.notes.empty());
    CHECK(e.notes.front().find("step 3b") != std::string::npos);
    CHECK(e.bounded());
    CHECK(e.plane_points.size() == 2);
}

TEST_CASE("OZAGR: PL, PJ and PD given") {
    auto t = trace_text(kHead +
                        "CALL OZAGR PR=5. PZ=-20. PI=12. PL=8. PJ=2.\n"
                        "CALL OZAGR PR=5. PZ=-20. PI=12. PJ=2. PD=50.\nM30\n");
    // step 3c: PZ-PI-PL = -20-12-8 = -40
    CHECK(at_line(t, 5).lowest->value == doctest::Approx(-40));
    CHECK(point(at_line(t, 5), "3a")->value.value == doctest::Approx(3));  // step 3a: PR-PJ = 5-2
    // step 3b: PR-PJ-PD = 5-2-50 = -47 lies below 3c (-20-12-5 = -37)
    const Envelope& e = at_line(t, 6);
    CHECK(e.lowest->value == doctest::Approx(-47));
    CHECK(low_point(e).step == "3b");
}

TEST_CASE("OZAGR: M53 goes to PT (step 11), PM=52 to the Z+ limit (step 12, G17 only)") {
    Config config = travel_z(-300, 150);
    auto t = trace_text(kHead +
                        "CALL OZAGR PR=5. PZ=-20. PI=12. PT=30. M53\n"
                        "M54\n"
                        "CALL OZAGR PR=5. PZ=-20. PI=12. PM=52\n"
                        "G18\n"
                        "CALL OZAGR PR=5. PZ=-20. PI=12. PM=52\n"
                        "G17\nM30\n",
                        config);
    // step 11: M53 in effect, to the T point: PT = 30
    CHECK(at_line(t, 5).highest->value == doctest::Approx(30));
    CHECK(high_point(at_line(t, 5)).step == "11");
    // step 12: G17 and PM=52: the Z+ limit = [machine.travel] z max 150
    const Envelope& pm = at_line(t, 7);
    CHECK(pm.highest->value == doctest::Approx(150));
    CHECK(high_point(pm).limit);
    CHECK(pm.limit_point.has_value());
    // In G18 the step does not run: the top is PR = 5 (on Y, the G18 cycle axis)
    const Envelope& g18 = at_line(t, 9);
    CHECK(g18.axis == 'Y');
    CHECK(g18.highest->value == doctest::Approx(5));
    CHECK(!g18.limit_point.has_value());
    // Without [machine.travel] the trip to the limit still bounds the top
    auto u = trace_text(kHead + "CALL OZAGR PR=5. PZ=-20. PI=12. PM=52\nM30\n");
    const Envelope& nolimit = at_line(u, 5);
    CHECK(nolimit.bounded());
    CHECK(nolimit.limit_point.has_value());
    CHECK(!nolimit.points[*nolimit.limit_point].value.known);
}

TEST_CASE("OM100: PL below the Z point (step 4), PK adds steps 3a/3b") {
    auto t = trace_text(kHead +
                        "CALL OM100 PR=10. PZ=-32. PI=4. PK=32.\n"
                        "CALL OM100 PR=10. PZ=-32. PI=4.\nM30\n");
    const Envelope& e = at_line(t, 5);
    // step 4: PZ-PL = -32-5 = -37 (PL default 5, 000:L688)
    CHECK(e.lowest->value == doctest::Approx(-37));
    CHECK(low_point(e).describe().find("step 4: PZ-PL = -32-5 = -37") == 0);
    // step 2: PR = 10
    CHECK(e.highest->value == doctest::Approx(10));
    // step 3a: PZ+PK+PL = -32+32+5 = 5; step 3b: PZ+PK = 0
    CHECK(point(e, "3a")->value.value == doctest::Approx(5));
    CHECK(point(e, "3b")->value.value == doctest::Approx(0));
    // without PK, step 3 goes straight to 4
    const Envelope& n = at_line(t, 6);
    CHECK(point(n, "3a") == nullptr);
    CHECK(n.lowest->value == doctest::Approx(-37));
}

TEST_CASE("OG87C: spans PA, PR and PZ; the counterbore circle in the plane") {
    auto t = trace_text(kHead +
                        "MODIN OG87C PR=-45. PZ=-36. PA=5. PC=22. PI=2.5 PD=21\n"
                        "X-60. Y-40.\n"
                        "MODOUT\nM30\n");
    CHECK(!has_envelope(t, 5));  // the MODIN line itself runs nothing
    const Envelope& e = at_line(t, 6);
    CHECK(e.call_kind == CallKind::ModinPositioning);
    CHECK(e.origin_line == 5);
    // step 4 (and 11): R point, PR = -45
    CHECK(e.lowest->value == doctest::Approx(-45));
    CHECK(low_point(e).step == "4");
    // step 2 (and 14): point A, PA = 5
    CHECK(e.highest->value == doctest::Approx(5));
    CHECK(high_point(e).step == "2");
    CHECK(point(e, "8")->value.value == doctest::Approx(-36));  // step 8: infeed to PZ
    // the circle PC=22 about (-60, -40): X -71..-49, Y -51..-29 (the PI shift 2.5 stays inside)
    bool x = false, y = false;
    for (const auto& s : e.plane_spans) {
        if (s.axis == 'X') {
            x = true;
            CHECK(s.range.lo == doctest::Approx(-71));
            CHECK(s.range.hi == doctest::Approx(-49));
        }
        if (s.axis == 'Y') {
            y = true;
            CHECK(s.range.lo == doctest::Approx(-51));
            CHECK(s.range.hi == doctest::Approx(-29));
        }
    }
    CHECK(x);
    CHECK(y);
}

TEST_CASE("OG87C without PA: point A is the current position, or unknown") {
    Config config;
    const auto a = osplint::testing::analyze_text("T.MIN", "X-60. Y-40.\n", config);
    REQUIRE(!a.blocks.empty());
    const Block& b = a.blocks.front().block;
    MacroCall call;
    call.kind = CallKind::ModinPositioning;
    call.name = "OG87C";
    call.spec = config.catalog.find("OG87C");
    REQUIRE(call.spec);
    call.modin_line = 1;
    for (auto [n, v] : std::vector<std::pair<std::string, double>>{{"PR", -45}, {"PZ", -36}, {"PC", 22}, {"PI", 2.5}, {"PD", 21}})
        call.args.push_back(MacroArg{n, nullptr, Val<double>::of(v)});
    ModalState before;
    before.plane = Val<Plane>::of(Plane::G17);
    before.distance = Val<Distance>::of(Distance::Absolute);
    before.return_level = Val<int>::of(0);
    before.z = Val<double>::of(50);
    ModalState after = before;
    auto e = cycle_envelope(b, before, after, &call, config);
    REQUIRE(e);
    // step 2: PA omitted = current value (000:L157): Z 50
    CHECK(e->highest->value == doctest::Approx(50));
    CHECK(high_point(*e).describe().find("current position 50") != std::string::npos);
    before.z = Val<double>{};
    auto u = cycle_envelope(b, before, after, &call, config);
    REQUIRE(u);
    CHECK(!u->bounded());  // never guessed
    CHECK(!u->unknown_points().empty());
    CHECK(u->unknown_points().front()->step == "2");
}

TEST_CASE("OG87N: printed targets bound the envelope, strokes of unprinted direction only may reach") {
    auto t = trace_text(kHead +
                        "MODIN OG87N PR=5. PZ=0 PL=3. PI=2. PJ=6.5\n"
                        "X0 Y-55.\n"
                        "MODOUT\nM30\n");
    const Envelope& e = at_line(t, 6);
    // step 4: PZ = 0 is the lowest printed target; step 7: PZ+PJ = 0+6.5 = 6.5 the highest
    CHECK(e.lowest->value == doctest::Approx(0));
    CHECK(low_point(e).step == "4");
    CHECK(e.highest->value == doctest::Approx(6.5));
    CHECK(high_point(e).step == "7");
    CHECK(point(e, "3")->value.value == doctest::Approx(1));    // step 3: PZ+1
    CHECK(point(e, "10")->value.value == doctest::Approx(4));   // step 10: PZ+PL+1 = 0+3+1
    // steps 5/6 from PZ: by PL (3) then by PI (2), either way: -5 .. 5
    REQUIRE(e.may_low.has_value());
    CHECK(e.may_low->value == doctest::Approx(-5));
    CHECK(e.points[e.may_low->point].step == "6");
    // steps 11/12 from PZ+PL+1 = 4: by PI+1 (3) then by PL (3): -2 .. 10
    REQUIRE(e.may_high.has_value());
    CHECK(e.may_high->value == doctest::Approx(10));
    CHECK(e.points[e.may_high->point].step == "12");
    CHECK(e.bounded());
}

TEST_CASE("OG87K and OG87M: the PL stroke below PZ, M53 to PT") {
    auto t = trace_text(kHead +
                        "MODIN OG87K PR=5. PZ=0 PL=4.5\nX0 Y0\nMODOUT\n"
                        "MODIN OG87M PR=5. PZ=0 PL=3. PT=30. M53\nX0 Y0\nMODOUT\nM30\n");
    // OG87K step 5: PZ-PL = 0-4.5 = -4.5 (inferred); step 2: PR = 5
    const Envelope& k = at_line(t, 6);
    CHECK(k.lowest->value == doctest::Approx(-4.5));
    CHECK(low_point(k).step == "5");
    CHECK(low_point(k).inferred);
    CHECK(k.highest->value == doctest::Approx(5));
    // OG87M step 6: PZ-PL = 0-3 = -3; step 11: M53 mode, to PT = 30
    const Envelope& m = at_line(t, 9);
    CHECK(m.lowest->value == doctest::Approx(-3));
    CHECK(low_point(m).step == "6");
    CHECK(m.highest->value == doctest::Approx(30));
    CHECK(high_point(m).step == "11");
}

TEST_CASE("OLPEX / OLPEY: PR -> PZ, the travel PI in the plane") {
    auto t = trace_text(kHead +
                        "CALL OLPEX PX=20. PY=0 PR=2. PZ=-100. PI=60. PQ=3. PK=.5\n"
                        "CALL OLPEY PX=100. PY=20. PR=2. PZ=-100. PI=-60. PQ=3. PK=.5\nM30\n");
    const Envelope& e = at_line(t, 5);
    // step 1: PR = 2 (start of the cycle-axis motion); step 2: PZ = -100 (end), both inferred (no action sequence is printed)
    CHECK(e.highest->value == doctest::Approx(2));
    CHECK(high_point(e).step == "1");
    CHECK(e.lowest->value == doctest::Approx(-100));
    CHECK(low_point(e).step == "2");
    REQUIRE(e.plane_spans.size() == 1);
    CHECK(e.plane_spans[0].axis == 'X');  // OLPEX travels along X in G17
    CHECK(e.plane_spans[0].range.lo == doctest::Approx(20));
    CHECK(e.plane_spans[0].range.hi == doctest::Approx(80));
    const Envelope& y = at_line(t, 6);
    REQUIRE(y.plane_spans.size() == 1);
    CHECK(y.plane_spans[0].axis == 'Y');  // OLPEY along Y: 20 + (-60) = -40 .. 20
    CHECK(y.plane_spans[0].range.lo == doctest::Approx(-40));
    CHECK(y.plane_spans[0].range.hi == doctest::Approx(20));
}

TEST_CASE("OKYOX and OKYLX: PR -> PZ -> PR; the slot in the plane") {
    auto t = trace_text(kHead +
                        "CALL OKYOX PX=-60. PY=40. PR=2. PZ=-5. PI=40. PJ=10. PD=15\n"
                        "CALL OKYLX PX=-135. PY=0 PR=2. PZ=-6. PI=40. PJ=14. PD=16\nM30\n");
    const Envelope& o = at_line(t, 5);
    // OKYOX step 3: cutting feed to PZ = -5; step 2 (and 9): PR = 2
    CHECK(o.lowest->value == doctest::Approx(-5));
    CHECK(low_point(o).step == "3");
    CHECK(o.highest->value == doctest::Approx(2));
    CHECK(high_point(o).step == "2");
    std::map<char, Interval> spans;
    for (const auto& s : o.plane_spans) spans[s.axis] = s.range;
    REQUIRE(spans.count('X'));
    REQUIRE(spans.count('Y'));
    CHECK(spans['X'].lo == doctest::Approx(-60));  // PX .. PX+PI
    CHECK(spans['X'].hi == doctest::Approx(-20));
    CHECK(spans['Y'].lo == doctest::Approx(35));   // PY -+ PJ/2
    CHECK(spans['Y'].hi == doctest::Approx(45));
    const Envelope& l = at_line(t, 6);
    // OKYLX step 4: to the Z point, PZ = -6; step 3: PR = 2
    CHECK(l.lowest->value == doctest::Approx(-6));
    CHECK(low_point(l).step == "4");
    CHECK(high_point(l).step == "3");
}

TEST_CASE("G114 (OG84L): I -> R -> Z+L, G91 from I and R") {
    auto t = trace_text(kHead +
                        "G98\n"
                        "G114 R10. Z-21.5 P.7 F1200 FA=1320\n"  // 6: declaration, positions only
                        "X-45. Y-45.\n"                          // 7: a hole
                        "M204\n"
                        "G114 R10. Z-21.5 L4. F1200 FA=1320\n"   // 9
                        "X45. Y-45.\n"                           // 10
                        "M204\n"
                        "G91\n"
                        "G114 R-40. Z-31.5 F1200 FA=1320\n"      // 13
                        "X0 Y0\n"                                // 14
                        "M204\nG90\nM30\n");
    CHECK(!has_envelope(t, 6));  // 003:L86-88: the declaration block does not tap
    const Envelope& e = at_line(t, 7);
    CHECK(e.source == MotionSource::CycleMacro);
    // I point: Z 50 where the hole starts; step 2: R = 10; step 3: Z+L = -21.5+0 (L not given)
    CHECK(e.highest->value == doctest::Approx(50));
    CHECK(high_point(e).step == "I");
    CHECK(point(e, "2")->value.value == doctest::Approx(10));
    CHECK(e.lowest->value == doctest::Approx(-21.5));
    CHECK(low_point(e).step == "3");
    // with L4 the spindle stops at Z+L = -21.5+4 = -17.5 (003 note 5)
    const Envelope& l = at_line(t, 10);
    CHECK(l.lowest->value == doctest::Approx(-17.5));
    CHECK(low_point(l).describe().find("-21.5+4 = -17.5") != std::string::npos);
    // G91: R from the I point 50-40 = 10, Z from R 10-31.5 = -21.5 (fixed cycles manual, "Cautions: programming in G91")
    const Envelope& g = at_line(t, 14);
    CHECK(g.incremental);
    CHECK(point(g, "2")->value.value == doctest::Approx(10));
    CHECK(g.lowest->value == doctest::Approx(-21.5));
}

TEST_CASE("every fixed cycle of the catalog runs I -> R -> Z") {
    Config config;
    for (const auto& cycle : config.catalog.cycles()) {
        CAPTURE(cycle.name);
        std::string g = "G" + std::to_string(cycle.gcode);
        // G98: every hole starts and ends at the I point, Z 50 (004:L6)
        auto t = trace_text(kHead + "G98\n" + g + " X10. Y10. Z-20. R3. Q5. K2. F100\nX20. Y10.\nG80\nM30\n");
        for (uint32_t line : {6u, 7u}) {
            const Envelope& e = at_line(t, line);
            CHECK(e.source == MotionSource::FixedCycle);
            CHECK(e.name == g);
            CHECK(e.highest->value == doctest::Approx(50));  // I point (004:L6)
            CHECK(high_point(e).step == "I");
            CHECK(point(e, "R")->value.value == doctest::Approx(3));  // R point (004:L7)
            CHECK(e.lowest->value == doctest::Approx(-20));           // Z point (004:L9)
            CHECK(low_point(e).step == "Z");
        }
        // G99: the second hole starts at R (the previous block's Z is the I point)
        auto r = trace_text(kHead + "G99\n" + g + " X10. Y10. Z-20. R3. Q5. K2. F100\nX20. Y10.\nG80\nM30\n");
        CHECK(at_line(r, 6).highest->value == doctest::Approx(50));
        CHECK(at_line(r, 7).highest->value == doctest::Approx(3));
    }
}

TEST_CASE("fixed cycles: G91, NCYL, BHC, M53 to the G71 level, G18") {
    auto t = trace_text(kHead +
                        "G98\n"
                        "NCYL G81 Z-3.5 R3. F150\n"          // 6: positions only
                        "BHC X0 Y0 I50. J0 K6\n"             // 7: six holes, one motion
                        "G80\n"
                        "G91\n"
                        "G81 X10. Y0 Z-23. R-47. F100\n"     // 10: R = 50-47 = 3, Z = 3-23 = -20
                        "G80\n"
                        "G90\n"
                        "G71 Z80.\n"
                        "G81 X10. Y10. Z-20. R3. F100 M53\n" // 14: returns to the G71 level 80
                        "G80\nM54\nM30\n");
    CHECK(!has_envelope(t, 6));
    const Envelope& bhc = at_line(t, 7);
    CHECK(bhc.lowest->value == doctest::Approx(-3.5));
    CHECK(bhc.plane_points.empty());
    const Envelope& inc = at_line(t, 10);
    CHECK(point(inc, "R")->value.value == doctest::Approx(3));
    CHECK(inc.lowest->value == doctest::Approx(-20));
    CHECK(low_point(inc).describe().find("3-23 = -20") != std::string::npos);
    const Envelope& m53 = at_line(t, 14);
    CHECK(m53.highest->value == doctest::Approx(80));
    CHECK(high_point(m53).mark == "G71");
    CHECK(m53.end.is(80));

    auto h = trace_text("O1000\nG18\nG0 G90 X0 Z0\nG0 Y50.\nG98\nG81 X10. Z10. Y-20. R3. F100\nG80\nM30\n");
    const Envelope& y = at_line(h, 6);
    CHECK(y.axis == 'Y');  // G18: the cycle axis is Y
    CHECK(y.highest->value == doctest::Approx(50));
    CHECK(y.lowest->value == doctest::Approx(-20));
}

TEST_CASE("G77 K, G83 J and G88 Q/K/I/J add their points to I -> R -> Z") {
    auto t = trace_text(kHead +
                        "G98\n"
                        "G77 X10. Y10. Z-20. R3. Q5. K-8. F100\n"         // 6: K point -8
                        "G80\n"
                        "G91\n"
                        "G77 X0 Y0 Z-23. R-47. Q5. K-5. F100\n"           // 9: R 3, K 3-5 = -2, Z -20
                        "G80\n"
                        "G90\n"
                        "G77 X10. Y10. Z-20. R3. Q5. K-25. F100\n"        // 12: K below Z
                        "G80\n"
                        "G83 X10. Y10. Z-40. R3. Q5. J10. F100\n"         // 14: J depth 3-10 = -7
                        "X20.\n"                                          // 15: J from line 14
                        "G80\n"
                        "G83 X10. Y10. Z-10. R3. Q5. J20. F100\n"         // 17: J deeper than the hole
                        "G80\n"
                        "G88 X-60. Y10. Z-30. R3. I1.5 J-0.5 Q0.3 F100\n" // 19: relief -30+0.3
                        "G80\n"
                        "G88 X-60. Y10. Z-30. R3. K0.2 F100\n"            // 21: K as the Z shift, no I/J
                        "G80\nM30\n");
    // G77: K is a point between R and Z (fixed cycles manual, "G77 Step & pick cycle")
    const Envelope& k = at_line(t, 6);
    REQUIRE(point(k, "K"));
    CHECK(point(k, "K")->value.value == doctest::Approx(-8));
    CHECK(!point(k, "K")->possible);
    CHECK(k.lowest->value == doctest::Approx(-20));
    CHECK(k.points[2].step == "K");  // I, R, K, Z
    CHECK(k.points[3].step == "Z");
    // under G91 K is the distance from the R point
    const Envelope& ki = at_line(t, 9);
    CHECK(point(ki, "K")->value.value == doctest::Approx(-2));
    CHECK(point(ki, "K")->describe().find("3-5 = -2") != std::string::npos);
    // a K below Z: only a possible point, and a note; the envelope stays [-20, 50]
    const Envelope& kb = at_line(t, 12);
    CHECK(point(kb, "K")->possible);
    CHECK(kb.lowest->value == doctest::Approx(-20));
    REQUIRE(kb.may_low.has_value());
    CHECK(kb.may_low->value == doctest::Approx(-25));
    CHECK(kb.notes.size() == 1);
    // G83 with J: the J depth R-J, the return to R, the approach to d2 short of it (a setting parameter: possible)
    const Envelope& j = at_line(t, 14);
    REQUIRE(point(j, "J"));
    CHECK(point(j, "J")->value.value == doctest::Approx(-7));
    CHECK(point(j, "J")->expr == "R-J");
    CHECK(point(j, "J return")->value.value == doctest::Approx(3));
    const MotionPoint* d2 = point(j, "d2");
    REQUIRE(d2);
    CHECK(d2->possible);
    REQUIRE(d2->reach.has_value());
    CHECK(d2->reach->lo == doctest::Approx(-6));
    CHECK(j.lowest->value == doctest::Approx(-40));
    CHECK(j.highest->value == doctest::Approx(50));
    CHECK(!j.may_low.has_value());
    CHECK(!j.may_high.has_value());
    // the next hole of the cycle reads J from the cycle's modal words
    CHECK(point(at_line(t, 15), "J")->value.value == doctest::Approx(-7));
    // J not less than the depth: no J points, a note
    const Envelope& jd = at_line(t, 17);
    CHECK(!point(jd, "J"));
    CHECK(!jd.notes.empty());
    // G88: Z relieved by Q away from the bottom; I/J shift X and Y (G17), read as signed
    const Envelope& f = at_line(t, 19);
    const MotionPoint* s = point(f, "shift");
    REQUIRE(s);
    CHECK(s->value.value == doctest::Approx(-29.7));
    CHECK(s->expr == "Z+Q");
    CHECK(f.lowest->value == doctest::Approx(-30));
    std::map<char, PlaneSpan> spans;
    for (const auto& sp : f.plane_spans) spans[sp.axis] = sp;
    REQUIRE(spans.count('X'));
    REQUIRE(spans.count('Y'));
    CHECK(spans['X'].range.lo == doctest::Approx(-60));
    CHECK(spans['X'].range.hi == doctest::Approx(-58.5));
    CHECK(spans['X'].inferred);
    CHECK(spans['Y'].range.lo == doctest::Approx(9.5));
    CHECK(spans['Y'].range.hi == doctest::Approx(10));
    // K is accepted as the Z shift; without I/J the setting parameters shift, not known here
    const Envelope& fk = at_line(t, 21);
    CHECK(point(fk, "shift")->value.value == doctest::Approx(-29.8));
    CHECK(point(fk, "shift")->expr == "Z+K");
    CHECK(fk.plane_spans.empty());
    CHECK(fk.notes.size() == 2);
}

TEST_CASE("after a macro call the cycle axis is where the last definite step of its sequence leaves it") {
    Config config = travel_z(-300, 150);
    auto t = trace_text(kHead +
                        "CALL OZAGR PX=0 PY=120. PR=5. PZ=-20. PI=5.\n"         // 5: step 10, PR = 5
                        "G98\n"
                        "G81 X10. Y10. Z-20. R3. F100\n"                         // 7: its I point is that 5
                        "G80\n"
                        "CALL OM100 PX=10. PY=0 PR=5. PZ=-20. PI=4. PM=52\n"     // 9: to the + limit
                        "G91\n"
                        "CALL OKYLX PX=0 PY=0 PR=2. PZ=-6. PI=40. PJ=14. PD=16\n" // 11: not usable under G91
                        "G90\n"
                        "CALL OZAGR PX=0 PY=120. PR=VC1 PZ=-20. PI=5.\n"        // 13: PR not known
                        "M30\n",
                        config);
    const auto& call = t.analysis.at(5);
    CHECK(call.after.z.is(5));
    CHECK(!call.after.x.known);  // the plane position stays unknown
    CHECK(at_line(t, 7).start.is(5));
    CHECK(high_point(at_line(t, 7)).step == "I");
    // the + travel limit is not known to the transfer function, even with [machine.travel]
    CHECK(!t.analysis.at(9).after.z.known);
    CHECK(!t.analysis.at(11).after.z.known);
    CHECK(!t.analysis.at(13).after.z.known);
}

TEST_CASE("the end point the transfer step takes is the end of the envelope the rules and the trace see") {
    // The transfer step evaluates the action sequence without the text
    // (macro_end); on every macro call of the corpus it must agree with the
    // full envelope.
    int compared = 0, unknown = 0;
    auto compare = [&](const std::string& name, const std::string& text) {
        const Config config;
        const auto analysis = osplint::testing::analyze_text(name, text, config);
        for (const auto& b : analysis.blocks) {
            if (!b.reachable) continue;
            const BlockView v = b.view();
            const auto env = cycle_envelope(v, config);
            if (!env || env->source != MotionSource::Macro || !env->plane) continue;
            // Where macro_end declines on purpose: G91 or inch, where the envelope is a reading.
            if (!v.before.distance.is(Distance::Absolute) || !v.before.units.is(Units::Mm)) continue;
            CAPTURE(name);
            CAPTURE(v.block.line);
            const auto end = macro_end(v.block, v.before, v.after, v.call);
            CHECK(end.has_value() == env->end.known);
            if (end) {
                CHECK(env->axis == end->first);
                CHECK(env->end.is(end->second));
            } else {
                ++unknown;
            }
            ++compared;
        }
    };
    for (const auto& f : osplint::testing::corpus_files()) compare(f.string(), osplint::testing::read_all(f));
    // The last step conditional on a return level that is known, not known,
    // or known not to hold; a last step that is skipped; a stroke.
    compare("conditions.MIN", kHead +
                                  "CALL OZAGR PX=0 PY=120. PR=5. PZ=-20. PI=5. PT=50. M54\n"
                                  "IF [VC1 EQ 1] NM1\n"
                                  "M53\n"
                                  "NM1 CALL OZAGR PX=0 PY=120. PR=5. PZ=-20. PI=5. PT=50.\n"
                                  "M53\n"
                                  "CALL OZAGR PX=0 PY=120. PR=5. PZ=-20. PI=5. PT=50.\n"
                                  "CALL OM100 PX=10. PY=0 PR=5. PZ=-20. PI=4. PK=10.\n"
                                  "CALL OG87N PR=5. PZ=-20. PL=4. PI=2. PJ=6.\n"
                                  "M30\n");
    CHECK(compared > 20);
    CHECK(unknown > 0);
}

TEST_CASE("an envelope worked out as values only has every number and flag of the full one") {
    // The travel rules decide on the values and ask for the text only for a
    // finding: on every block of the corpus, with and without travel limits,
    // the two must agree on all but the text.
    int compared = 0, with_text = 0;
    const auto same_end = [](const std::optional<EnvelopeEnd>& a, const std::optional<EnvelopeEnd>& b) {
        return a.has_value() == b.has_value() && (!a || (a->value == b->value && a->point == b->point));
    };
    auto compare = [&](const std::string& name, const std::string& text, const Config& config) {
        const auto analysis = osplint::testing::analyze_text(name, text, config);
        for (const auto& b : analysis.blocks) {
            const BlockView v = b.view();
            const auto full = cycle_envelope(v, config);
            const auto values = cycle_envelope(v, config, EnvelopeDetail::Values);
            CAPTURE(name);
            CAPTURE(v.block.line);
            REQUIRE(full.has_value() == values.has_value());
            if (!full) continue;
            ++compared;
            if (!full->notes.empty() || !full->points.empty()) ++with_text;
            CHECK(full->source == values->source);
            CHECK(full->name == values->name);
            CHECK(full->axis == values->axis);
            CHECK(full->plane == values->plane);
            CHECK(full->bounded_low == values->bounded_low);
            CHECK(full->bounded_high == values->bounded_high);
            CHECK(same_end(full->lowest, values->lowest));
            CHECK(same_end(full->highest, values->highest));
            CHECK(same_end(full->may_low, values->may_low));
            CHECK(same_end(full->may_high, values->may_high));
            CHECK(full->limit_point == values->limit_point);
            CHECK(full->start == values->start);
            CHECK(full->end == values->end);
            check_same_points(full->points, values->points);
            REQUIRE(full->plane_points.size() == values->plane_points.size());
            for (size_t i = 0; i < full->plane_points.size(); ++i) {
                CHECK(full->plane_points[i].axis == values->plane_points[i].axis);
                CHECK(full->plane_points[i].value == values->plane_points[i].value);
                CHECK(full->plane_points[i].what == values->plane_points[i].what);
            }
            REQUIRE(full->plane_spans.size() == values->plane_spans.size());
            for (size_t i = 0; i < full->plane_spans.size(); ++i) {
                const PlaneSpan& f = full->plane_spans[i];
                const PlaneSpan& w = values->plane_spans[i];
                CHECK((f.axis == w.axis && f.range.lo == w.range.lo && f.range.hi == w.range.hi));
                CHECK((f.inferred == w.inferred && f.compensated == w.compensated && f.either_way == w.either_way));
                CHECK(f.arg == w.arg);
            }
            CHECK(travel_violations(*full, config).size() == travel_violations(*values, config).size());
        }
    };
    Config travel;
    travel.travel['X'] = TravelLimit{-20, 20};
    travel.travel['Y'] = TravelLimit{-30, 30};
    travel.travel['Z'] = TravelLimit{-25, 60};
    on_corpus(travel, compare);
    CHECK(compared > 100);
    CHECK(with_text > 50);
}

namespace {

// Walks the blocks of `name` that run a macro (`macros`) or drill a hole,
// asking `same(view)` before `remember(view)` on each, as OSP301 asks its
// memo; counts the hits and misses. On a hit the envelope worked out in
// values must have the points of the last one remembered, and the one
// worked out for the plane (EnvelopeDetail::Plane) no points but the same
// plane part: its points, its spans and what of them is past the travel
// (the memo may hold a block past the travel on the cycle axis: OSP301
// remembers quiet ones only).
template <class Same, class Remember>
void walk_memo(const std::string& name, const std::string& text, const Config& config, bool macros, Same&& same,
               Remember&& remember, int& hits, int& misses) {
    const auto analysis = osplint::testing::analyze_text(name, text, config);
    std::optional<Envelope> last;
    for (const auto& b : analysis.blocks) {
        const BlockView v = b.view();
        const auto values = cycle_envelope(v, config, EnvelopeDetail::Values);
        if (!values || (values->source == MotionSource::Macro) != macros) continue;
        CAPTURE(name);
        CAPTURE(v.block.line);
        if (same(v)) {
            ++hits;
            REQUIRE(last);
            check_same_points(values->points, last->points);
            const auto plane = cycle_envelope(v, config, EnvelopeDetail::Plane);
            REQUIRE(plane);
            CHECK(plane->points.empty());
            CHECK(plane->axis == values->axis);
            REQUIRE(plane->plane_points.size() == values->plane_points.size());
            for (size_t i = 0; i < plane->plane_points.size(); ++i)
                CHECK((plane->plane_points[i].axis == values->plane_points[i].axis &&
                       plane->plane_points[i].value == values->plane_points[i].value &&
                       plane->plane_points[i].what == values->plane_points[i].what));
            REQUIRE(plane->plane_spans.size() == values->plane_spans.size());
            for (size_t i = 0; i < plane->plane_spans.size(); ++i)
                CHECK((plane->plane_spans[i].range.lo == values->plane_spans[i].range.lo &&
                       plane->plane_spans[i].range.hi == values->plane_spans[i].range.hi));
            const auto past = travel_violations(*values, config);
            CHECK(travel_violations(*plane, config).size() ==
                  static_cast<size_t>(std::count_if(past.begin(), past.end(),
                                                    [](const TravelViolation& t) { return t.point < 0; })));
        } else {
            ++misses;
        }
        remember(v);
        last = values;
    }
}

}  // namespace

TEST_CASE("a macro call MacroAxisMemo calls the same as the last one has the same action-step points") {
    // OSP301 passes over the cycle-axis points of a call the memo calls the
    // same as the last quiet one, and looks only at the positioning plane
    // (EnvelopeDetail::Plane). On every pair of macro calls in a row, in the
    // corpus and in a program that changes one input at a time, the memo's
    // "same" must mean the same points, and the plane part must be the one
    // of the envelope worked out in values.
    int hits = 0, misses = 0;
    auto compare = [&](const std::string& name, const std::string& text, const Config& config) {
        MacroAxisMemo memo;
        walk_memo(
            name, text, config, true, [&](const BlockView& v) { return memo.same(v, config.travel); },
            [&](const BlockView& v) { memo.remember(v, config.travel); }, hits, misses);
    };
    Config travel;
    travel.travel['X'] = TravelLimit{-20, 20};
    travel.travel['Z'] = TravelLimit{-25, 60};
    on_corpus(travel, compare);
    // Each call after the second repeats the one before but for one input:
    // the position in the plane only (a hit), an argument the steps read,
    // whether one is given, the return level, the macro, the kind of call,
    // the current Z (read for OG87C's omitted PA), the distance mode, the
    // plane. The second differs from the first in Z, where the first left
    // the tool (a miss: the memo takes in the current position whether the
    // macro reads it or not).
    const std::string program = kHead +
                                "CALL OZAGR PX=0 PY=10. PR=5. PZ=-20. PI=5. PT=50.\n"
                                "CALL OZAGR PX=7. PY=10. PR=5. PZ=-20. PI=5. PT=50.\n"
                                "CALL OZAGR PX=9. PY=11. PR=5. PZ=-20. PI=5. PT=50.\n"
                                "CALL OZAGR PX=7. PY=10. PR=5. PZ=-22. PI=5. PT=50.\n"
                                "CALL OZAGR PX=7. PY=10. PR=5. PZ=-22. PI=5. PT=50. PL=3.\n"
                                "M53\n"
                                "CALL OZAGR PX=7. PY=10. PR=5. PZ=-22. PI=5. PT=50. PL=3.\n"
                                "MODIN OG87C PR=-45. PZ=-36. PC=22. PI=2.5 PD=21.\n"
                                "X10. Y5.\n"
                                "X12. Y5.\n"
                                "MODOUT\n"
                                "G0 Z40.\n"
                                "CALL OG87C PX=0 PY=0 PR=-45. PZ=-36. PC=22. PI=2.5 PD=21.\n"
                                "CALL OG87C PX=5. PY=0 PR=-45. PZ=-36. PC=22. PI=2.5 PD=21.\n"
                                "G0 Z45.\n"
                                "CALL OG87C PX=5. PY=0 PR=-45. PZ=-36. PC=22. PI=2.5 PD=21.\n"
                                "G91\n"
                                "CALL OZAGR PX=0 PY=0 PR=5. PZ=-20. PI=5. PT=50.\n"
                                "G90 G18\n"
                                "CALL OZAGR PX=0 PY=0 PR=5. PZ=-20. PI=5. PT=50.\n"
                                "M30\n";
    const int hits_before = hits, misses_before = misses;
    compare("inputs.MIN", program, travel);
    CHECK(hits - hits_before == 3);  // lines 7, 14 and 18
    CHECK(misses - misses_before == 10);
    CHECK(hits > 20);
}

TEST_CASE("a hole HoleAxisMemo calls the same as the last one has the same cycle-axis points") {
    // OSP301 passes over the cycle-axis points of a hole the memo calls the
    // same as the last quiet one, and looks only at the hole's position
    // (EnvelopeDetail::Plane). On every pair of holes in a row, in the
    // corpus and in a program that changes one input at a time, "same" must
    // mean the same points, and the plane part must be the one of the
    // envelope worked out in values.
    int hits = 0, misses = 0;
    auto compare = [&](const std::string& name, const std::string& text, const Config& config) {
        HoleAxisMemo memo;
        walk_memo(
            name, text, config, false, [&](const BlockView& v) { return memo.same(v, config); },
            [&](const BlockView& v) { memo.remember(v, config); }, hits, misses);
    };
    Config travel;
    travel.travel['X'] = TravelLimit{-20, 20};
    travel.travel['Z'] = TravelLimit{-25, 60};
    on_corpus(travel, compare);
    // The holes after the first of each cycle repeat the one before but for
    // one input: the position in the plane only (a hit), a word of the
    // cycle on the block, G98/G99, the return level, the distance mode, the
    // plane. A G88 hole is never the same (its shifts move in the plane
    // from the hole); the holes of G114 (OG84L) are, since its steps read
    // R, Z and L only.
    const std::string program = kHead +
                                "G98 G114 X14.5 Y-20. R10. Z-21.5 L1.5 P.5 F600 FA=650\n"  // 5: no hole
                                "X19.5 Y-20.\n"                        // 6: miss (nothing remembered)
                                "X-17.5 Y-20.\n"                       // 7: hit
                                "X-15.5 Y-20. L2.\n"                   // 8: miss (L)
                                "X-13.5 Y-20.\n"                       // 9: miss (the cycle's L changed)
                                "X-11.5 Y-20.\n"                       // 10: hit
                                "M204\n"
                                "G98 G81 X10. Y10. R3. Z-20. F100\n"   // 12: the start
                                "X12. Y10.\n"                          // 13: miss (the start gives R and Z)
                                "X14. Y10.\n"                          // 14: hit
                                "X16.\n"                               // 15: hit
                                "X25. Y10.\n"                          // 16: hit (past X: the plane part says so)
                                "X18. Y10. Z-22.\n"                    // 17: miss (a Z word)
                                "X20. Y10.\n"                          // 18: miss (the cycle's Z changed)
                                "X19. Y10.\n"                          // 19: hit
                                "G99 X18. Y10.\n"                      // 20: miss (a G word)
                                "X17. Y10.\n"                          // 21: miss (G99: from the R point)
                                "X16. Y10.\n"                          // 22: hit
                                "G98 G91 X1.\n"                        // 23: miss (G words)
                                "X1.\n"                                // 24: miss (G91)
                                "X1.\n"                                // 25: hit
                                "G90\n"
                                "X15. Y10.\n"                          // 27: miss (G90)
                                "M53\n"
                                "X14. Y10.\n"                          // 29: miss (the return level)
                                "X13. Y10.\n"                          // 30: miss (M53 left Z at a G71 level not known)
                                "X12. Y10.\n"                          // 31: hit
                                "G80\n"
                                "G0 Z50.\n"
                                "G98 G88 X0 Y0 R3. Z-20. Q1. I1. J1. F100\n"  // 34: the start
                                "X5. Y5.\n"                            // 35: miss (G88)
                                "X6. Y5.\n"                            // 36: miss (G88)
                                "G80\n"
                                "G18 G0 Y50.\n"
                                "G98 G81 X10. Z10. R3. Y-20. F100\n"   // 39: the start
                                "X12. Z10.\n"                          // 40: miss
                                "X13. Z10.\n"                          // 41: hit
                                "X14. Y-19.\n"                         // 42: miss (Y is the cycle axis in G18)
                                "G80\n"
                                "M30\n";
    const int hits_before = hits, misses_before = misses;
    compare("holes.MIN", program, travel);
    CHECK(hits - hits_before == 10);
    CHECK(misses - misses_before == 20);
    CHECK(hits > 20);

    // A G-code macro cycle whose step reads the argument X gives (a shop's
    // catalog entry could): X changes from hole to hole, so no hole is the
    // same as the last.
    std::string text = testing::read_file(fs::path(OSPLINT_SOURCE_DIR) / "data" / "macros.toml");
    const std::string step = "target = \"Z+L\", source = \"003:L121\"";
    const size_t at = text.find(step);
    REQUIRE(at != std::string::npos);
    text.replace(at, step.size(), "target = \"Z+L-X\", source = \"003:L121\"");
    Config reads_x = travel;
    reads_x.catalog = Catalog::from_toml_text(text, "macros.toml");
    const int hits_x = hits, misses_x = misses;
    compare("reads-x.MIN", program, reads_x);
    CHECK(hits - hits_x == 8);      // the holes of the G81s
    CHECK(misses - misses_x == 22);  // and those of G114 every one (lines 6 to 10)
}

TEST_CASE("unknown values stay unknown") {
    auto t = trace_text(kHead +
                        "CALL OZAGR PR=5. PZ=VC1 PI=6.\n"
                        "CALL OTHER\n"
                        "G81 X10. Y10. Z-20. R3. F100\n"
                        "G80\nM30\n");
    const Envelope& z = at_line(t, 5);
    CHECK(!z.bounded());
    CHECK(z.lowest->value == doctest::Approx(5));  // only PR is known
    REQUIRE(!z.unknown_points().empty());
    CHECK(z.unknown_points().front()->describe().find("VC1") != std::string::npos);
    const Envelope& g = at_line(t, 7);
    CHECK(!g.bounded());
    CHECK(g.unknown_points().front()->step == "I");
    // a subprogram library: the plane is not known, so neither is the axis
    auto s = trace_text("OSUB\nCALL OZAGR PR=5. PZ=-20. PI=6.\nRTS\n", Config{}, "S.SSB");
    const Envelope& sub = at_line(s, 2);
    CHECK(!sub.plane.has_value());
    CHECK(!sub.bounded());
}

// ---------------------------------------------------------------------------
// Rules

TEST_CASE("OSP301 fires when OZAGR goes below the Z travel and not when it stays inside") {
    Config config = travel_z(-300, 150);
    auto bad = run_rule("OSP301", kHead + "CALL OZAGR PX=0 PY=120. PR=5. PZ=-298. PI=5.\nM30\n", config);
    REQUIRE(bad.size() == 1);
    CHECK(bad[0].rule == "OSP301");
    CHECK(bad[0].severity == Severity::Error);
    CHECK(bad[0].range.start.line == 5);
    CHECK(bad[0].message.find("-308") != std::string::npos);   // the value reached
    CHECK(bad[0].message.find("-300") != std::string::npos);   // the limit
    CHECK(bad[0].message.find("step 3c") != std::string::npos);  // the step
    auto good = run_rule("OSP301", kHead + "CALL OZAGR PX=0 PY=120. PR=5. PZ=-288. PI=5.\nM30\n", config);
    CHECK(good.empty());
    // without [machine.travel] nothing is checked
    CHECK(run_rule("OSP301", kHead + "CALL OZAGR PR=5. PZ=-298. PI=5.\nM30\n", Config{}).empty());
    // the bundled mistake
    fs::path mistake = fs::path(OSPLINT_SOURCE_DIR) / "examples" / "mistakes" / "ZTRAVEL.MIN";
    auto r = run_rule("OSP301", testing::read_file(mistake), load_config(fs::path(OSPLINT_SOURCE_DIR) / "examples" / "osplint.toml"));
    REQUIRE(r.size() == 1);
    CHECK(r[0].message.find("PZ-PI-PL = -298-5-5 = -308") != std::string::npos);
}

TEST_CASE("plane spans past [machine.travel]: reported once per axis and direction, with what they rest on") {
    Config config;
    config.travel['X'] = {-400, 400};
    config.travel['Y'] = {-250, 250};
    config.travel['Z'] = {-300, 150};
    auto t = trace_text(kHead +
                        "M54\n"
                        "CALL OKYOX PX=370. PY=0 PR=2. PZ=-5. PI=40. PJ=10. PD=15\n"  // 6: slot X 370..410
                        "CALL OKYOX PX=350. PY=0 PR=2. PZ=-5. PI=40. PJ=10. PD=15\n"  // 7: X 350..390, inside
                        "CALL OKYOX PX=420. PY=0 PR=2. PZ=-5. PI=40. PJ=10. PD=15\n"  // 8: the start point is past
                        "G98\n"
                        "G88 X399. Y10. Z-30. R3. I1.5 J-0.5 Q0.3 F100\n"            // 10: X 399..400.5
                        "G80\nM30\n",
                        config);
    auto slot = travel_violations(at_line(t, 6), config);
    REQUIRE(slot.size() == 1);
    CHECK(slot[0].axis == 'X');
    CHECK(!slot[0].below);
    CHECK(slot[0].value == doctest::Approx(410));
    CHECK(slot[0].limit == doctest::Approx(400));
    CHECK(slot[0].inferred);  // the start point taken as one end; a compensated contour
    CHECK(slot[0].name == "PI");
    CHECK(slot[0].note.find("reading") != std::string::npos);
    CHECK(slot[0].note.find("compensation") != std::string::npos);
    CHECK(travel_violations(at_line(t, 7), config).empty());
    auto start = travel_violations(at_line(t, 8), config);
    REQUIRE(start.size() == 1);  // the position, not the slot beyond it as well
    CHECK(start[0].value == doctest::Approx(420));
    CHECK(start[0].note.empty());
    auto shift = travel_violations(at_line(t, 10), config);
    REQUIRE(shift.size() == 1);
    CHECK(shift[0].value == doctest::Approx(400.5));
    CHECK(shift[0].name == "I");
    CHECK(shift[0].inferred);
    // outside G17 the direction of PI is not documented: the span both ways is not checked
    auto g18 = trace_text("O1000\nG18\nG0 G90 X380. Z0\nG0 Y50.\nM54\n"
                          "CALL OKYOX PX=0 PZ=0 PR=2. PY=380. PI=40. PJ=10. PD=15\nM30\n",
                          config);
    const Envelope& h = at_line(g18, 6);
    bool either = false;
    for (const auto& sp : h.plane_spans)
        if (sp.axis == 'X') {
            either = sp.either_way;
            CHECK(sp.range.hi == doctest::Approx(420));
        }
    CHECK(either);
    for (const auto& tv : travel_violations(h, config)) CHECK(tv.axis != 'X');
    // OSP301 reports the span on the word that sets it, with the note
    auto d = run_rule("OSP301", kHead + "G98\nG88 X399. Y10. Z-30. R3. I1.5 J-0.5 Q0.3 F100\nG80\nM30\n", config);
    REQUIRE(d.size() == 1);
    CHECK(d[0].range.start.line == 6);
    CHECK(d[0].message.find("400.5") != std::string::npos);
    bool noted = false;
    for (const auto& n : d[0].notes) noted = noted || n.message.find("reading of the manual") != std::string::npos;
    CHECK(noted);
}

TEST_CASE("OSP302 fires on an OLPEX whose PA+PK exceeds its stroke") {
    auto bad = run_rule("OSP302",
                        kHead + "CALL OLPEX PX=20. PY=0 PR=2. PZ=-30. PI=60. PQ=3. PA=22. PK=12. PJ=1.5\nM30\n", Config{});
    REQUIRE(bad.size() == 1);
    CHECK(bad[0].severity == Severity::Warning);
    CHECK(bad[0].message.find("PA+PK = 22+12 = 34") != std::string::npos);
    CHECK(bad[0].message.find("PR-PZ = 2-(-30) = 32") != std::string::npos);
    CHECK(bad[0].message.find("inferred") != std::string::npos);
    auto good = run_rule("OSP302",
                         kHead + "CALL OLPEX PX=20. PY=0 PR=2. PZ=-30. PI=60. PQ=3. PA=3. PK=.5 PJ=1.5\nM30\n", Config{});
    CHECK(good.empty());
    // PR not above PZ, read along +Y in G18
    auto g18 = run_rule("OSP302", "O1000\nG18\nCALL OZAGR PR=-30. PZ=-20. PI=6.\nG17\nM30\n", Config{});
    REQUIRE(g18.size() == 1);
    CHECK(g18[0].message.find("above PZ on Y") != std::string::npos);
}

TEST_CASE("OSP303 is off by default and honours [analysis] explain-unknown") {
    const std::string text = kHead + "CALL OZAGR PR=5. PZ=VC1 PI=6.\nM30\n";
    auto count = [](const std::vector<Diagnostic>& ds) {
        size_t n = 0;
        for (const auto& d : ds)
            if (d.rule == "OSP303") ++n;
        return n;
    };
    Config off;
    CHECK(count(check_text("T.MIN", text, off).diagnostics) == 0);
    Config on = parse_config("[analysis]\nexplain-unknown = true\n", "on.toml");
    auto ds = check_text("T.MIN", text, on).diagnostics;
    REQUIRE(count(ds) == 1);
    for (const auto& d : ds)
        if (d.rule == "OSP303") {
            CHECK(d.severity == Severity::Info);
            CHECK(d.message.find("VC1") != std::string::npos);
        }
    // selected explicitly: it runs itself, once
    Config selected;
    selected.explain_unknown = true;
    selected.rule_severity["OSP303"] = Severity::Info;
    CHECK(count(check_text("T.MIN", text, selected).diagnostics) == 1);
    // switched off explicitly
    Config ignored = parse_config("[analysis]\nexplain-unknown = true\n[rules]\nOSP303 = \"off\"\n", "off.toml");
    CHECK(count(check_text("T.MIN", text, ignored).diagnostics) == 0);
}

// ---------------------------------------------------------------------------
// The picture

namespace {

// A small XML well-formedness check: one root element, tags nest and match,
// attributes are quoted and unique, entities are known, nothing after the root.
std::string xml_problem(const std::string& s) {
    size_t i = 0;
    std::vector<std::string> stack;
    bool root_seen = false, root_closed = false;
    auto name_char = [](char c) { return std::isalnum(static_cast<unsigned char>(c)) || c == '-' || c == '_' || c == ':' || c == '.'; };
    auto check_text = [&](size_t from, size_t to) -> std::string {
        for (size_t k = from; k < to; ++k) {
            if (s[k] == '<') return "stray <";
            if (s[k] == '&') {
                size_t semi = s.find(';', k);
                if (semi == std::string::npos || semi > to) return "unterminated entity";
                std::string ent = s.substr(k + 1, semi - k - 1);
                if (ent != "amp" && ent != "lt" && ent != "gt" && ent != "quot" && ent != "apos" && ent.rfind('#', 0) != 0)
                    return "unknown entity &" + ent + ";";
            }
            if (root_closed && !std::isspace(static_cast<unsigned char>(s[k]))) return "text after the root element";
        }
        return "";
    };
    while (i < s.size()) {
        size_t lt = s.find('<', i);
        if (lt == std::string::npos) {
            if (auto p = check_text(i, s.size()); !p.empty()) return p;
            break;
        }
        if (auto p = check_text(i, lt); !p.empty()) return p;
        if (s.compare(lt, 5, "<?xml") == 0) {
            if (lt != 0) return "XML declaration not at the start";
            size_t e = s.find("?>", lt);
            if (e == std::string::npos) return "unterminated declaration";
            i = e + 2;
            continue;
        }
        if (s.compare(lt, 4, "<!--") == 0) {
            size_t e = s.find("-->", lt);
            if (e == std::string::npos) return "unterminated comment";
            i = e + 3;
            continue;
        }
        size_t gt = s.find('>', lt);
        if (gt == std::string::npos) return "unterminated tag";
        std::string tag = s.substr(lt + 1, gt - lt - 1);
        if (!tag.empty() && tag[0] == '/') {
            std::string n = tag.substr(1);
            while (!n.empty() && std::isspace(static_cast<unsigned char>(n.back()))) n.pop_back();
            if (stack.empty() || stack.back() != n) return "mismatched </" + n + ">";
            stack.pop_back();
            if (stack.empty()) root_closed = true;
            i = gt + 1;
            continue;
        }
        bool self = !tag.empty() && tag.back() == '/';
        if (self) tag.pop_back();
        size_t k = 0;
        while (k < tag.size() && name_char(tag[k])) ++k;
        std::string name = tag.substr(0, k);
        if (name.empty()) return "element without a name";
        if (root_closed) return "second root element <" + name + ">";
        std::set<std::string> attrs;
        while (k < tag.size()) {
            while (k < tag.size() && std::isspace(static_cast<unsigned char>(tag[k]))) ++k;
            if (k >= tag.size()) break;
            size_t a = k;
            while (k < tag.size() && name_char(tag[k])) ++k;
            std::string an = tag.substr(a, k - a);
            if (an.empty() || k >= tag.size() || tag[k] != '=') return "bad attribute in <" + name + ">";
            if (!attrs.insert(an).second) return "duplicate attribute " + an + " in <" + name + ">";
            ++k;
            if (k >= tag.size() || (tag[k] != '"' && tag[k] != '\'')) return "unquoted attribute " + an;
            char q = tag[k];
            size_t e = tag.find(q, k + 1);
            if (e == std::string::npos) return "unterminated attribute " + an;
            std::string v = tag.substr(k + 1, e - k - 1);
            if (v.find('<') != std::string::npos) return "< in attribute " + an;
            k = e + 1;
        }
        if (!root_seen) root_seen = true;
        if (!self) stack.push_back(name);
        else if (stack.empty()) root_closed = true;
        i = gt + 1;
    }
    if (!root_seen) return "no root element";
    if (!stack.empty()) return "unclosed <" + stack.back() + ">";
    return "";
}

std::map<std::string, std::string> attributes(const std::string& tag) {
    std::map<std::string, std::string> out;
    static const std::regex re("([a-zA-Z_:][-a-zA-Z0-9_:.]*)=\"([^\"]*)\"");
    for (auto it = std::sregex_iterator(tag.begin(), tag.end(), re); it != std::sregex_iterator(); ++it)
        out[(*it)[1]] = (*it)[2];
    return out;
}

std::vector<std::map<std::string, std::string>> elements(const std::string& svg, const std::string& start) {
    std::vector<std::map<std::string, std::string>> out;
    size_t i = 0;
    while ((i = svg.find(start, i)) != std::string::npos) {
        size_t e = svg.find('>', i);
        out.push_back(attributes(svg.substr(i, e - i)));
        i = e;
    }
    return out;
}

// Checks every bar of the picture against the envelope of its first line,
// with the scale the picture declares on its panel.
void check_bars(const std::string& svg, const std::vector<Envelope>& envelopes, size_t expected_columns) {
    INFO(xml_problem(svg));
    REQUIRE(xml_problem(svg).empty());
    auto panels = elements(svg, "<g class=\"panel\"");
    REQUIRE(!panels.empty());
    auto columns = elements(svg, "<g class=\"column\"");
    CHECK(columns.size() == expected_columns);
    // Bars in order, each inside its column group.
    size_t pos = 0, bars = 0;
    while ((pos = svg.find("<g class=\"column\"", pos)) != std::string::npos) {
        size_t end = svg.find("</g>", pos);
        std::string col = svg.substr(pos, end - pos);
        auto head = attributes(col.substr(0, col.find('>')));
        uint32_t line = static_cast<uint32_t>(std::stoul(head["data-lines"]));
        const Envelope* env = nullptr;
        for (const auto& e : envelopes)
            if (e.line == line) env = &e;
        REQUIRE(env);
        // the panel of this column: the last panel opened before it
        size_t ppos = svg.rfind("<g class=\"panel\"", pos);
        auto panel = attributes(svg.substr(ppos, svg.find('>', ppos) - ppos));
        CHECK(panel["data-axis"] == std::string(1, env->axis));
        double v_top = std::stod(panel["data-v-top"]), y_top = std::stod(panel["data-y-top"]),
               ppu = std::stod(panel["data-px-per-unit"]);
        auto bar = elements(col, "<rect class=\"envelope\"");
        if (env->bounded()) {
            REQUIRE(bar.size() == 1);
            ++bars;
            CHECK(std::stod(bar[0]["data-low"]) == doctest::Approx(env->lowest->value));
            CHECK(std::stod(bar[0]["data-high"]) == doctest::Approx(env->highest->value));
            double y = y_top + (v_top - env->highest->value) * ppu;
            double h = (env->highest->value - env->lowest->value) * ppu;
            CHECK(std::stod(bar[0]["y"]) == doctest::Approx(y).epsilon(1e-3));
            CHECK(std::stod(bar[0]["height"]) == doctest::Approx(h).epsilon(1e-3));
        } else {
            CHECK(bar.empty());
            CHECK(col.find("class=\"unbounded\"") != std::string::npos);
        }
        pos = end;
    }
    CHECK(bars > 0);
}

}  // namespace

TEST_CASE("the XML check itself rejects broken documents") {
    CHECK(xml_problem("<svg><g></g></svg>").empty());
    CHECK(!xml_problem("<svg><g></svg>").empty());
    CHECK(!xml_problem("<svg a=\"1\" a=\"2\"/>").empty());
    CHECK(!xml_problem("<svg>a & b</svg>").empty());
    CHECK(!xml_problem("<svg/><svg/>").empty());
    CHECK(!xml_problem("<svg x=1/>").empty());
}

TEST_CASE("the side view: bars match the envelopes, violations are red, columns merge alike holes") {
    Config config = load_config(fs::path(OSPLINT_SOURCE_DIR) / "examples" / "osplint.toml");
    auto t = trace_text(kHead +
                        "CALL OZAGR PX=0 PY=120. PR=5. PZ=-298. PI=5.\n"  // 5: below the travel
                        "G98\n"
                        "G81 X10. Y10. Z-20. R3. F100\n"                  // 7
                        "X20. Y10.\nX30. Y10.\n"                           // 8, 9: same motion as 7
                        "G80\n"
                        "CALL OZAGR PR=5. PZ=VC1 PI=6.\n"                  // 11: unbounded
                        "M30\n",
                        config);
    SvgPicture pic = render_motion_svg(t.envelopes, config, "T.MIN & <test>");
    CHECK(pic.columns == 3 + 0);  // OZAGR, G81 x3, OZAGR (unbounded)
    CHECK(pic.svg.find("T.MIN &amp; &lt;test&gt;") != std::string::npos);
    check_bars(pic.svg, t.envelopes, pic.columns);
    CHECK(pic.svg.find("class=\"violation\"") != std::string::npos);
    CHECK(pic.svg.find("data-lines=\"7,8,9\"") != std::string::npos);
    CHECK(pic.svg.find("class=\"travel\"") != std::string::npos);
    CHECK(pic.svg.find("class=\"legend\"") != std::string::npos);
    REQUIRE(pic.panels.size() == 1);
    // the scale the picture reports is the one the bars use
    const Envelope& oz = at_line(t, 5);
    CHECK(pic.panels[0].y(oz.highest->value) < pic.panels[0].y(oz.lowest->value));
}

TEST_CASE("osplint trace --svg on the bundled examples draws well-formed pictures of their envelopes") {
    fs::path src(OSPLINT_SOURCE_DIR);
    Config config = load_config(src / "examples" / "osplint.toml");
    fs::path tmp = fs::temp_directory_path() / ("osplint_motion_" + std::to_string(::getpid()));
    fs::create_directories(tmp);
    size_t drawn = 0;
    for (const char* name : {"BACKBAR.MIN", "BACKBORE.MIN", "DRILL.MIN", "KEYWAY.MIN", "PUMPBODY.MIN", "TAPG114.MIN",
                             "WALLFIN.MIN", "mistakes/ZTRAVEL.MIN"}) {
        CAPTURE(name);
        fs::path in = src / "examples" / name;
        fs::path out = tmp / (fs::path(name).stem().string() + ".svg");
        std::string cmd = std::string("\"") + OSPLINT_BINARY + "\" trace --svg \"" + out.string() + "\" \"" +
                          in.string() + "\" > \"" + (tmp / "trace.txt").string() + "\" 2>&1";
        REQUIRE(std::system(cmd.c_str()) == 0);
        std::string svg = testing::read_file(out);
        std::string text = testing::read_file(tmp / "trace.txt");
        CHECK(text.find("envelope [") != std::string::npos);
        auto t = trace_text(testing::read_file(in), config, in.string());
        REQUIRE(!t.envelopes.empty());
        SvgPicture pic = render_motion_svg(t.envelopes, config, in.filename().string());
        CHECK(svg == pic.svg);  // the CLI draws exactly what the library computes
        check_bars(svg, t.envelopes, pic.columns);
        if (std::string(name) == "mistakes/ZTRAVEL.MIN") CHECK(svg.find("class=\"violation\"") != std::string::npos);
        else CHECK(svg.find("class=\"violation\"") == std::string::npos);
        ++drawn;
    }
    CHECK(drawn == 8);
    fs::remove_all(tmp);
}

TEST_CASE("a call's arguments are found by their spec: name first, then aliases, as by name") {
    Config config;
    const MacroSpec* spec = config.catalog.find("OG84L");
    REQUIRE(spec);
    const ArgSpec* z = spec->arg("Z");
    const ArgSpec* r = spec->arg("R");
    const ArgSpec* l = spec->arg("L");
    REQUIRE((z && r && l));
    REQUIRE(spec->arg("PZ") == z);  // PZ is an alias of Z
    auto make = [&](std::vector<std::string> names) {
        MacroCall call;
        call.kind = CallKind::Call;
        call.name = "OG84L";
        call.spec = spec;
        for (auto& n : names) call.args.push_back(MacroArg{n, nullptr, Val<double>::of(1)});
        return call;
    };
    for (bool linked : {false, true}) {
        CAPTURE(linked);
        MacroCall c = make({"R", "PZ"});
        if (linked) link_arg_specs(c);
        CHECK(c.given(*z) == &c.args[1]);
        CHECK(c.given(*r) == &c.args[0]);
        CHECK(c.given(*l) == nullptr);
        if (linked) CHECK(c.args[1].spec == z);
        // Given by its alias and its name: the name wins, wherever it is written.
        MacroCall both = make({"PZ", "R", "Z"});
        if (linked) link_arg_specs(both);
        CHECK(both.given(*z) == &both.args[2]);
        // A name in other letters than the catalog's is not the argument.
        MacroCall lower = make({"pz"});
        if (linked) link_arg_specs(lower);
        CHECK(lower.given(*z) == nullptr);
    }
    // An argument of another spec is looked up by name.
    const MacroSpec* other = config.catalog.find("OZAGR");
    REQUIRE(other);
    REQUIRE(other->arg("PZ"));
    MacroCall c = make({"PZ"});
    link_arg_specs(c);
    CHECK(c.given(*other->arg("PZ")) == &c.args[0]);
}
