// The glob patterns of `exclude`, `[[per-path]]` and --exclude, and the edit
// distance behind the "did you mean" hints.
#include <doctest/doctest.h>

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
