// User subprograms across files: what a subprogram in a file beside the
// checked one leaves behind (G90/G91, plane, units, a fixed cycle, a MODIN,
// common variables; whether it returns) is applied at its CALL.
#include <doctest/doctest.h>

#include <unistd.h>

#include <filesystem>
#include <fstream>
#include <string>

#include "api/check.h"
#include "engine/summaries.h"
#include "rules/registry.h"

using namespace osplint;

namespace {

struct Folder {
    std::filesystem::path dir;
    Folder() {
        dir = std::filesystem::temp_directory_path() / ("osplint-summaries-" + std::to_string(::getpid()));
        std::filesystem::remove_all(dir);
        std::filesystem::create_directories(dir);
    }
    ~Folder() { std::filesystem::remove_all(dir); }
    std::string write(const std::string& name, const std::string& text) const {
        std::ofstream(dir / name, std::ios::binary) << text;
        return (dir / name).string();
    }
};

const char* kMain =
    "O1000\n"
    "G90 G17 G21\n"
    "G0 X0 Y0 Z50.\n"
    "CALL O100\n"
    "CALL OKYLX PX=10 PY=0 PR=3 PZ=-5 PI=60 PD=21 PFA=100\n"
    "M30\n";

// The findings of `rule` in the main program, checked with summaries.
std::vector<Diagnostic> findings(const Folder& f, const std::string& main_text, SubprogramSummaries& summaries,
                                 const std::string& rule = "OSP109") {
    const std::string path = f.write("MAIN.MIN", main_text);
    Config config;
    AnalysisOptions options;
    options.summaries = &summaries;
    FileResult r = check_file(path, config, options);
    CHECK(r.io_error.empty());
    std::vector<Diagnostic> out;
    for (auto& d : r.diagnostics)
        if (d.rule == rule) out.push_back(std::move(d));
    return out;
}

// Whether some note of `d` contains `text`.
bool noted(const Diagnostic& d, const std::string& text) {
    for (const auto& n : d.notes)
        if (n.message.find(text) != std::string::npos) return true;
    return false;
}

}  // namespace

TEST_CASE("subprogram summaries: the modes a subprogram leaves apply at its CALL") {
    Folder f;
    SubprogramDirectories dirs;
    SubprogramSummaries summaries(builtin_rules(), dirs);

    SUBCASE("a subprogram that leaves G91 makes the next OKYLX a finding, with the subprogram as a note") {
        f.write("SUB.SSB", "O100\nG91 G0 X10.\nRTS\n");
        auto ds = findings(f, kMain, summaries);
        REQUIRE(ds.size() == 1);
        CHECK(ds[0].range.start.line == 5);
        bool noted = false;
        for (const auto& n : ds[0].notes)
            if (n.message.find("G91 comes from the subprogram O100 (SUB.SSB, line 1)") != std::string::npos) noted = true;
        CHECK(noted);
        // Without summaries the CALL is taken to keep G90: no finding (today's reading for unknown subprograms).
        Config config;
        FileResult plain = check_file((f.dir / "MAIN.MIN").string(), config, AnalysisOptions{});
        for (const auto& d : plain.diagnostics) CHECK(d.rule != "OSP109");
    }
    SUBCASE("one that restores G90 before RTS leaves nothing behind") {
        f.write("SUB.SSB", "O100\nG91 G0 X10.\nG90\nRTS\n");
        CHECK(findings(f, kMain, summaries).empty());
    }
    SUBCASE("G91 on one path only: not known after the call, so no finding rests on it") {
        f.write("SUB.SSB", "O100\nIF [VC1 EQ 1] NSKIP\nG91\nNSKIP G0 X10.\nRTS\n");
        CHECK(findings(f, kMain, summaries).empty());
        const SubprogramSummary* s = summaries.find(Config{}, (f.dir / "MAIN.MIN").string(), "O100");
        REQUIRE(s);
        CHECK(s->distance.kind == ModeEffect<Distance>::Kind::Unknown);
        CHECK(s->plane.kind == ModeEffect<Plane>::Kind::Kept);
    }
    SUBCASE("one that does not touch G90/G91 keeps the caller's G91") {
        f.write("SUB.SSB", "O100\nG0 X10.\nRTS\n");
        std::string main = kMain;
        main.replace(main.find("G90 G17"), 3, "G91");
        auto ds = findings(f, main, summaries);
        REQUIRE(ds.size() == 1);
        for (const auto& n : ds[0].notes) CHECK(n.message.find("comes from the subprogram") == std::string::npos);
    }
    SUBCASE("inch units and the plane: OSP110 after a subprogram that leaves G20") {
        f.write("SUB.SSB", "O100\nG20 G18\nRTS\n");
        auto ds = findings(f, kMain, summaries, "OSP110");
        REQUIRE(ds.size() == 1);
        const SubprogramSummary* s = summaries.find(Config{}, (f.dir / "MAIN.MIN").string(), "O100");
        REQUIRE(s);
        CHECK(s->describe() == "leaves G18 and G20 (inch) in effect");
        bool noted = false;
        for (const auto& n : ds[0].notes)
            if (n.message.find("G20 comes from the subprogram O100 (SUB.SSB, line 1)") != std::string::npos) noted = true;
        CHECK(noted);
    }
    SUBCASE("a subprogram that ends in G60 makes NCYL ineffective (OSP201), with the subprogram as a note") {
        f.write("SUB.SSB", "O100\nG60 X10. Y10.\nRTS\n");
        const std::string main = "O1000\nG90 G17 G21\nCALL OZAGR PR=5 PZ=-20 PI=12 PL=3 PD=2\nG0 X0 Y0 Z50.\n"
                                 "CALL O100\nNCYL X20. Y20.\nM30\n";
        auto ds = findings(f, main, summaries, "OSP201");
        REQUIRE(ds.size() == 1);
        CHECK(ds[0].range.start.line == 6);
        bool noted = false;
        for (const auto& n : ds[0].notes)
            if (n.message.find("G60 comes from the subprogram O100") != std::string::npos) noted = true;
        CHECK(noted);
        // A G0 in the subprogram after the G60: nothing to report.
        f.write("SUB.SSB", "O100\nG60 X10. Y10.\nG0 Z50.\nRTS\n");
        CHECK(findings(f, main, summaries, "OSP201").empty());
    }
    SUBCASE("a program of the checked file itself is not looked for beside it") {
        f.write("SUB.SSB", "O100\nG91\nRTS\n");
        std::string main = std::string(kMain) + "O100\nG0 X1.\nRTS\n";
        CHECK(findings(f, main, summaries).empty());
    }
    SUBCASE("a subprogram of the checked file itself is summarised from its own text") {
        const std::string main = std::string(kMain) + "O100\nG91 G0 X10.\nRTS\n";
        auto ds = findings(f, main, summaries);
        REQUIRE(ds.size() == 1);
        CHECK(ds[0].range.start.line == 5);
        CHECK(noted(ds[0], "G91 comes from the subprogram O100 (MAIN.MIN, line 7)"));
        // An edit of the subprogram is a new summary; the file's name does not change.
        const uint64_t walks = summaries.walks();
        CHECK(findings(f, std::string(kMain) + "O100\nG91 G0 X10.\nG90\nRTS\n", summaries).empty());
        CHECK(summaries.walks() == walks + 2);
        // The same text again: the summary is kept.
        CHECK(findings(f, main, summaries).size() == 1);
        CHECK(summaries.walks() == walks + 2);
        // A program that calls itself is not summarised (its CALL keeps the modes).
        const std::string self = "O1000\nG90 G17 G21\nG0 X0 Y0 Z50.\nIF [VC1 EQ 1] NE\nVC1=1\nCALL O1000\n"
                                 "NE CALL OKYLX PX=10 PY=0 PR=3 PZ=-5 PI=60 PD=21 PFA=100\nG91\nM30\n";
        CHECK(findings(f, self, summaries).empty());
    }
    SUBCASE("a summary is made once per file version") {
        f.write("SUB.SSB", "O100\nG91\nRTS\n");
        const std::string main = f.write("MAIN.MIN", kMain);
        const Config config;
        const SubprogramSummary* a = summaries.find(config, main, "O100");
        REQUIRE(a);
        CHECK(summaries.walks() == 2);
        CHECK(summaries.find(config, main, "O100") == a);
        CHECK(summaries.walks() == 2);
        CHECK(summaries.find(config, main, "O999") == nullptr);  // no file defines it
        CHECK(summaries.walks() == 2);
        // A subprogram with no path to its end has no summary.
        f.write("LOOP.SSB", "O200\nNA G0 X1.\nGOTO NA\n");
        CHECK(summaries.find(config, main, "O200") == nullptr);
    }
}

TEST_CASE("subprogram summaries: a cycle or MODIN left open, common variables, RTS") {
    Folder f;
    SubprogramDirectories dirs;
    SubprogramSummaries summaries(builtin_rules(), dirs);
    const std::string call_only = "O1000\nG90 G17 G21 G0 X0 Y0 Z50.\nS800 M3\nCALL O100\nM30\n";
    auto summary = [&] { return summaries.find(Config{}, (f.dir / "MAIN.MIN").string(), "O100"); };

    SUBCASE("a MODIN the subprogram leaves open is never closed in the caller (OSP203, at the CALL)") {
        f.write("SUB.SSB", "O100\nMODIN OG87N PR=5 PZ=-25 PL=4 PI=2 PJ=6 PF=100\nX20 Y20\nRTS\n");
        auto ds = findings(f, call_only, summaries, "OSP203");
        REQUIRE(ds.size() == 1);
        CHECK(ds[0].range.start.line == 4);
        CHECK(ds[0].message.find("MODIN OG87N, which the subprogram O100 opens and leaves open, is never closed") !=
              std::string::npos);
        REQUIRE(summary());
        CHECK(summary()->describe() == "leaves MODIN OG87N in effect");
        // The caller closes it: nothing to report.
        std::string closed = call_only;
        closed.replace(closed.find("M30"), 3, "MODOUT\nM30");
        CHECK(findings(f, closed, summaries, "OSP203").empty());
    }
    SUBCASE("a fixed cycle the subprogram leaves modal is still modal at the caller's end (OSP204, at the CALL)") {
        f.write("SUB.SSB", "O100\nG98 G81 X10 Y10 Z-5 R3 F150\nRTS\n");
        auto ds = findings(f, call_only, summaries, "OSP204");
        REQUIRE(ds.size() == 1);
        CHECK(ds[0].range.start.line == 4);
        CHECK(ds[0].message.find("G81 (left modal by the subprogram O100) is still modal") != std::string::npos);
        std::string cancelled = call_only;
        cancelled.replace(cancelled.find("M30"), 3, "G80\nM30");
        CHECK(findings(f, cancelled, summaries, "OSP204").empty());
    }
    SUBCASE("a cycle cancelled on some paths of the subprogram only: unknown after the call, nothing reported") {
        f.write("SUB.SSB", "O100\nIF [VC1 EQ 1] NS\nG80\nNS RTS\n");
        const std::string main = "O1000\nG90 G17 G21 G0 X0 Y0 Z50.\nS800 M3\nG98 G81 X10 Y10 Z-5 R3 F150\n"
                                 "CALL O100\nM30\n";
        CHECK(findings(f, main, summaries, "OSP204").empty());
        REQUIRE(summary());
        CHECK(summary()->uncancelled.kind == ModeEffect<std::optional<OpenCycle>>::Kind::Unknown);
        // Without the IF the G80 cancels on every path: known, and the caller's end is clean as well.
        f.write("SUB.SSB", "O100\nG80\nRTS\n");
        CHECK(findings(f, main, summaries, "OSP204").empty());
    }
    SUBCASE("the common variables it writes, and a macro it runs that overwrites VC120-VC128 (OSP202)") {
        f.write("SUB.SSB", "O100\nVC130=5\nVC131=VC[VC1]\nCALL OM100 PR=5 PZ=-20 PI=12 PF=100 PFA=1000\nRTS\n");
        REQUIRE(summary());
        const SubprogramSummary& s = *summary();
        CHECK(s.writes.size() == 2);
        CHECK(s.writes.at(130) == std::optional<double>(5.0));
        CHECK_FALSE(s.writes.at(131).has_value());
        CHECK_FALSE(s.writes_any);
        CHECK(s.clobbers_reserved == "OM100");
        CHECK(s.returns);
        const std::string main = "O1000\nG90 G17 G21 G0 X0 Y0 Z50.\nVC121=5\nCALL O100\nG0 X=VC121\nM30\n";
        auto ds = findings(f, main, summaries, "OSP202");
        REQUIRE(ds.size() == 2);  // the write and the read of VC121
        CHECK(noted(ds[0], "O100 runs OM100, which overwrites VC121 when it runs"));
        // The caller's other common variables keep their values across the call.
        ModalState caller;
        caller.vars["VC130"] = 1;
        caller.vars["VC132"] = 2;
        caller.vars["VC121"] = 3;
        apply_summary(s, 4, {}, caller);
        CHECK(caller.vars.at("VC130") == 5);
        CHECK(caller.vars.at("VC132") == 2);
        CHECK(caller.vars.count("VC121") == 0);
        // A subprogram that calls another one may write any common variable.
        f.write("SUB.SSB", "O100\nCALL O200\nRTS\nO200\nVC140=1\nRTS\n");
        REQUIRE(summary());
        CHECK(summary()->writes_any);
        apply_summary(*summary(), 4, {}, caller);
        CHECK(caller.vars.count("VC132") == 0);
    }
    SUBCASE("a WHILE loop inside the subprogram: G91 in its body is unknown after it, G90 after END is set") {
        f.write("SUB.SSB", "O100\nVC1=0\nWHILE [VC1 LT 2] DO 1\nG91 G0 X10.\nVC1=VC1+1\nEND 1\nRTS\n");
        REQUIRE(summary());
        CHECK(summary()->distance.kind == ModeEffect<Distance>::Kind::Unknown);
        CHECK(findings(f, kMain, summaries).empty());
        f.write("SUB.SSB", "O100\nVC1=0\nWHILE [VC1 LT 2] DO 1\nG91 G0 X10.\nVC1=VC1+1\nEND 1\nG91\nRTS\n");
        REQUIRE(summary());
        CHECK(summary()->distance.kind == ModeEffect<Distance>::Kind::Set);
        CHECK(findings(f, kMain, summaries).size() == 1);  // OSP109: OKYLX under the G91 the subprogram leaves
    }
    SUBCASE("a subprogram with no RTS never returns: OSP004 at the CALL") {
        f.write("SUB.SSB", "O100\nG0 X1.\nM30\n");
        auto ds = findings(f, call_only, summaries, "OSP004");
        REQUIRE(ds.size() == 1);
        CHECK(ds[0].range.start.line == 4);
        CHECK(ds[0].message.find("O100 (SUB.SSB, line 1) has no RTS on any path") != std::string::npos);
        f.write("SUB.SSB", "O100\nIF [VC1 EQ 1] NE\nRTS\nNE M30\n");
        CHECK(findings(f, call_only, summaries, "OSP004").empty());  // RTS on one path: it may return
    }
}

TEST_CASE("subprogram summaries: each mode is set, kept or unknown") {
    ModalState end0 = summary_probe(0), end1 = summary_probe(1);
    end0.distance = end1.distance = Val<Distance>::of(Distance::Incremental);  // set on every path
    end1.units = Val<Units>{};                                                 // unknown in one walk
    end0.motion = end1.motion = Val<int>::of(60);                              // G60 on every path
    const SubprogramSummary s = summarize(&end0, &end1);
    CHECK(s.distance.kind == ModeEffect<Distance>::Kind::Set);
    CHECK(s.distance.value == Distance::Incremental);
    CHECK(s.plane.kind == ModeEffect<Plane>::Kind::Kept);
    CHECK(s.units.kind == ModeEffect<Units>::Kind::Unknown);
    CHECK(s.motion.kind == ModeEffect<int>::Kind::Set);
    CHECK(s.describe() == "leaves G91 and G60 in effect; may change the units");

    ModalState caller;
    caller.distance = Val<Distance>::of(Distance::Absolute);
    caller.plane = Val<Plane>::of(Plane::G19);
    caller.units = Val<Units>::of(Units::Mm);
    apply_summary(s, 7, {}, caller);
    CHECK(caller.distance.is(Distance::Incremental));
    CHECK(caller.plane.is(Plane::G19));
    CHECK_FALSE(caller.units.known);
    CHECK(caller.motion.is(60));
    CHECK(caller.modes_from == &s);
    // No path to the end: nothing is known after the call.
    const SubprogramSummary none = summarize(nullptr, nullptr);
    CHECK(none.distance.kind == ModeEffect<Distance>::Kind::Unknown);
}
