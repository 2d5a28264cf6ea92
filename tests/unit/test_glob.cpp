// The glob patterns of `exclude`, `[[per-path]]` and --exclude, and the edit
// distance behind the "did you mean" hints.
#include <doctest/doctest.h>

#include <random>
#include <string>

#include "support/glob.h"
#include "support/text.h"

using namespace osplint;

TEST_CASE("glob: *, ?, [...] stay within one component") {
    CHECK(glob_match("*.MIN", "P1.MIN"));
    CHECK_FALSE(glob_match("*.MIN", "a/P1.MIN"));
    CHECK(glob_match("*.BAK.MIN", "P1.BAK.MIN"));
    CHECK_FALSE(glob_match("*.BAK.MIN", "P1.MIN"));
    CHECK(glob_match("P?.MIN", "P1.MIN"));
    CHECK_FALSE(glob_match("P?.MIN", "P12.MIN"));
    CHECK_FALSE(glob_match("a?b", "a/b"));
    CHECK(glob_match("P[0-9].MIN", "P7.MIN"));
    CHECK_FALSE(glob_match("P[0-9].MIN", "PX.MIN"));
    CHECK(glob_match("P[!0-9].MIN", "PX.MIN"));
    CHECK(glob_match("P[^0-9].MIN", "PX.MIN"));
    CHECK_FALSE(glob_match("P[!0-9].MIN", "P3.MIN"));
    CHECK(glob_match("[]x]", "]"));
    CHECK(glob_match("a*b*c", "aXXbYYc"));
    CHECK_FALSE(glob_match("a*b*c", "aXXbYY"));
    CHECK(glob_match("*", "anything"));
    CHECK_FALSE(glob_match("*", "a/b"));
    CHECK(glob_match("P[1", "P[1"));  // an unclosed '[' is itself
    CHECK_FALSE(glob_match("p1.min", "P1.MIN"));  // case sensitive
}

TEST_CASE("glob: ** spans any number of components") {
    CHECK(glob_match("old/**", "old/P1.MIN"));
    CHECK(glob_match("old/**", "old/a/b/P1.MIN"));
    CHECK(glob_match("old/**", "old"));
    CHECK_FALSE(glob_match("old/**", "older/P1.MIN"));
    CHECK(glob_match("**/x.MIN", "x.MIN"));
    CHECK(glob_match("**/x.MIN", "a/b/x.MIN"));
    CHECK(glob_match("a/**/z/*.MIN", "a/z/P.MIN"));
    CHECK(glob_match("a/**/z/*.MIN", "a/b/c/z/P.MIN"));
    CHECK_FALSE(glob_match("a/**/z/*.MIN", "a/b/c/y/P.MIN"));
    CHECK(glob_match("a/**/**/b", "a/b"));
    CHECK(glob_match("a//b", "a/b"));
}

TEST_CASE("glob: well-formed patterns") {
    CHECK(glob_valid("old/**"));
    CHECK(glob_valid("P[0-9]*.MIN"));
    std::string_view why;
    CHECK_FALSE(glob_valid("P[0-9.MIN", &why));
    CHECK(why.find("']'") != std::string_view::npos);
    CHECK_FALSE(glob_valid(""));
}

TEST_CASE("edit distance and the nearest candidate") {
    CHECK(edit_distance("check", "check") == 0);
    CHECK(edit_distance("chek", "check") == 1);
    CHECK(edit_distance("chekc", "check") == 1);  // a swap is one edit
    CHECK(edit_distance("CHECK", "check") == 0);
    CHECK(edit_distance("", "abc") == 3);
    CHECK(closest_match("chek", {"check", "rules", "explain", "config", "trace", "lsp"}) == "check");
    CHECK(closest_match("formt", {"format", "fail-on", "fold"}) == "format");
    CHECK(closest_match("zzzzzz", {"check", "rules"}).empty());
}

TEST_CASE("same_prefix: where two byte ranges first differ") {
    CHECK(same_prefix("", "", 0) == 0);
    CHECK(same_prefix("abc", "abd", 3) == 2);
    CHECK(same_prefix("CALL OZAGR PX=", "CALL OZAGR PX=", 14) == 14);
    CHECK(same_prefix("CALL OZAGR PX=1", "CALL OZAGR PY=1", 15) == 12);
    // Every length around the 8- and 16-byte steps, a difference at every place.
    std::mt19937 random(7);
    for (size_t n = 0; n <= 40; ++n) {
        std::string a(n, ' ');
        for (char& c : a) c = static_cast<char>('A' + random() % 26);
        CHECK(same_prefix(a.data(), a.data(), n) == n);
        for (size_t at = 0; at < n; ++at) {
            std::string b = a;
            b[at] = static_cast<char>(b[at] ^ (1 + random() % 0x7f));
            // A second difference after the first changes nothing.
            if (at + 1 < n && random() % 2) b[n - 1] = static_cast<char>(b[n - 1] ^ 0x20);
            CHECK(same_prefix(a.data(), b.data(), n) == at);
            CHECK(same_prefix(b.data(), a.data(), n) == at);
        }
    }
}
