// The public library interfaces as a program that links osplint sees them:
// include/osplint/osplint.h (C++) and include/osplint/osplint_c.h (C), on the
// bundled examples. Only the public headers are included here.
#include <doctest/doctest.h>

#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

#include "osplint/osplint.h"
#include "osplint/osplint_c.h"

namespace fs = std::filesystem;

namespace {

const fs::path kSource(OSPLINT_SOURCE_DIR);

std::string slurp(const fs::path& p) {
    std::ifstream in(p, std::ios::binary);
    std::ostringstream ss;
    ss << in.rdbuf();
    return ss.str();
}

// The rules of a result, in order.
std::vector<std::string> rules_of(const osplint::FileResult& r) {
    std::vector<std::string> v;
    for (const auto& d : r.diagnostics) v.push_back(d.rule);
    return v;
}

}  // namespace

TEST_CASE("library: a buffer and a file with the default configuration") {
    const fs::path file = kSource / "examples" / "mistakes" / "M52CALL.MIN";
    const osplint::Configuration config;
    osplint::FileResult r = osplint::check_text("M52CALL.MIN", slurp(file), config);
    CHECK(r.path == "M52CALL.MIN");
    CHECK(r.io_error.empty());
    REQUIRE(rules_of(r) == std::vector<std::string>{"OSP104"});
    const osplint::Diagnostic& d = r.diagnostics[0];
    CHECK(d.severity == osplint::Severity::Error);
    CHECK(d.name == "m52-on-call-line");
    CHECK(d.range.start.line == 13);
    CHECK(d.range.start.byte_col == 57);
    REQUIRE(d.fixes.size() == 1);
    CHECK(d.fixes[0].title == "Replace M52 by PM=52");
    CHECK(!d.fingerprint.empty());

    osplint::FileResult from_disk = osplint::check_file(file.string(), config);
    CHECK(rules_of(from_disk) == rules_of(r));
    CHECK(from_disk.diagnostics[0].message == d.message);
}

TEST_CASE("library: [[per-path]] tables apply to the paths they match") {
    const std::string text = slurp(kSource / "examples" / "mistakes" / "M52CALL.MIN");
    const auto config = osplint::Configuration::parse(
        "[[per-path]]\npaths = [\"probe/**\"]\nrules = { m52-on-call-line = \"info\" }\n", "shop/osplint.toml");
    osplint::FileResult probe = osplint::check_text("shop/probe/M52CALL.MIN", text, config);
    REQUIRE(rules_of(probe) == std::vector<std::string>{"OSP104"});
    CHECK(probe.diagnostics[0].severity == osplint::Severity::Info);
    osplint::FileResult other = osplint::check_text("shop/M52CALL.MIN", text, config);
    REQUIRE(rules_of(other) == std::vector<std::string>{"OSP104"});
    CHECK(other.diagnostics[0].severity == osplint::Severity::Error);
}

TEST_CASE("library: configuration errors are thrown, a missing osplint.toml is not an error") {
    // A fresh directory of the temporary directory: no osplint.toml there or above.
    const fs::path dir = fs::temp_directory_path() / "osplint-library-test";
    fs::create_directories(dir);
    CHECK_FALSE(osplint::Configuration::find(dir.string()).has_value());
    CHECK_THROWS_AS(osplint::Configuration::load((dir / "osplint.toml").string()), osplint::ConfigurationError);
    try {
        osplint::Configuration::load((dir / "osplint.toml").string());
    } catch (const osplint::ConfigurationError& e) {
        CHECK(std::string(e.what()).find("osplint.toml") != std::string::npos);
    }
    CHECK_THROWS_AS(osplint::Configuration::parse("[machine]\nunits = \"furlong\"\n", "shop.toml"),
                    osplint::ConfigurationError);
    fs::remove_all(dir);

    // The examples' osplint.toml is found from a subdirectory and sets the Z travel.
    auto found = osplint::Configuration::find((kSource / "examples" / "mistakes").string());
    REQUIRE(found.has_value());
    CHECK(fs::path(*found) == kSource / "examples" / "osplint.toml");
    const osplint::Configuration shop = osplint::Configuration::load(*found);
    CHECK(shop.dump().find("-300") != std::string::npos);
    const fs::path ztravel = kSource / "examples" / "mistakes" / "ZTRAVEL.MIN";
    CHECK(rules_of(osplint::check_file(ztravel.string(), shop)) == std::vector<std::string>{"OSP301"});
    CHECK(rules_of(osplint::check_file(ztravel.string(), osplint::Configuration())).empty());
}

TEST_CASE("library: options, unreadable files and the streaming sink") {
    const fs::path unksub = kSource / "examples" / "mistakes" / "UNKSUB.MIN";
    const osplint::Configuration config;
    CHECK(rules_of(osplint::check_file(unksub.string(), config)) == std::vector<std::string>{"OSP005"});
    osplint::CheckOptions known;
    known.known_programs = {"OCLMP"};
    CHECK(osplint::check_file(unksub.string(), config, known).diagnostics.empty());
    osplint::CheckOptions other;
    other.only_rules = {"OSP104"};
    CHECK(osplint::check_file(unksub.string(), config, other).diagnostics.empty());

    CHECK(osplint::check_file("/nonexistent/NOPE.MIN", config).io_error == "no such file");

    struct Counter : osplint::DiagnosticSink {
        std::vector<std::string> events;
        void begin_file(const std::string& path) override { events.push_back("begin " + path); }
        void diagnostic(osplint::Diagnostic&& d) override { events.push_back(d.rule); }
        void end_file(const std::string&, const std::string& io_error) override { events.push_back("end" + io_error); }
    } sink;
    osplint::check_file(unksub.string(), config, {}, sink);
    CHECK(sink.events == std::vector<std::string>{"begin " + unksub.string(), "OSP005", "end"});
    CHECK(osplint::version() == OSPLINT_VERSION);
}

TEST_CASE("C library: configurations, checks, results and errors") {
    char* error = nullptr;
    osplint_config* config = nullptr;
    REQUIRE(osplint_config_new(&config, &error) == OSPLINT_STATUS_OK);
    CHECK(error == nullptr);
    REQUIRE(config != nullptr);

    const std::string text = slurp(kSource / "examples" / "mistakes" / "M52CALL.MIN");
    osplint_result* result = nullptr;
    REQUIRE(osplint_check_text("M52CALL.MIN", text.data(), text.size(), config, nullptr, &result, &error) ==
            OSPLINT_STATUS_OK);
    CHECK(std::string(osplint_result_path(result)) == "M52CALL.MIN");
    REQUIRE(osplint_result_count(result) == 1);
    const osplint_diagnostic* d = osplint_result_diagnostic(result, 0);
    REQUIRE(d != nullptr);
    CHECK(std::string(d->rule) == "OSP104");
    CHECK(std::string(d->name) == "m52-on-call-line");
    CHECK(d->severity == OSPLINT_SEVERITY_ERROR);
    CHECK(std::string(osplint_severity_name(d->severity)) == "error");
    CHECK(d->line == 13);
    CHECK(d->column == 58);
    CHECK(d->end_column == 61);
    CHECK(text.substr(d->byte_begin, d->byte_end - d->byte_begin) == "M52");
    CHECK(std::string(d->fix_title) == "Replace M52 by PM=52");
    CHECK(d->fix_safe == 1);
    CHECK(std::string(d->line_text).find("CALL OZAGR PX=-70.") == 0);
    REQUIRE(d->note_count == 1);
    CHECK(std::string(osplint_diagnostic_note(result, 0, 0)).find("M52 commanded") != std::string::npos);
    CHECK(osplint_diagnostic_note(result, 0, 1) == nullptr);
    CHECK(osplint_result_diagnostic(result, 1) == nullptr);
    CHECK(osplint_result_count_severity(result, OSPLINT_SEVERITY_ERROR) == 1);
    CHECK(osplint_result_count_severity(result, OSPLINT_SEVERITY_WARNING) == 0);
    osplint_result_free(result);

    // Options: a known program, a rule selected by ID or by name, an unknown rule.
    const std::string unksub = (kSource / "examples" / "mistakes" / "UNKSUB.MIN").string();
    osplint_options* options = nullptr;
    REQUIRE(osplint_options_new(&options, &error) == OSPLINT_STATUS_OK);
    REQUIRE(osplint_check_file(unksub.c_str(), config, options, &result, &error) == OSPLINT_STATUS_OK);
    CHECK(osplint_result_count(result) == 1);
    osplint_result_free(result);
    REQUIRE(osplint_options_add_known_program(options, "OCLMP", &error) == OSPLINT_STATUS_OK);
    REQUIRE(osplint_check_file(unksub.c_str(), config, options, &result, &error) == OSPLINT_STATUS_OK);
    CHECK(osplint_result_count(result) == 0);
    osplint_result_free(result);
    CHECK(osplint_options_select_rule(options, "m52-on-call-line", &error) == OSPLINT_STATUS_OK);
    CHECK(osplint_options_select_rule(options, "OSP999", &error) == OSPLINT_STATUS_INVALID_ARGUMENT);
    REQUIRE(error != nullptr);
    CHECK(std::string(error) == "unknown rule: OSP999");
    osplint_string_free(error);
    error = nullptr;
    osplint_options_free(options);

    // A file that cannot be read: an error and no result (the out handle is reset).
    osplint_result* held = nullptr;
    REQUIRE(osplint_check_text("A.MIN", "O1\nM30\n", 7, config, nullptr, &held, &error) == OSPLINT_STATUS_OK);
    result = held;
    CHECK(osplint_check_file("/nonexistent/NOPE.MIN", config, nullptr, &result, &error) == OSPLINT_STATUS_IO_ERROR);
    CHECK(result == nullptr);
    osplint_result_free(held);
    REQUIRE(error != nullptr);
    CHECK(std::string(error) == "/nonexistent/NOPE.MIN: no such file");
    osplint_string_free(error);
    error = nullptr;

    // NULL arguments are refused, not dereferenced.
    CHECK(osplint_check_file(nullptr, config, nullptr, &result, nullptr) == OSPLINT_STATUS_INVALID_ARGUMENT);
    CHECK(osplint_check_text("A.MIN", "O1\n", 3, nullptr, nullptr, &result, nullptr) ==
          OSPLINT_STATUS_INVALID_ARGUMENT);
    CHECK(osplint_result_count(nullptr) == 0);
    osplint_config_free(config);
    osplint_config_free(nullptr);

    // Configurations: a missing file, invalid text, the nearest osplint.toml.
    CHECK(osplint_config_load("/nonexistent/osplint.toml", &config, &error) == OSPLINT_STATUS_CONFIG_ERROR);
    CHECK(config == nullptr);
    REQUIRE(error != nullptr);
    CHECK(std::string(error).find("/nonexistent/osplint.toml") != std::string::npos);
    osplint_string_free(error);
    const std::string bad = "[machine]\nunits = \"furlong\"\n";
    CHECK(osplint_config_parse(bad.data(), bad.size(), "shop.toml", &config, &error) == OSPLINT_STATUS_CONFIG_ERROR);
    REQUIRE(error != nullptr);
    CHECK(std::string(error).find("shop.toml") != std::string::npos);
    osplint_string_free(error);

    char* path = nullptr;
    REQUIRE(osplint_config_find((kSource / "examples" / "mistakes").c_str(), &path, &error) == OSPLINT_STATUS_OK);
    REQUIRE(path != nullptr);
    CHECK(fs::path(path) == kSource / "examples" / "osplint.toml");
    REQUIRE(osplint_config_load(path, &config, &error) == OSPLINT_STATUS_OK);
    osplint_string_free(path);
    char* toml = nullptr;
    REQUIRE(osplint_config_dump(config, &toml, &error) == OSPLINT_STATUS_OK);
    CHECK(std::string(toml).find("-300") != std::string::npos);
    osplint_string_free(toml);
    const std::string ztravel = (kSource / "examples" / "mistakes" / "ZTRAVEL.MIN").string();
    REQUIRE(osplint_check_file(ztravel.c_str(), config, nullptr, &result, &error) == OSPLINT_STATUS_OK);
    REQUIRE(osplint_result_count(result) == 1);
    CHECK(std::string(osplint_result_diagnostic(result, 0)->rule) == "OSP301");
    osplint_result_free(result);
    osplint_config_free(config);

    CHECK(std::string(osplint_version()) == OSPLINT_VERSION);
}
