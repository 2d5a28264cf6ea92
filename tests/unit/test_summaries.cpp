// User subprograms across files: what a subprogram in a file beside the
// checked one leaves behind (G90/G91, plane, units) is applied at its CALL.
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
    apply_summary(s, caller);
    CHECK(caller.distance.is(Distance::Incremental));
    CHECK(caller.plane.is(Plane::G19));
    CHECK_FALSE(caller.units.known);
    CHECK(caller.motion.is(60));
    CHECK(caller.modes_from == &s);
    // No path to the end: nothing is known after the call.
    const SubprogramSummary none = summarize(nullptr, nullptr);
    CHECK(none.distance.kind == ModeEffect<Distance>::Kind::Unknown);
}
