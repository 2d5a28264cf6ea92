// The corpus of realistic programs (tests/programs/) parses without a syntax
// error; every error case (tests/programs/errors/) yields OSP001 exactly where
// its `(expect-next: OSP001 col N)` says, and nothing else at syntax level.
#include <doctest/doctest.h>

#include <algorithm>
#include <filesystem>
#include <set>

#include "expectations.h"

namespace fs = std::filesystem;
using namespace osplint;
using namespace osplint::testing;

namespace {

std::vector<fs::path> files_in(const fs::path& dir, bool recursive) {
    std::vector<fs::path> out;
    if (!fs::exists(dir)) return out;
    auto add = [&](const fs::directory_entry& e) {
        std::string ext = e.path().extension().string();
        for (auto& c : ext) c = static_cast<char>(std::toupper(static_cast<unsigned char>(c)));
        if (e.is_regular_file() && (ext == ".MIN" || ext == ".SSB" || ext == ".SUB" || ext == ".LIB" ||
                                    ext == ".NC" || ext == ".SDF"))
            out.push_back(e.path());
    };
    if (recursive)
        for (const auto& e : fs::recursive_directory_iterator(dir)) add(e);
    else
        for (const auto& e : fs::directory_iterator(dir)) add(e);
    std::sort(out.begin(), out.end());
    return out;
}

}  // namespace

TEST_CASE("corpus programs parse without syntax errors") {
    fs::path root = fs::path(OSPLINT_SOURCE_DIR) / "tests" / "programs";
    std::vector<fs::path> files = files_in(root, false);
    auto special = files_in(root / "special", true);
    files.insert(files.end(), special.begin(), special.end());
    CHECK(files.size() >= 40);
    AnalysisOptions options;
    options.only_rules = {"OSP001"};
    for (const auto& f : files) {
        CAPTURE(f.string());
        FileResult r = check_text(f.string(), read_file(f), Config{}, options);
        for (const auto& d : r.diagnostics)
            FAIL_CHECK("line " << d.range.start.line << ":" << d.range.start.cp_col + 1 << ": " << d.message);
    }
}

TEST_CASE("syntax error cases report OSP001 at the expected line and column") {
    fs::path root = fs::path(OSPLINT_SOURCE_DIR) / "tests" / "programs" / "errors";
    auto files = files_in(root, true);
    CHECK(files.size() >= 12);
    AnalysisOptions options;
    options.only_rules = {"OSP001"};
    for (const auto& f : files) {
        CAPTURE(f.string());
        std::string text = read_file(f);
        auto expected = parse_expectations(text);
        CHECK_MESSAGE(!expected.empty(), "error case without expectations");
        FileResult r = check_text(f.string(), text, Config{}, options);
        // One expectation per error line: further OSP001 findings on the same
        // line (the parser may report a second problem there) are tolerated.
        std::vector<Diagnostic> firsts;
        std::set<uint32_t> seen;
        for (const auto& d : r.diagnostics)
            if (seen.insert(d.range.start.line).second) firsts.push_back(d);
        for (const auto& p : compare(expected, firsts, {})) FAIL_CHECK(p);
    }
}
