// The modal state: what the transfer function computes for each kind of
// block, how states merge where paths join (jumps, loops), and that the
// fixpoint stays linear in the size of the program.
#include <doctest/doctest.h>

#include <string>
#include <vector>

#include "analysis.h"

using namespace osplint;

namespace {

using Run = osplint::testing::Analysis;

Run run(std::string text, std::vector<std::string> rules = {}, std::string path = "T.MIN") {
    static const Config config;
    return osplint::testing::analyze_text(path, text, config, std::move(rules));
}

const ActiveCycle& cycle_of(const ModalState& s) {
    REQUIRE(s.cycle.known);
    REQUIRE(s.cycle.value.has_value());
    return *s.cycle.value;
}

}  // namespace

TEST_CASE("modal state: G-code modes, offsets and compensation") {
    auto r = run(
        "O1000\n"              // 1
        "G20\n"                // 2
        "G21\n"                // 3
        "G18\n"                // 4
        "G19\n"                // 5
        "G17\n"                // 6
        "G56 Z50 H3\n"         // 7
        "G41 D21\n"            // 8
        "G40\n"                // 9
        "G53\n"                // 10
        "G91\n"                // 11
        "G90\n"                // 12
        "G60 X1\n"             // 13
        "X2\n"                 // 14
        "G1 X3 F200\n"         // 15
        "G15 H2\n"             // 16
        "M30\n");
    CHECK(r.at(1).after.units.is(Units::Mm));  // [machine] units default
    CHECK(r.at(2).after.units.is(Units::Inch));
    CHECK(r.at(3).after.units.is(Units::Mm));
    CHECK(r.at(4).after.plane.is(Plane::G18));
    CHECK(r.at(5).after.plane.is(Plane::G19));
    CHECK(r.at(6).after.plane.is(Plane::G17));
    CHECK(r.at(7).after.length_offset.is(true));
    CHECK(r.at(7).after.length_offset_h.is(3));
    CHECK(r.at(7).after.z.is(50));
    CHECK(r.at(8).after.cutter_comp.is(41));
    CHECK(r.at(8).after.cutter_comp_d.is(21));
    CHECK(r.at(9).after.cutter_comp.is(40));
    CHECK(r.at(10).after.length_offset.is(false));
    CHECK_FALSE(r.at(10).after.z.known);  // the offset changed the tip's Z
    CHECK(r.at(11).after.distance.is(Distance::Incremental));
    CHECK(r.at(12).after.distance.is(Distance::Absolute));
    // G60 is in the interpolation group: modal until G0/G1/G2/G3.
    CHECK(r.at(13).after.motion.is(60));
    CHECK(r.at(14).after.motion.is(60));
    CHECK(r.at(14).after.x.is(2));
    CHECK(r.at(15).after.motion.is(1));
    CHECK(r.at(15).after.feed.is(200));
    CHECK(r.at(16).after.work_offset.is(2));
    CHECK_FALSE(r.at(16).after.x.known);  // a new work coordinate system
}

TEST_CASE("modal state: units default from [machine] units") {
    Config inch = parse_config("[machine]\nunits = \"inch\"\n", "osplint.toml");
    auto res = osplint::testing::analyze_text("T.MIN", "O1000\nG0 X1\nG21\nM30\n", inch);
    CHECK(res.at(2).after.units.is(Units::Inch));
    CHECK(res.at(3).after.units.is(Units::Mm));
}

TEST_CASE("modal state: MODIN/MODOUT, fixed cycles, G114 and M204, NCYL") {
    auto r = run(
        "O1000\n"                                   // 1
        "MODIN OG87N PR=5 PZ=-25 PL=4 PI=2 PJ=6\n"  // 2
        "MODOUT\n"                                  // 3
        "G90 G17 G0 X0 Y0 Z50\n"                    // 4
        "G98 G81 X10 Y10 Z-5 R3 F150\n"             // 5
        "X20 Y10\n"                                 // 6
        "G80\n"                                     // 7
        "S800 M3\n"                                 // 8
        "G114 X5 Y5 R10 Z-21.5 F1200 FA=1300\n"     // 9
        "X10 Y10\n"                                 // 10
        "M204\n"                                    // 11
        "G99 G81 X10 Y10 Z-5 R3 F150 M53\n"         // 12
        "NCYL X30 Y30\n"                            // 13
        "X40 Y40\n"                                 // 14
        "G80\n"                                     // 15
        "M30\n");
    // MODIN ... MODOUT
    const ModalState& m = r.at(2).after;
    REQUIRE(m.modin.known);
    REQUIRE(m.modin.value.has_value());
    CHECK(m.modin.value->macro == "OG87N");
    CHECK(m.modin.value->line == 2);
    CHECK(m.modin.value->values().at("PR") == 5);
    CHECK(m.modin.value->values().at("PZ") == -25);
    CHECK(r.at(3).after.modin.known);
    CHECK_FALSE(r.at(3).after.modin.value.has_value());

    // G81 ... G80: R, Z, initial point, and the return to the initial point (G98).
    const ActiveCycle& c = cycle_of(r.at(5).after);
    CHECK(c.code == 81);
    CHECK(c.macro.empty());
    CHECK(c.start_line == 5);
    CHECK(c.r.is(3));
    CHECK(c.z.is(-5));
    CHECK(c.initial.is(50));
    CHECK(r.at(5).after.cycle_return.is(CycleReturn::Initial));
    CHECK(r.at(5).after.z.is(50));
    CHECK(r.at(6).after.x.is(20));
    CHECK(cycle_of(r.at(6).after).start_line == 5);
    CHECK(r.at(7).after.cycle.known);
    CHECK_FALSE(r.at(7).after.cycle.value.has_value());

    // G114 (OG84L registered to G114) ... M204 (OC84L): overrides, spindle.
    const ActiveCycle& t = cycle_of(r.at(9).after);
    CHECK(t.code == 114);
    CHECK(t.macro == "OG84L");
    CHECK(t.words.get().at("FA").is(1300));
    // A hole block gives no modal word: it keeps the cycle's words as they
    // are, shared with the state before it.
    CHECK(cycle_of(r.at(10).after).words.shares(t.words));
    CHECK(cycle_of(r.at(10).after) == t);
    CHECK(r.at(9).after.overrides_disabled.is(true));
    CHECK(r.at(9).after.x.is(5));
    CHECK(r.at(9).after.z.is(50));  // the declaration block does not run the cycle axis
    CHECK(r.at(10).after.spindle.is(3));
    const ModalState& after_m204 = r.at(11).after;
    CHECK(after_m204.cycle.known);
    CHECK_FALSE(after_m204.cycle.value.has_value());
    CHECK(after_m204.overrides_disabled.is(false));
    CHECK(after_m204.spindle.is(5));
    CHECK(after_m204.spindle_stopped_by.is(11));

    // G99 with M53: the return level; NCYL is one-shot and positions only.
    CHECK(r.at(12).after.return_level.is(53));
    CHECK(r.at(12).after.cycle_return.is(CycleReturn::R));
    CHECK_FALSE(r.at(12).after.z.known);  // M53 returns to the G71 level, never set here
    CHECK(r.at(13).after.ncyl);
    CHECK_FALSE(r.at(13).before.ncyl);
    CHECK_FALSE(r.at(14).before.ncyl);
    CHECK(r.at(13).after.x.is(30));
}

TEST_CASE("modal state: variables with known constant values") {
    auto r = run(
        "O1000\n"              // 1
        "VC1=5\n"              // 2
        "VC[2]=VC1+1\n"        // 3
        "PX=3\n"               // 4
        "VC3=VC9\n"            // 5
        "CALL OZAGR PR=5 PZ=-20 PI=12\n"  // 6
        "CALL OSUB1\n"         // 7
        "M30\n");
    const auto& v = r.at(4).after.vars;
    CHECK(v.at("VC1") == 5);
    CHECK(v.at("VC2") == 6);
    CHECK(v.at("PX") == 3);
    CHECK(r.at(5).after.vars.count("VC3") == 0);  // VC9 is not known
    // A catalog macro that keeps VC120-VC128 for itself leaves VC1 alone;
    // an unknown subprogram may change any common variable, not the locals.
    CHECK(r.at(6).after.vars.count("VC1") == 1);
    CHECK(r.at(7).after.vars.count("VC1") == 0);
    CHECK(r.at(7).after.vars.count("PX") == 1);
}

TEST_CASE("modal state: a macro that keeps VC120-VC128 for itself forgets those nine only") {
    auto r = run(
        "O1000\n"                                                  // 1
        "VC119=1 VC120=2 VC124=3 VC128=4 VC129=5 VC1200=6 VC12=7\n"  // 2
        "CALL OZAGR PR=5 PZ=-20 PI=12\n"                          // 3
        "M30\n");
    const auto& before = r.at(2).after.vars;
    const auto& after = r.at(3).after.vars;
    for (const char* kept : {"VC119", "VC129", "VC1200", "VC12"}) {
        CHECK_MESSAGE(before.count(kept) == 1, kept);
        CHECK_MESSAGE(after.count(kept) == 1, kept);
    }
    for (const char* gone : {"VC120", "VC124", "VC128"}) {
        CHECK_MESSAGE(before.count(gone) == 1, gone);
        CHECK_MESSAGE(after.count(gone) == 0, gone);
    }
}

TEST_CASE("merged state at a forward GOTO target") {
    const std::string head =
        "O1000\n"                  // 1
        "G90 G0 X0 Y0 Z50\n"       // 2
        "IF [VC1 EQ 1] NB\n"       // 3
        "G90\n"                    // 4
        "GOTO NA\n";               // 5
    const std::string tail =
        "NA G81 X10 Y10 Z-5 R3 F150 L2\n"  // 7
        "G80\n"                            // 8
        "M30\n";
    SUBCASE("the paths disagree on G90/G91: unknown, OSP209 silent") {
        auto r = run(head + "NB G91\n" + tail, {"OSP209"});
        CHECK_FALSE(r.at(7).before.distance.known);
        CHECK(r.findings("OSP209", 7) == 0);
    }
    SUBCASE("every path has G90: known, OSP209 fires") {
        auto r = run(head + "NB G90\n" + tail, {"OSP209"});
        CHECK(r.at(7).before.distance.is(Distance::Absolute));
        CHECK(r.findings("OSP209", 7) == 1);
    }
}

TEST_CASE("merged state at a WHILE/DO/END loop head") {
    const std::string body =
        "VC1=0\n"                              // 4
        "WHILE [VC1 LT 3] DO 1\n"              // 5
        "G82 X10 Y10 Z-5 R3 P1 F150\n"         // 6
        "G83 X20 Y10 Z-20 R3 Q5 F120\n"        // 7
        "VC1=VC1+1\n"                          // 8
        "END 1\n"                              // 9
        "G80\n"                                // 10
        "M30\n";
    SUBCASE("G81 before the loop, G83 at its end: the cycle is unknown at the head") {
        auto r = run("O1000\nG90 G17 G0 X0 Y0 Z50\nG98 G81 X10 Y10 Z-5 R3 F150\n" + body, {"OSP204"});
        CHECK_FALSE(r.at(5).before.cycle.known);
        CHECK_FALSE(r.at(6).before.cycle.known);
        CHECK(r.findings("OSP204", 6) == 0);
        CHECK(r.findings("OSP204", 7) == 1);  // G82 is known there
        CHECK_FALSE(r.at(5).before.vars.count("VC1"));  // 0 on entry, 1.. on the back edge
    }
    SUBCASE("G83 on both edges: known (fields that differ are dropped), OSP204 fires") {
        auto r = run("O1000\nG90 G17 G0 X0 Y0 Z50\nG98 G83 X10 Y10 Z-20 R3 Q5 F120\n" + body, {"OSP204"});
        const ActiveCycle& c = cycle_of(r.at(6).before);
        CHECK(c.code == 83);
        CHECK(c.start_line == 0);  // started on line 3 on one path, line 7 on the other
        CHECK(c.r.is(3));          // equal on both paths
        CHECK(r.findings("OSP204", 6) == 1);
    }
}

TEST_CASE("merged state: a MODIN opened by the same block on every path stays open") {
    // Each pass evaluates PZ=VC1+1 to its own value: the MODIN is open on
    // every path, with the arguments the paths agree on.
    const std::string program =
        "O1000\n"                                          // 1
        "VC1=0\n"                                          // 2
        "N10 MODIN OG87N PR=5 PZ=-25 PL=4 PI=2 PJ=6 PF=100\n"  // 3
        "VC1=VC1+1\n"                                      // 4
        "IF [VC1 LT 2] N10\n"                              // 5
        "MODIN OG87N PR=5 PZ=VC1+1\n"                      // 6
        "IF [VC1 LT 2] N10\n";                             // 7
    auto r = run(program, {"OSP203"});
    const ModalState& end = r.at(7).after;
    REQUIRE(end.modin.known);
    REQUIRE(end.modin.value);
    CHECK(end.modin.value->line == 6);
    CHECK(end.modin.value->values().count("PR") == 1);  // 5 on every pass
    CHECK(end.modin.value->values().count("PZ") == 0);  // VC1+1: not the same on every pass
    // Open at the end on every path: a definite finding, not a "may".
    const FileResult f = check_text("T.MIN", program, Config{});
    bool never_closed = false;
    for (const auto& d : f.diagnostics)
        never_closed = never_closed || (d.rule == "OSP203" && d.message.find("OG87N is never closed") != std::string::npos);
    CHECK(never_closed);
    // Opened by different blocks on the two paths: unknown.
    ModalState a, b;
    ActiveModin m;
    m.macro = "OG87N";
    m.line = 3;
    m.args_to_edit() = ModinArgs{{{"PR", 5.0}}, {"PR"}};
    a.modin = Val<std::optional<ActiveModin>>::of(m);
    m.line = 6;
    b.modin = Val<std::optional<ActiveModin>>::of(m);
    a.merge(b);
    CHECK_FALSE(a.modin.known);
}

TEST_CASE("copies of an open MODIN share its arguments until one of them changes") {
    ModalState a, b;
    ActiveModin m;
    m.macro = "OG87N";
    m.line = 3;
    m.args_to_edit() = ModinArgs{{{"PR", 5.0}, {"PZ", -25.0}}, {"PR", "PZ"}};
    a.modin = Val<std::optional<ActiveModin>>::of(m);
    b = a;
    CHECK(&a.modin.value->values() == &b.modin.value->values());  // shared, not copied
    CHECK(a.modin == b.modin);
    // The paths disagree on PZ: the merge drops it from one state only.
    ActiveModin other = m;
    other.args_to_edit().values["PZ"] = -30.0;
    ModalState c;
    c.modin = Val<std::optional<ActiveModin>>::of(other);
    a.merge(c);
    REQUIRE(a.modin.known);
    CHECK(a.modin.value->values().count("PZ") == 0);
    CHECK(a.modin.value->values().at("PR") == 5.0);
    CHECK(b.modin.value->values().at("PZ") == -25.0);
    CHECK(m.values().at("PZ") == -25.0);
    CHECK(other.values().at("PZ") == -30.0);
    CHECK_FALSE(a.modin == b.modin);
}

TEST_CASE("merged state at the target of a backward IF jump") {
    auto program = [](const char* mode) {
        return std::string("O1000\n"                          // 1
                           "G90 G0 X0 Y0 Z50\n"               // 2
                           "VC1=0\n"                          // 3
                           "NLOOP G81 X10 Y10 Z-5 R3 F150 L2\n"  // 4
                           "G80\n"                            // 5
                           ) +
               mode +                                         // 6
               "\nVC1=VC1+1\n"                                // 7
               "IF [VC1 LT 3] NLOOP\n"                        // 8
               "G90\n"                                        // 9
               "M30\n";
    };
    SUBCASE("G91 on the back edge: unknown at NLOOP, OSP209 silent") {
        auto r = run(program("G91"), {"OSP209"});
        CHECK_FALSE(r.at(4).before.distance.known);
        CHECK(r.findings("OSP209") == 0);
        CHECK(r.at(9).after.distance.is(Distance::Absolute));
    }
    SUBCASE("G90 on the back edge: known at NLOOP, OSP209 fires") {
        auto r = run(program("G90"), {"OSP209"});
        CHECK(r.at(4).before.distance.is(Distance::Absolute));
        CHECK(r.findings("OSP209", 4) == 1);
    }
}

TEST_CASE("a subprogram starts from an unknown state") {
    auto r = run("OSUB1\nG81 X10 Y10 Z-5 R3 F150 L2\nG80\nRTS\n", {"OSP209"}, "S.SSB");
    CHECK_FALSE(r.at(1).before.distance.known);
    CHECK_FALSE(r.at(1).before.cycle.known);
    CHECK(r.findings("OSP209") == 0);
}

TEST_CASE("the fix of OSP208 replaces G80 by the registered cancel code") {
    auto r = run("O1000\nG90 G0 X0 Y0 Z50\nS800 M3\nG98 G114 R10 Z-21.5 F1200 FA=1300\nX10 Y10\nG80\nM30\n",
                 {"OSP208"});
    REQUIRE(r.result.diagnostics.size() == 1);
    const Diagnostic& d = r.result.diagnostics.front();
    REQUIRE(d.fixes.size() == 1);
    REQUIRE(d.fixes[0].edits.size() == 1);
    CHECK(d.fixes[0].edits[0].replacement == "M204");
    CHECK(d.fixes[0].edits[0].range.start.line == 6);
}

TEST_CASE("the fixpoint sweeps a loop a small constant number of times") {
    // A 50,000-block loop body with 5,000 labels, forward and backward
    // conditional jumps among them, and blocks that change the distance mode,
    // start and cancel cycles and assign variables, so that states disagree
    // where paths join.
    std::string p = "O1000\nG90 G17 G0 X0 Y0 Z50\nVC1=0\nWHILE [VC1 LT 10] DO 1\n";
    const int labels = 5000, per_label = 10;
    for (int k = 0; k < labels; ++k) {
        p += "N" + std::to_string(k + 1) + " G0 X" + std::to_string(k % 97) + "\n";
        switch (k % 5) {
            case 0: p += "G91\n"; break;
            case 1: p += "G90\n"; break;
            case 2: p += "G81 X1 Y1 Z-5 R3 F100\n"; break;
            case 3: p += "G80\n"; break;
            default: p += "VC" + std::to_string(2 + k % 50) + "=" + std::to_string(k) + "\n"; break;
        }
        // Jumps: forward by 3 labels, backward by 7 (where possible).
        int fwd = k + 3 < labels ? k + 3 : k;
        int back = k >= 7 ? k - 7 : 0;
        p += "IF [VC1 EQ " + std::to_string(k) + "] N" + std::to_string(fwd + 1) + "\n";
        p += "IF [VC2 EQ " + std::to_string(k) + "] N" + std::to_string(back + 1) + "\n";
        for (int j = 4; j < per_label; ++j) p += "Y" + std::to_string(j) + "\n";
    }
    p += "VC1=VC1+1\nEND 1\nG80\nM30\n";
    auto r = run(p, {"OSP204", "OSP205", "OSP209"});
    const uint64_t blocks = r.blocks.size();
    REQUIRE(blocks > 50000);
    // Every reachable block is visited; the loop is swept until the states
    // where paths join stop changing, then once more with the rules.
    CHECK(r.stats.transfers >= blocks - 1);
    CHECK(r.stats.loops == 1);
    CHECK(r.stats.loop_sweeps <= 4);
    CHECK(r.stats.transfers <= 5 * blocks);
    MESSAGE("blocks " << blocks << ", transfers " << r.stats.transfers << ", sweeps " << r.stats.loop_sweeps);
}

TEST_CASE("modal state: the cycle's words are shared between copies until one changes") {
    ActiveCycle a;
    a.code = 114;
    a.words.edit()["FA"] = Val<double>::of(650);
    ActiveCycle b = a;
    CHECK(b.words.shares(a.words));
    CHECK(b == a);
    b.words.edit()["L"] = Val<double>::of(1.5);  // b's own copy: a keeps its words
    CHECK_FALSE(b.words.shares(a.words));
    CHECK(a.words.get().size() == 1);
    CHECK(b.words.get().size() == 2);
    CHECK_FALSE(b == a);
    // Equal words held apart are equal.
    ActiveCycle c;
    c.code = 114;
    c.words.edit()["FA"] = Val<double>::of(650);
    CHECK_FALSE(c.words.shares(a.words));
    CHECK(c == a);
    // A merge of the same words keeps them shared and known.
    ModalState s, t;
    s.cycle = Val<std::optional<ActiveCycle>>::of(a);
    t.cycle = Val<std::optional<ActiveCycle>>::of(a);
    s.merge(t);
    CHECK(s.cycle.value->words.shares(a.words));
    CHECK(s.cycle.value->words_known);
    // A merge of other words keeps what both give, and no longer knows absence.
    t.cycle = Val<std::optional<ActiveCycle>>::of(b);
    s.merge(t);
    CHECK(s.cycle.value->words.get().size() == 1);
    CHECK_FALSE(s.cycle.value->words_known);
    CHECK(a.words.get().size() == 1);
    CHECK(b.words.get().size() == 2);
}
