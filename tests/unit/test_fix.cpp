// Fixes: choosing those applied together, composing rounds, applying them,
// and the unified diff of them.
#include <doctest/doctest.h>

#include <initializer_list>
#include <random>
#include <string>
#include <vector>

#include "api/fix.h"
#include "output/diff.h"

using namespace osplint;

namespace {

std::string applied(std::string_view text, const std::vector<Edit>& edits) {
    MemorySource src(text);
    std::string out, error;
    REQUIRE(apply_edits(src, edits, [&](std::string_view p) { out += p; return true; }, error));
    return out;
}

std::string diff_of(std::string_view text, const std::vector<Edit>& edits, unsigned context = 3) {
    MemorySource src(text);
    std::string out, error;
    REQUIRE(write_unified_diff(src, edits, "P.MIN", [&](std::string_view p) { out += p; return true; }, error,
                               nullptr, context));
    return out;
}

// Sorted, non-overlapping random edits of a text of `size` bytes.
std::vector<Edit> random_edits(std::mt19937& rng, size_t size) {
    std::vector<Edit> edits;
    uint32_t pos = 0;
    const char* pieces[] = {"", "X", "\n", "ab\n", "PM=52", "\r\n"};
    while (true) {
        pos += static_cast<uint32_t>(rng() % 12);
        if (pos > size) break;
        const uint32_t len = std::min<uint32_t>(static_cast<uint32_t>(rng() % 4), static_cast<uint32_t>(size - pos));
        std::string text = pieces[rng() % 6];
        if (len == 0 && text.empty()) text = "Y";
        edits.push_back({pos, pos + len, text});
        pos += len + 1;  // a gap: insertions at one place would overlap
    }
    return edits;
}

Diagnostic with_fix(std::initializer_list<Edit> edits, bool safe = true) {
    Diagnostic d;
    d.rule = "OSP104";
    Fix f;
    f.title = "fix";
    f.safe = safe;
    for (const auto& e : edits) {
        TextEdit t;
        t.range.bytes = {e.begin, e.end};
        t.replacement = e.text;
        f.edits.push_back(t);
    }
    d.fixes.push_back(f);
    return d;
}

}  // namespace

TEST_CASE("fix: apply_edits replaces, inserts and deletes in order") {
    CHECK(applied("abcdef", {{0, 0, ">"}, {1, 3, "XY"}, {4, 6, ""}}) == ">aXYd");
    CHECK(applied("abc", {{3, 3, "!"}}) == "abc!");
    CHECK(applied("abc", {}) == "abc");
    MemorySource src("abc");
    std::string error;
    CHECK_FALSE(apply_edits(src, {{5, 6, "x"}}, [](std::string_view) { return true; }, error));
    CHECK(!error.empty());
}

TEST_CASE("fix: the collector takes safe fixes, leaves unsafe ones, and one of two that overlap") {
    FixCollector c(false);
    c.diagnostic(with_fix({{10, 13, "PM=52"}}));
    c.diagnostic(with_fix({{11, 12, "Z"}}));            // overlaps the first: waits
    c.diagnostic(with_fix({{10, 13, "PM=52"}}));        // identical to the first: counted once
    c.diagnostic(with_fix({{20, 20, "A"}, {30, 32, ""}}));
    c.diagnostic(with_fix({{20, 20, "B"}}));            // a second insertion at 20: waits
    c.diagnostic(with_fix({{40, 41, "U"}}, false));     // unsafe
    uint64_t chosen = 0, waiting = 0;
    const auto edits = c.choose(chosen, waiting);
    CHECK(chosen == 2);
    CHECK(waiting == 2);
    CHECK(c.unsafe_left() == 1);
    REQUIRE(edits.size() == 3);
    CHECK(edits[0] == Edit{10, 13, "PM=52"});
    CHECK(edits[1] == Edit{20, 20, "A"});
    CHECK(edits[2] == Edit{30, 32, ""});

    FixCollector u(true);
    u.diagnostic(with_fix({{40, 41, "U"}}, false));
    CHECK(u.choose(chosen, waiting).size() == 1);
    CHECK(u.unsafe_left() == 0);
}

TEST_CASE("fix: an insertion at the start of a deletion goes with it; inside it, it waits") {
    FixCollector c(false);
    c.diagnostic(with_fix({{5, 5, "M843\n"}, {5, 10, ""}}));
    c.diagnostic(with_fix({{7, 7, "x"}}));
    uint64_t chosen = 0, waiting = 0;
    const auto edits = c.choose(chosen, waiting);
    CHECK(chosen == 1);
    CHECK(waiting == 1);
    CHECK(applied("0123456789AB", edits) == "01234M843\nAB");
}

TEST_CASE("fix: composing two rounds gives the text of applying them one after the other") {
    std::mt19937 rng(12345);
    const std::string alphabet = "G0X1.\n\r ;";
    for (int round = 0; round < 3000; ++round) {
        std::string text;
        const size_t n = rng() % 40;
        for (size_t i = 0; i < n; ++i) text += alphabet[rng() % alphabet.size()];
        const auto first = random_edits(rng, text.size());
        const std::string middle = applied(text, first);
        const auto second = random_edits(rng, middle.size());
        const std::string want = applied(middle, second);
        MemorySource src(text);
        std::vector<Edit> composed;
        std::string error;
        REQUIRE(compose_edits(src, first, second, composed, error));
        for (size_t i = 1; i < composed.size(); ++i) REQUIRE(composed[i - 1].end <= composed[i].begin);
        INFO("text: ", text, " round ", round);
        REQUIRE(applied(text, composed) == want);
    }
}

TEST_CASE("diff: a changed line with context, and the numbers of later hunks") {
    std::string text;
    for (int i = 1; i <= 20; ++i) text += "N" + std::to_string(i) + "\n";
    // "N2" -> "N2 M52"; line 15 split in two.
    const size_t at2 = text.find("N2\n") + 2;
    const size_t at15 = text.find("N15\n") + 1;
    const std::string d = diff_of(text, {{static_cast<uint32_t>(at2), static_cast<uint32_t>(at2), " M52"},
                                         {static_cast<uint32_t>(at15), static_cast<uint32_t>(at15 + 1), "\nX"}});
    CHECK(d ==
          "--- a/P.MIN\n+++ b/P.MIN\n"
          "@@ -1,5 +1,5 @@\n N1\n-N2\n+N2 M52\n N3\n N4\n N5\n"
          "@@ -12,7 +12,8 @@\n N12\n N13\n N14\n-N15\n+N\n+X5\n N16\n N17\n N18\n");
}

TEST_CASE("diff: close changes share a hunk; a last line without a newline is marked") {
    const std::string text = "A\nB\nC\nD\nE\nF\nG\nH\nI\nJ";
    const std::string d = diff_of(text, {{2, 3, "b"}, {14, 15, "h"}, {18, 19, "j"}}, 1);
    // With one line of context, H (line 8) and J (line 10) are two lines
    // apart: one hunk holds both.
    CHECK(d ==
          "--- a/P.MIN\n+++ b/P.MIN\n"
          "@@ -1,3 +1,3 @@\n A\n-B\n+b\n C\n"
          "@@ -7,4 +7,4 @@\n G\n-H\n+h\n I\n-J\n\\ No newline at end of file\n+j\n\\ No newline at end of file\n");
}

TEST_CASE("diff: insertions at the end and into an empty file; CRLF lines kept") {
    CHECK(diff_of("A\n", {{2, 2, "M30\n"}}) == "--- a/P.MIN\n+++ b/P.MIN\n@@ -1,1 +1,2 @@\n A\n+M30\n");
    CHECK(diff_of("", {{0, 0, "M30\n"}}) == "--- a/P.MIN\n+++ b/P.MIN\n@@ -0,0 +1,1 @@\n+M30\n");
    CHECK(diff_of("A\r\nB\r\n", {{3, 4, "C"}}) == "--- a/P.MIN\n+++ b/P.MIN\n@@ -1,2 +1,2 @@\n A\r\n-B\r\n+C\r\n");
    CHECK(diff_of("A", {{1, 1, "B"}}) ==
          "--- a/P.MIN\n+++ b/P.MIN\n@@ -1,1 +1,1 @@\n-A\n\\ No newline at end of file\n+AB\n\\ No newline at end of file\n");
    CHECK(diff_of("A\n", {}).empty());
}
