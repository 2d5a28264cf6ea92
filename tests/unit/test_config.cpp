// osplint.toml: valid settings are read, and every kind of mistake is a
// ConfigError that names the file, the line and the key.
#include <doctest/doctest.h>

#include <filesystem>
#include <fstream>

#include <unistd.h>

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
[macros.gcode]
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
        auto e = error_of("[macros.gcode]\nG114 = \"OXXXX\"\n");
        CHECK(e.key() == "macros.gcode.G114");
        CHECK(e.line() == 2);
    }
    SUBCASE("registration of something that is not a G or M code") {
        auto e = error_of("[macros.gcode]\nX114 = \"OG84L\"\n");
        CHECK(e.key() == "macros.gcode.X114");
    }
}

TEST_CASE("codes of the control, infinite and undefined numbers, and huge keys are configuration mistakes") {
    SUBCASE("a motion, end or other built-in code registered as a macro code") {
        for (const char* code : {"G0", "G01", "G2", "G80", "G83", "G90", "M30", "M2", "M06", "M53"}) {
            auto e = error_of(std::string("[macros.gcode]\n") + code + " = \"OZAGR\"\n");
            CHECK(e.key() == std::string("macros.gcode.") + code);
            CHECK(std::string(e.what()).find("of the control, not a macro code") != std::string::npos);
        }
        auto e = error_of("[macro.OZAGR]\ncodes = [\"M30\"]\n");
        CHECK(e.key() == "macro.OZAGR.codes");
        CHECK(std::string(e.what()).find("M30 is the program end of the control") != std::string::npos);
        CHECK(parse_config("[macros.gcode]\nG115 = \"OZAGR\"\n", "x").catalog.find_by_code("G115") != nullptr);
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
