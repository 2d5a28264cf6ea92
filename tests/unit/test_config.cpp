// osplint.toml: valid settings are read, and every kind of mistake is a
// ConfigError that names the file, the line and the key.
#include <doctest/doctest.h>

#include <filesystem>
#include <fstream>

#include <unistd.h>

#include "api/check.h"
#include "api/config.h"
#include "support/errors.h"

using namespace osplint;

namespace {

ConfigError error_of(const std::string& text) {
    try {
        parse_config(text, "shop/osplint.toml");
    } catch (const ConfigError& e) {
        return e;
    }
    FAIL("no ConfigError for:\n" << text);
    return ConfigError("", 0, "", "");
}

}  // namespace

TEST_CASE("a full configuration is read") {
    Config c = parse_config(R"([machine]
units = "inch"
plane = "G18"
distance = "G91"
[machine.travel]
z = [-300.0, 150]
x = [-500, 500]
[codes]
G115 = "OG84L"
[rules]
OSP202 = "off"
OSP111 = "warning"
[analysis]
explain-unknown = true
)",
                            "osplint.toml");
    CHECK(c.units == Units::Inch);
    CHECK(c.plane == Plane::G18);
    CHECK(c.distance == Distance::Incremental);
    REQUIRE(c.travel.count('Z'));
    CHECK(c.travel.at('Z').min == -300.0);
    CHECK(c.travel.at('Z').max == 150.0);
    CHECK(c.travel.at('X').max == 500.0);
    REQUIRE(c.catalog.find_by_code("G115"));
    CHECK(c.catalog.find_by_code("G115")->name == "OG84L");
    CHECK_FALSE(c.severity_of("OSP202", Severity::Warning, true).has_value());
    CHECK(c.severity_of("OSP111", Severity::Info, true) == Severity::Warning);
    CHECK(c.severity_of("OSP303", Severity::Info, false) == Severity::Info);  // explain-unknown
    CHECK(c.severity_of("OSP104", Severity::Error, true) == Severity::Error);
}

TEST_CASE("[analysis] may-findings: a severity or off; warning by default") {
    CHECK(Config{}.may_severity == Severity::Warning);
    CHECK(parse_config("[analysis]\nmay-findings = \"error\"\n", "osplint.toml").may_severity == Severity::Error);
    CHECK(parse_config("[analysis]\nmay-findings = \"info\"\n", "osplint.toml").may_severity == Severity::Info);
    CHECK_FALSE(parse_config("[analysis]\nmay-findings = \"off\"\n", "osplint.toml").may_severity.has_value());
    for (const char* bad : {"may-findings = \"sometimes\"", "may-findings = true", "may-finding = \"off\""}) {
        CAPTURE(bad);
        CHECK_THROWS_AS(parse_config(std::string("[analysis]\n") + bad + "\n", "osplint.toml"), ConfigError);
    }
    CHECK(dump_config(parse_config("[analysis]\nmay-findings = \"off\"\n", "osplint.toml")).find(
              "may-findings = 'off'") != std::string::npos);
}

TEST_CASE("defaults: mm, G17, G90, G114 and M204 registered") {
    Config c;
    CHECK(c.units == Units::Mm);
    CHECK(c.plane == Plane::G17);
    CHECK(c.distance == Distance::Absolute);
    REQUIRE(c.catalog.find_by_code("G114"));
    CHECK(c.catalog.find_by_code("G114")->name == "OG84L");
    REQUIRE(c.catalog.find_by_code("M204"));
    CHECK(c.catalog.find_by_code("M204")->name == "OC84L");
    std::string dump = dump_config(c);
    CHECK(dump.find("G114 = 'OG84L'") != std::string::npos);
    CHECK(dump.find("units = 'mm'") != std::string::npos);
}

TEST_CASE("configuration mistakes name the file, line and key") {
    SUBCASE("bad TOML") {
        auto e = error_of("[machine]\nunits = \"mm\"\nplane = G17\n");
        CHECK(e.file() == "shop/osplint.toml");
        CHECK(e.line() == 3);
    }
    SUBCASE("unknown top-level key") {
        auto e = error_of("[machine]\nunits = \"mm\"\n\n[rulez]\nOSP104 = \"off\"\n");
        CHECK(e.key() == "rulez");
        CHECK(e.line() == 4);
    }
    SUBCASE("unknown machine key") {
        auto e = error_of("[machine]\nunit = \"mm\"\n");
        CHECK(e.key() == "machine.unit");
        CHECK(e.line() == 2);
    }
    SUBCASE("wrong type") {
        auto e = error_of("[machine]\nunits = 25\n");
        CHECK(e.key() == "machine.units");
        CHECK(std::string(e.what()).find("expected a string") != std::string::npos);
    }
    SUBCASE("bad value") {
        auto e = error_of("[machine]\nplane = \"G20\"\n");
        CHECK(e.key() == "machine.plane");
        CHECK(e.line() == 2);
    }
    SUBCASE("travel min not below max") {
        auto e = error_of("[machine.travel]\nz = [150, -300]\n");
        CHECK(e.key() == "machine.travel.z");
    }
    SUBCASE("unknown rule ID") {
        auto e = error_of("[rules]\nOSP104 = \"off\"\nOSP999 = \"error\"\n");
        CHECK(e.key() == "rules.OSP999");
        CHECK(e.line() == 3);
    }
    SUBCASE("bad severity") {
        auto e = error_of("[rules]\nOSP104 = \"fatal\"\n");
        CHECK(e.key() == "rules.OSP104");
    }
    SUBCASE("registration of an unknown macro") {
        auto e = error_of("[codes]\nG114 = \"OXXXX\"\n");
        CHECK(e.key() == "codes.G114");
        CHECK(e.line() == 2);
    }
    SUBCASE("registration of something that is not a G or M code") {
        auto e = error_of("[codes]\nX114 = \"OG84L\"\n");
        CHECK(e.key() == "codes.X114");
    }
    SUBCASE("an empty macro name removes a registration") {
        Config c = parse_config("[codes]\nG114 = \"\"\nG113 = \"OG84L\"\n", "osplint.toml");
        CHECK(c.catalog.find_by_code("G114") == nullptr);
        REQUIRE(c.catalog.find_by_code("G113") != nullptr);
        CHECK(c.catalog.find_by_code("G113")->name == "OG84L");
    }
    SUBCASE("the [macros.gcode] table of catalog schema 1 names its new place") {
        auto e = error_of("[macros.gcode]\nG113 = \"OLAPX\"\n");
        CHECK(e.key() == "macros");
        CHECK(e.line() == 1);
        CHECK(std::string(e.what()).find("[codes]") != std::string::npos);
    }
}

TEST_CASE("codes of the control, infinite and undefined numbers, and huge keys are configuration mistakes") {
    SUBCASE("a motion, end or other built-in code registered as a macro code") {
        for (const char* code : {"G0", "G01", "G2", "G80", "G83", "G90", "M30", "M2", "M06", "M53"}) {
            auto e = error_of(std::string("[codes]\n") + code + " = \"OZAGR\"\n");
            CHECK(e.key() == std::string("codes.") + code);
            CHECK(std::string(e.what()).find("of the control, not a macro code") != std::string::npos);
        }
        auto e = error_of("[macro.OZAGR]\ncodes = [\"M30\"]\n");
        CHECK(e.key() == "macro.OZAGR.codes");
        CHECK(std::string(e.what()).find("M30 is the program end of the control") != std::string::npos);
        CHECK(parse_config("[codes]\nG115 = \"OZAGR\"\n", "x").catalog.find_by_code("G115") != nullptr);
    }
    SUBCASE("travel limits that are not finite") {
        for (const char* t : {"[-inf, inf]", "[nan, 1]", "[0, +inf]"}) {
            auto e = error_of(std::string("[machine.travel]\nz = ") + t + "\n");
            CHECK(e.key() == "machine.travel.z");
            CHECK(std::string(e.what()).find("expected finite numbers") != std::string::npos);
        }
    }
    SUBCASE("catalog numbers that are not finite") {
        auto e = error_of("[macro.OZAGR.arg.PM]\nallowed = [nan]\n");
        CHECK(e.key() == "macro.OZAGR.arg.PM.allowed");
        CHECK(std::string(e.what()).find("expected a finite number, found nan") != std::string::npos);
        e = error_of("[macro.OZAGR.arg.PM]\ndefault = inf\n");
        CHECK(std::string(e.what()).find("expected a finite number") != std::string::npos);
    }
    SUBCASE("a 1 MB key is not echoed whole") {
        const std::string key(1 << 20, 'k');
        auto e = error_of("[machine]\n" + key + " = 1\n");
        CHECK(e.key().size() > (1u << 20));
        CHECK(std::string(e.what()).size() < 2500);
        CHECK(std::string(e.what()).find("bytes)") != std::string::npos);
    }
}

TEST_CASE("a configuration path that is a directory or missing is an error") {
    const auto dir = std::filesystem::temp_directory_path() / ("osplint-config-" + std::to_string(::getpid()));
    std::filesystem::create_directories(dir);
    CHECK_THROWS_WITH_AS(load_config(dir), doctest::Contains("is a directory"), ConfigError);
    CHECK_THROWS_WITH_AS(load_config(dir / "none.toml"), doctest::Contains("no such configuration file"), ConfigError);
    std::filesystem::remove_all(dir);
}

TEST_CASE("rule names serve as IDs in [rules] and [[per-path]]; a mistyped one gets a suggestion") {
    Config c = parse_config("[rules]\nm52-on-call-line = \"warning\"\nosp202 = \"off\"\n", "osplint.toml");
    CHECK(c.severity_of("OSP104", Severity::Error, true) == Severity::Warning);
    CHECK_FALSE(c.severity_of("OSP202", Severity::Warning, true).has_value());
    auto e = error_of("[rules]\nm52-on-cal-line = \"off\"\n");
    CHECK(e.key() == "rules.m52-on-cal-line");
    CHECK(std::string(e.what()).find("did you mean 'm52-on-call-line'?") != std::string::npos);
    auto e2 = error_of("[[per-path]]\npaths = [\"probe/**\"]\nrules = { OSP14 = \"off\" }\n");
    CHECK(e2.key() == "per-path.rules.OSP14");
    CHECK(e2.line() == 3);
    CHECK(std::string(e2.what()).find("did you mean 'OSP") != std::string::npos);
}

TEST_CASE("exclude and [[per-path]] are read relative to the file's directory") {
    Config c = parse_config(R"(exclude = ["old/**", "*.BAK.MIN"]
[rules]
OSP204 = "error"
[[per-path]]
paths = ["probe/**"]
rules = { OSP204 = "off", OSP1 = "warning", m52-on-call-line = "info" }
)",
                            "shop/osplint.toml");
    CHECK(c.excluded("shop/old/P1.MIN"));
    CHECK(c.excluded("shop/old/deep/P1.MIN"));
    CHECK(c.excluded("shop/old"));
    CHECK(c.excluded("shop/a/P1.BAK.MIN"));
    CHECK_FALSE(c.excluded("shop/P1.MIN"));
    CHECK_FALSE(c.excluded("shop/older/P1.MIN"));
    CHECK_FALSE(c.excluded("other/old/P1.MIN"));  // patterns with '/' hold below the file's directory only
    CHECK(c.excluded("other/P1.BAK.MIN"));        // one without '/' is a file name anywhere
    REQUIRE(c.per_path.size() == 1);
    CHECK(c.per_path_matching("shop/P1.MIN").empty());
    auto m = c.per_path_matching("shop/probe/P2.MIN");
    REQUIRE(m.size() == 1);
    Config probe = c;
    probe.apply_per_path(m);
    CHECK_FALSE(probe.severity_of("OSP204", Severity::Warning, true).has_value());
    CHECK(probe.severity_of("OSP104", Severity::Error, true) == Severity::Info);  // its name wins over OSP1
    CHECK(probe.severity_of("OSP101", Severity::Error, true) == Severity::Warning);  // the prefix OSP1
    CHECK(probe.severity_of("OSP110", Severity::Error, true) == Severity::Warning);
    Config zero = parse_config("[rules]\nOSP0 = \"off\"\nOSP1 = \"off\"\nOSP10 = \"info\"\n", "osplint.toml");
    CHECK(zero.severity_of("OSP001", Severity::Error, true) == Severity::Error);  // by its own key only
    CHECK_FALSE(zero.severity_of("OSP002", Severity::Error, true).has_value());
    CHECK(zero.severity_of("OSP104", Severity::Error, true) == Severity::Info);  // the longer prefix wins
    CHECK_FALSE(zero.severity_of("OSP110", Severity::Error, true).has_value());
    CHECK(c.severity_of("OSP204", Severity::Warning, true) == Severity::Error);

    SUBCASE("mistakes") {
        CHECK(error_of("exclude = \"old/**\"\n").key() == "exclude");
        CHECK(error_of("exclude = [\"old/[ab\"]\n").key() == "exclude");
        CHECK(error_of("[per-path]\npaths = [\"a\"]\n").key() == "per-path");
        CHECK(error_of("[[per-path]]\nrules = { OSP204 = \"off\" }\n").key() == "per-path.paths");
        CHECK(error_of("[[per-path]]\npaths = [\"a\"]\nrule = {}\n").key() == "per-path.rule");
        auto e = error_of("[[per-path]]\npaths = [\"a\"]\nrules = { OSP204 = \"loud\" }\n");
        CHECK(e.key() == "per-path.rules.OSP204");
        CHECK(e.line() == 3);
    }
}

namespace {

struct TempTree {
    std::filesystem::path root;
    explicit TempTree(const std::string& name)
        : root(std::filesystem::temp_directory_path() / (name + "-" + std::to_string(::getpid()))) {
        std::filesystem::remove_all(root);
        std::filesystem::create_directories(root);
    }
    ~TempTree() { std::filesystem::remove_all(root); }
    std::filesystem::path write(const std::string& rel, const std::string& text) const {
        auto p = root / rel;
        std::filesystem::create_directories(p.parent_path());
        std::ofstream(p, std::ios::binary) << text;
        return p;
    }
};

}  // namespace

TEST_CASE("extend: the file inherits the one it names, and overrides it") {
    TempTree t("osplint-extend");
    t.write("shop/osplint.toml", R"(exclude = ["*.BAK.MIN"]
[machine]
units = "inch"
plane = "G18"
[rules]
OSP204 = "off"
OSP202 = "off"
[[per-path]]
paths = ["probe/**"]
rules = { OSP104 = "off" }
)");
    t.write("base/osplint.toml", "extend = \"../shop/osplint.toml\"\n[machine]\nplane = \"G19\"\n");
    auto cell = t.write("base/cell/osplint.toml",
                        "extend = \"../osplint.toml\"\nexclude = [\"old/**\"]\n[rules]\nOSP204 = \"warning\"\n");
    Config c = load_config(cell);
    CHECK(c.units == Units::Inch);  // from shop, two files up the chain
    CHECK(c.plane == Plane::G19);   // base overrides shop
    CHECK(c.severity_of("OSP204", Severity::Info, true) == Severity::Warning);  // cell overrides shop
    CHECK_FALSE(c.severity_of("OSP202", Severity::Warning, true).has_value());
    REQUIRE(c.extends.size() == 2);
    CHECK(c.extends[0] == (t.root / "base/osplint.toml").string());
    CHECK(c.extends[1].find("shop/osplint.toml") != std::string::npos);
    // Patterns stay relative to the file that names them.
    CHECK(c.excluded(t.root / "base/cell/old/P.MIN"));
    CHECK(c.excluded(t.root / "base/cell/P.BAK.MIN"));
    CHECK_FALSE(c.excluded(t.root / "base/old/P.MIN"));
    CHECK(c.per_path_matching(t.root / "shop/probe/P.MIN").size() == 1);
    CHECK(c.per_path_matching(t.root / "base/cell/probe/P.MIN").empty());
    const std::string shown = dump_config(c);
    CHECK(shown.find("# extends ") != std::string::npos);
    CHECK(shown.find("'old/**',  # " + cell.string()) != std::string::npos);
    CHECK(shown.find("[[per-path]]  # ") != std::string::npos);
}

TEST_CASE("extend: a missing file and a cycle are errors naming both files") {
    TempTree t("osplint-extend-bad");
    auto a = t.write("a/osplint.toml", "extend = \"../b/osplint.toml\"\n");
    t.write("b/osplint.toml", "[machine]\nunits = \"mm\"\nextend = 3\n");
    auto missing = t.write("m/osplint.toml", "\n\nextend = \"../shop/osplint.toml\"\n");
    try {
        load_config(missing);
        FAIL("no error for a missing file");
    } catch (const ConfigError& e) {
        CHECK(e.file() == missing.string());
        CHECK(e.line() == 3);
        CHECK(e.key() == "extend");
        CHECK(std::string(e.what()).find("shop/osplint.toml, does not exist") != std::string::npos);
    }
    auto cyc = t.write("c/osplint.toml", "extend = \"../d/osplint.toml\"\n");
    auto d = t.write("d/osplint.toml", "extend = \"../c/osplint.toml\"\n");
    try {
        load_config(cyc);
        FAIL("no error for a cycle");
    } catch (const ConfigError& e) {
        CHECK(e.file() == (t.root / "d/osplint.toml").string());
        CHECK(e.key() == "extend");
        CHECK(std::string(e.what()).find("extend each other") != std::string::npos);
        CHECK(std::string(e.what()).find("c/osplint.toml") != std::string::npos);
    }
    auto self = t.write("s/osplint.toml", "extend = \"osplint.toml\"\n");
    CHECK_THROWS_WITH_AS(load_config(self), doctest::Contains("extend each other"), ConfigError);
    (void)a;
    (void)d;
}

TEST_CASE("config: a [cycle] table patches a shipped fixed cycle, as OSP103's note says") {
    // G83's Q (the peck) must be positive in the reading taken; the finding's
    // note says which table changes that reading, and that table does.
    const std::string program = "O1\nG0 G90 X0 Y0 Z50.\nG83 X0 Y0 Z-10. R2. Q0 F100\nG80\nM30\n";
    const auto findings = [&](const Config& config) {
        std::vector<Diagnostic> out;
        for (auto& d : check_text("p.min", program, config, {}).diagnostics)
            if (d.rule == "OSP103") out.push_back(d);
        return out;
    };
    const std::vector<Diagnostic> shipped = findings(Config{});
    REQUIRE(shipped.size() == 1);
    std::string notes;
    for (const auto& n : shipped[0].notes) notes += n.message;
    const std::string table = "[cycle.G83.arg.Q] sign = \"any\"";
    CHECK(notes.find(table) != std::string::npos);
    CHECK(findings(parse_config("[cycle.G83.arg.Q]\nsign = \"any\"\n", "shop/osplint.toml")).empty());
    // The patch leaves the rest of the cycle as shipped.
    const Config patched = parse_config("[cycle.g83.arg.Q]\nsign = \"any\"\n", "shop/osplint.toml");
    const CycleSpec* g83 = patched.catalog.find_cycle(83);
    REQUIRE(g83);
    CHECK(g83->arg("Q")->sign == ArgSign::Any);
    CHECK(g83->arg("Z") != nullptr);
    CHECK(g83->arg("J")->sign == ArgSign::Positive);
    CHECK(Config{}.catalog.find_cycle(83)->arg("Q")->sign == ArgSign::Positive);
    // Bad entries stop the run with the key, and leave nothing half-applied.
    CHECK(error_of("[cycle.X83]\nnotes = []\n").key() == "cycle.X83");
    CHECK(error_of("[cycle.G83.arg.Q]\nsign = \"sometimes\"\n").key() == "cycle.G83.arg.Q.sign");
    CHECK(error_of("[cycle.G83]\nbogus = 1\n").key() == "cycle.G83.bogus");
}
