// Differential tests of the hand-written front end (syntax/frontend_fast.h)
// against the tree-sitter front end (syntax/frontend.h), the definition of
// the syntax: every corpus and example program, the grammar's corpus inputs,
// generated programs and randomly mutated ones (seeded) give the same Blocks
// (operator==) and the same programs. No difference is tolerated. Lines with
// syntax errors agree because both front ends parse such a line on its own,
// so that tree-sitter's error recovery does not depend on the neighbouring
// lines.
#include <doctest/doctest.h>

#include <cctype>
#include <cstring>
#include <algorithm>
#include <array>
#include <optional>
#include <random>
#include <sstream>
#include <string>
#include <vector>

#include "api/check.h"
#include "programs.h"
#include "semantics/transfer.h"
#include "syntax/frontend.h"
#include "syntax/directive.h"
#include "syntax/frontend_fast.h"
#include "syntax/outline.h"

using namespace osplint;
using namespace osplint::testing;

namespace {

struct ModelComparison {
    size_t blocks = 0;
    size_t fallback = 0;
    size_t strict = 0;  // divergences
    std::string report;
};

ModelComparison compare_models(const std::string& name, const std::string& text) {
    ModelComparison c;
    const ProgramFile ts = parse_program_file(name, text);
    uint64_t fallback = 0;
    const ProgramFile fast = parse_program_file_fast(name, text, &fallback);
    c.blocks = ts.blocks.size();
    c.fallback = fallback;
    if (ts.blocks.size() != fast.blocks.size()) {
        ++c.strict;
        c.report += name + ": " + std::to_string(ts.blocks.size()) + " blocks vs " +
                    std::to_string(fast.blocks.size()) + "\n";
        return c;
    }
    for (size_t k = 0; k < ts.blocks.size(); ++k) {
        const Block& a = ts.blocks[k];
        const Block& b = fast.blocks[k];
        if (a == b) continue;
        ++c.strict;
        if (c.report.size() < 20000)
            c.report += name + " line " + std::to_string(a.line) + ": '" + std::string(ts.source.line_text(a.line)) +
                        "'\n-- tree-sitter:\n" + dump_block(a) + "-- fast:\n" + dump_block(b);
    }
    if (!(ts.programs == fast.programs)) {
        ++c.strict;
        c.report += name + ": programs differ\n";
    }
    return c;
}

}  // namespace

TEST_CASE("fast front end: corpus, examples and fixtures give the tree-sitter model") {
    const auto files = corpus_files();
    REQUIRE(files.size() > 50);
    size_t blocks = 0, fallback = 0;
    for (const auto& f : files) {
        const ModelComparison c = compare_models(f.string(), read_all(f));
        blocks += c.blocks;
        fallback += c.fallback;
        CHECK_MESSAGE(c.strict == 0, c.report);
    }
    MESSAGE(files.size() << " files, " << blocks << " blocks, " << fallback << " parsed by tree-sitter");
}

TEST_CASE("fast front end: the grammar corpus inputs") {
    const auto inputs = grammar_inputs();
    CHECK(inputs.size() > 20);
    for (size_t i = 0; i < inputs.size(); ++i) {
        const ModelComparison c = compare_models("corpus" + std::to_string(i) + ".min", inputs[i]);
        CHECK_MESSAGE(c.strict == 0, c.report);
    }
    MESSAGE(inputs.size() << " grammar corpus inputs");
}

TEST_CASE("fast front end: common blocks take the hand-written path") {
    FastLineParser p;
    Block b;
    for (const char* line :
         {"G01X10.5Y-3", "N10 G0 G90 X0 Y0 (START)", "/N20 X-.75 F.2 Z3.", "O1234 (PART)", "VC1=5", "PX=PX",
          "X=VC1+2*[VC2-1] Y=-VC3", "CALL OKYOY PX=-50. PY=-30. PR=2. PZ=-5. Q5", "MODIN OG87C PR=-45.", "MODOUT",
          "G56 Z50. HA", "RTS", "NCYL G81 Z-3.5 R3. F150", "G85 N0207 D7", "VTOFX[16]=VTOFX[6]+.5", "%",
          // Call arguments: `Pname=number` read straight into its word, and its near misses.
          "CALL OZAGR PX=12.5 PY=-3 PZ = +.5 pfa=1000 PQ= 0.", "CALL O100 PX=1 Q2 PY=2 PZ=VC1+1 PW=3 (NOTE) PV=4",
          "CALL O100 PX=-5 M54", "CALL O100 PX=- 5 PY=1.5", "CALL O100 PX=1234567890123456 PY=1",
          "(COMMENT ONLY)", "", "  \t", "n10 g1 x1 y2 z3 f100", "$HDR.MIN%",
          // Jumps and loops, with conditions of keyword operators between blanks.
          "IF [VC1 LT 3] N10", "GOTO NSTOP", "N5 IF [VC1 EQ 1] GOTO N20", "if[vc1 ge 2]n30",
          "IF [[VC1 EQ 1] AND [VC2 NE VC3+1]] NEND", "IF [VC1 LT 2 OR VC2 GT 3 AND -VC3 LE 4] N1 (NOTE)",
          "IF [VC1 EOR VC2 EQ 0] N1", "WHILE [VC2 LT VC3*2] DO 1", "WHILE[VC2 LT 5]DO 12", "DO 2", "END 1",
          "END", "END X5", "/ GOTO N100", "VC1=VC2 EQ 3"}) {
        const std::string text(line);
        CHECK_MESSAGE(p.parse_fast_only(LineRef{text, "\n", 1, 0}, b), line);
        const ProgramFile ts = parse_program_file("t.min", text + "\n");
        REQUIRE(ts.blocks.size() == 1);
        CHECK_MESSAGE(b == ts.blocks[0], line << "\n-- tree-sitter:\n" << dump_block(ts.blocks[0]) << "-- fast:\n"
                                              << dump_block(b));
    }
    // Outside the subset: parsed by tree-sitter, with the same result.
    for (const char* line : {"X=SIN[30]", "PUT 'TEXT'", "S15O0 M3", "G1 X10..5", "VUACM[1]='NO DATA'", "X5 @",
                             // Jumps and loops the scanner may read otherwise, or with an error.
                             "IF [VC1 LT[2]] N10", "IF [VC1LT 2] N10", "IF [NOT VC1] N10", "IF [VC1 LT 3] (C) N10",
                             "IF [VC1 LT 3] N10A", "GOTO", "GOTO NX=1", "DO1", "DO 1.5", "END1", "WHILE [VC1] DO",
                             "IF [] N10", "GOTO N10.5"}) {
        const std::string text(line);
        CHECK_FALSE_MESSAGE(p.parse(LineRef{text, "\n", 7, 100}, b), text);
        Block alone;
        parse_line_tree_sitter(LineRef{text, "\n", 7, 100}, alone);
        CHECK(b == alone);
        CHECK(b.line == 7);
        CHECK(b.range == ByteRange{100, 100 + static_cast<uint32_t>(text.size())});
    }
}

TEST_CASE("fast front end: a comment ends at its first `)`, and a control byte in it is the tree-sitter's to read") {
    // Comments of every length around the 16 bytes the scan reads at a time,
    // with a `)`, a tab, a control byte, DEL or a byte above 0x7F at every place.
    FastLineParser p;
    Block b;
    for (size_t len = 0; len <= 40; ++len) {
        for (size_t at = 0; at <= len; ++at) {
            for (const char c : {')', '\t', '\x01', '\x1f', '\x7f', '\xe9', 'A'}) {
                std::string body(len, 'C');
                if (at < len) body[at] = c;
                const std::string text = "G0 X1 (" + body + ") Y2";
                const bool fast = p.parse(LineRef{text, "\n", 1, 0}, b);
                Block alone;
                parse_line_tree_sitter(LineRef{text, "\n", 1, 0}, alone);
                CHECK_MESSAGE(b == alone, "length " << len << ", byte " << int(static_cast<unsigned char>(c)) << " at " << at
                                                    << "\n-- tree-sitter:\n" << dump_block(alone) << "-- fast:\n"
                                                    << dump_block(b));
                const bool control = at < len && (c == '\x01' || c == '\x1f' || c == '\x7f');
                if (control) CHECK_FALSE_MESSAGE(fast, text);  // not the fast path's to read
                if (c == '\t' || c == 'A') CHECK_MESSAGE(fast, text);
            }
        }
    }
}

TEST_CASE("fast front end: generated programs") {
    size_t blocks = 0, files = 0;
    for (uint32_t seed = 1; seed <= 300; ++seed) {
        Generator g(seed, true);
        const std::string text = g.program();
        const ModelComparison c = compare_models("gen" + std::to_string(seed) + ".min", text);
        blocks += c.blocks;
        ++files;
        CHECK_MESSAGE(c.strict == 0, "seed " << seed << "\n" << c.report);
    }
    MESSAGE(files << " generated programs, " << blocks << " blocks");
}

TEST_CASE("fast front end: randomly mutated corpus programs") {
    const auto files = corpus_files();
    std::vector<std::string> texts;
    for (const auto& f : files) texts.push_back(read_all(f));
    std::mt19937 rng(20261122);
    const int rounds = 1500;
    for (int i = 0; i < rounds; ++i) {
        const std::string text = mutate(texts[rng() % texts.size()], rng);
        const ModelComparison c = compare_models("mut" + std::to_string(i) + ".min", text);
        CHECK_MESSAGE(c.strict == 0, "round " << i << "\n" << c.report);
    }
    MESSAGE(rounds << " mutated programs");
}

TEST_CASE("fast front end: lines too deep or too long past their error give the tree-sitter model") {
    const std::vector<std::string> lines = {
        "X=" + std::string(70000, '['),
        "IF " + std::string(300, '[') + "VC1 EQ 1" + std::string(300, ']') + " NA",
        "VC1=" + std::string(5000, '-') + "1",
        "VC1=NOT " + std::string(250, '-'),
        "VC1=1" + std::string(5000, ']'),
        "G1 X1" + std::string(3000, ',') + " Y2 (comment)",
        "N10 G1 X=1" + std::string(3000, '=') + "(OSPLINT-IGNORE OSP001)",
        "VC1=[" + std::string(63, ' ') + "]" + std::string(100, ']'),
    };
    for (size_t i = 0; i < lines.size(); ++i) {
        const std::string text = "G0\n" + lines[i] + "\nG1 X2\n" + lines[i];
        const ModelComparison c = compare_models("bound" + std::to_string(i) + ".min", text);
        CHECK_MESSAGE(c.strict == 0, c.report);
        const ProgramFile f = parse_program_file("bound.min", text);
        REQUIRE(f.blocks.size() == 4);
        CHECK_FALSE(f.blocks[1].errors.empty());
        CHECK(f.blocks[2].errors.empty());
        CHECK(f.blocks[1].errors.size() == f.blocks[3].errors.size());
    }
}

TEST_CASE("fast front end: numbers too large for a double give the tree-sitter model and its error") {
    const std::string over(400, '9');
    const std::vector<std::string> lines = {
        "G81 Z-" + over + " R" + over + " F0.1",
        "N10 G1 X" + over + " Y-" + over,
        "X=" + over + "+1",
        "VC1=[" + over + "*" + over + "]",
        "CALL OZAGR PX=" + over,
        "G85 N" + over + " D7",
        "G1 X." + std::string(400, '0') + "1 Z0." + std::string(400, '0') + "1",
    };
    for (size_t i = 0; i < lines.size(); ++i) {
        const std::string text = "G0\n" + lines[i] + "\nG1 X2\n" + lines[i];
        const ModelComparison c = compare_models("huge" + std::to_string(i) + ".min", text);
        CHECK_MESSAGE(c.strict == 0, c.report);
        const ProgramFile f = parse_program_file("huge.min", text);
        REQUIRE(f.blocks.size() == 4);
        const bool tiny = i + 1 == lines.size();
        CHECK(f.blocks[1].errors.empty() == tiny);
        CHECK(f.blocks[1].errors.size() == f.blocks[3].errors.size());
    }
}

TEST_CASE("tree-sitter front end: an error line is parsed on its own, whatever its neighbours") {
    // `$` inside a block: in the whole file, error recovery took `$1 D12` for a
    // tape header after a missing line end, which gave no syntax error at all.
    const ProgramFile f = parse_program_file("t.min", "G0\nG4$1 D12 X-15.\nM30\n");
    REQUIRE(f.blocks.size() == 3);
    CHECK_FALSE(f.blocks[1].errors.empty());
    Block alone;
    parse_line_tree_sitter(LineRef{"G4$1 D12 X-15.", "\n", 2, 3}, alone);
    CHECK(f.blocks[1] == alone);
    CHECK(f.blocks[0].errors.empty());
    CHECK(f.blocks[2].errors.empty());
    const FileResult r = check_text("t.min", "G0\nG4$1 D12 X-15.\nM30\n", Config{});
    bool syntax = false;
    for (const auto& d : r.diagnostics) syntax = syntax || (d.rule == "OSP001" && d.range.start.line == 2);
    CHECK(syntax);
}

namespace {

// What the outline (syntax/outline.cpp, Outliner::take) reads of a block:
// parse_outline must give the same for every line.
std::string outline_view(const Block& b) {
    std::string v = std::to_string(static_cast<int>(b.kind)) + (b.is_empty() ? " empty" : "") +
                    (b.errors.empty() ? "" : " errors") + (b.block_delete ? " /" : "");
    if (b.program_name)
        v += " O" + b.program_name->name + "@" + std::to_string(b.program_name->range.begin) + "-" +
             std::to_string(b.program_name->range.end);
    for (const auto& st : b.statements)
        v += " st" + std::to_string(static_cast<int>(st.kind)) + ":" + st.name + ":" + std::to_string(st.loop);
    for (const auto& w : b.words)
        if (w.address == "N") v += " N" + w.value_text;
    for (const auto& c : b.comments) v += " (" + std::to_string(c.range.begin) + "-" + std::to_string(c.range.end);
    return v;
}

// Compares parse_outline with parse on every line of `text`; returns the differences.
std::string compare_outline(const std::string& name, const std::string& text) {
    FastLineParser full, outline;
    Block a, b;
    std::string report;
    for_each_line(text, [&](const LineRef& line) {
        full.parse(line, a);
        outline.parse_outline(line, b);
        if (outline_view(a) != outline_view(b) && report.size() < 4000)
            report += name + " line " + std::to_string(line.line) + ": '" + std::string(line.text) + "'\n  parse:   " +
                      outline_view(a) + "\n  outline: " + outline_view(b) + "\n";
        // A line the outline passes over unparsed (outline_passes_over) must
        // be a CALL or MODIN statement and nothing else the outline reads:
        // no program name, sequence name, block delete, jump, loop, RTS, N
        // word or directive. A plain call (plain_call) is that statement alone.
        // A line the front end reads as a tape header (a `$` after the call's
        // name makes one of it) gives the outline nothing either, once the
        // program has begun (where the outline passes over lines).
        const bool plain = outline.plain_call(line);
        if ((plain || outline_passes_over(outline, line)) && !(!plain && a.kind == LineKind::Header)) {
            const bool call_first = !a.statements.empty() && (a.statements[0].kind == StmtKind::Call ||
                                                              a.statements[0].kind == StmtKind::Modin);
            bool takes = false;
            for (const auto& st : a.statements)
                takes = takes || st.kind == StmtKind::Rts || st.kind == StmtKind::Goto || st.kind == StmtKind::If ||
                        st.kind == StmtKind::While || st.kind == StmtKind::Do || st.kind == StmtKind::End;
            const bool only_call = a.kind == LineKind::Block && !a.block_delete && !a.program_name && !a.sequence &&
                                   call_first && !takes && !has_directive(a, line.text) &&
                                   std::none_of(a.words.begin(), a.words.end(),
                                                [](const Word& w) { return w.address == "N"; }) &&
                                   (!plain || (a.errors.empty() && a.comments.empty() && a.statements.size() == 1));
            if (!only_call && report.size() < 4000)
                report += name + " line " + std::to_string(line.line) + ": '" + std::string(line.text) +
                          "' passed over, but parse: " + outline_view(a) + "\n";
        }
        // A line of comments only that the outline passes over (comments_only)
        // must be read as one: no content, no error, no directive.
        if (comments_only(line.text)) {
            const bool none = a.kind == LineKind::Block && a.is_empty() && a.errors.empty() && !a.block_delete &&
                              !a.comments.empty() && !has_directive(a, line.text);
            if (!none && report.size() < 4000)
                report += name + " line " + std::to_string(line.line) + ": '" + std::string(line.text) +
                          "' passed over as comments only, but parse: " + outline_view(a) + "\n";
        }
    });
    return report;
}

// Runs `compare` (name, text -> a report, empty when the two readings agree)
// on the corpus, on 100 generated programs and on 300 mutated corpus files.
template <class Compare>
void on_test_programs(uint32_t seed, Compare&& compare) {
    const auto files = corpus_files();
    for (const auto& f : files) {
        const std::string report = compare(f.string(), read_all(f));
        CHECK_MESSAGE(report.empty(), report);
    }
    for (uint32_t g = 1; g <= 100; ++g) {
        const std::string report = compare("gen" + std::to_string(g), Generator(g, true).program());
        CHECK_MESSAGE(report.empty(), report);
    }
    std::mt19937 rng(seed);
    for (int i = 0; i < 300; ++i) {
        const std::string report = compare("mut" + std::to_string(i), mutate(read_all(files[rng() % files.size()]), rng));
        CHECK_MESSAGE(report.empty(), "round " << i << "\n" << report);
    }
}

}  // namespace

TEST_CASE("fast front end: parse_outline reads what parse reads for the outline") {
    on_test_programs(20261126, [](const std::string& name, const std::string& text) { return compare_outline(name, text); });
    // The arguments the outline may skip, and those it may not.
    FastLineParser p;
    Block b;
    auto outline_words = [&](const std::string& text) {
        p.parse_outline(LineRef{text, "\n", 1, 0}, b);
        REQUIRE(b.statements.size() >= 1);
        CHECK(b.statements[0].kind == (text.rfind("MODIN", 0) == 0 ? StmtKind::Modin : StmtKind::Call));
        return b.words.size();
    };
    CHECK(outline_words("CALL OZAGR PX=12.5 PY=-3 PZ = +.5 PFA=1000") == 0);
    CHECK(outline_words("MODIN OG87N PR=-45. PZ=-60.") == 0);
    CHECK(b.statements[0].name == "OG87N");
    CHECK(outline_words("CALL O100 PX=1 N10") > 0);         // an N word: a reference
    CHECK(outline_words("CALL O100 PX=VC1") > 0);           // an expression
    CHECK(outline_words("CALL O100 PX=1 Q2") > 0);          // not a P name
    CHECK(outline_words("CALL O100 PX=1 (NOTE)") > 0);      // a comment (a directive may be in it)
    CHECK(b.comments.size() == 1);
    CHECK(outline_words("CALL O100 PX=1234567890123456") > 0);  // more digits than the outline skips
    // The lines the outline passes over without parsing them, and those it parses.
    auto plain_call = [&](const std::string& text) { return p.plain_call(LineRef{text, "\n", 1, 0}); };
    CHECK(plain_call("CALL OZAGR PX=12.5 PY=-3 PZ = +.5 PFA=1000"));
    CHECK(plain_call("call ozagr px=1 py=2"));
    CHECK(plain_call("MODIN OG87N PR=-45. PZ=-60."));
    CHECK(plain_call("CALL O100"));
    CHECK_FALSE(plain_call("N10 CALL O100 PX=1"));      // a sequence name
    CHECK_FALSE(plain_call("/CALL O100 PX=1"));         // block delete
    CHECK_FALSE(plain_call("CALL O100 PX=1 N10"));      // an N word: a reference
    CHECK_FALSE(plain_call("CALL O100 PX=1 (NOTE)"));   // a comment
    CHECK_FALSE(plain_call("CALL O100 PX=VC1"));        // an expression
    CHECK_FALSE(plain_call("CALLO100 PX=1"));           // one name, no keyword
    CHECK_FALSE(plain_call("CALL 100 PX=1"));           // no program name
    CHECK_FALSE(plain_call("MODOUT"));
    CHECK_FALSE(plain_call("GOTO N10"));
    // The outline passes over a call line whose arguments hold no byte an
    // outlined item must hold (o, e, t, w, n, f after i), whatever they are.
    auto passes = [&](const std::string& text) { return outline_passes_over(p, LineRef{text, "\n", 1, 0}); };
    CHECK(passes("CALL OZAGR PX=12.5 PY=-3 PZ = +.5 PFA=1000"));
    CHECK(passes("CALL O100 PX=VC1+[2*VC2] PY=1.2.3"));       // expressions, even errors
    CHECK(passes("CALL O100 PX=1 (ABC)"));                    // a comment that cannot be a directive
    CHECK(passes("CALL O100 PE=1 PT=2"));                     // plain arguments, candidates or not
    CHECK_FALSE(passes("CALL O100 PX=1 (OSPLINT: DISABLE=OSP101)"));
    CHECK_FALSE(passes("CALL O100 PX=VC1 N10"));              // an N word
    CHECK_FALSE(passes("CALL O100 PX=SIN[VC1]"));             // a function (an n)
    CHECK_FALSE(passes("CALL O100 PX=VC1 GOTO N1"));
    CHECK_FALSE(passes("CALL O100 PX=VC1 IF"));
    CHECK_FALSE(passes("CALL O100 PX=VC1 RTS"));
    CHECK_FALSE(passes("CALL O100 PX=VC1 PY=VC2 IF"));       // I and F across 16 bytes of the arguments
    CHECK(passes("CALL O100 PX=VC1 PY=VC2 IXF"));
    // The last letter of an argument's name (a P before it, an `=` after it)
    // is no keyword's and no N word: passed over, whatever the values are.
    CHECK(passes("CALL O100 PT=VC1 PN=VC2 PO=[VC3] PE=1 pw=2"));
    CHECK_FALSE(passes("CALL O100 PX=VC1 N=60"));             // an N word
    CHECK_FALSE(passes("CALL O100 PX=VC1 XT=1"));             // not after a P
    CHECK_FALSE(passes("CALL O100 PX=VC1 PT =1"));            // not before the `=`
    // A line of comments only, none of them a directive, is passed over too.
    CHECK(comments_only("(T31 BIG BACK C'BORE BAR - BACK SPOTFACES)"));
    CHECK(comments_only("  (ONE)\t(TWO) "));
    CHECK(comments_only("(OSPLINT IS NOT A DIRECTIVE WITHOUT ITS COLON)"));
    CHECK_FALSE(comments_only(""));                                // no comment
    CHECK_FALSE(comments_only("   "));
    CHECK_FALSE(comments_only("(osplint: disable=OSP104 -- checked)"));
    CHECK_FALSE(comments_only("(NOTE) ( OSPLINT : disable-file=OSP005)"));
    CHECK_FALSE(comments_only("(NOT CLOSED"));
    CHECK_FALSE(comments_only("(A) X1."));                         // a word after it
    CHECK_FALSE(comments_only("/(BLOCK DELETE)"));
    CHECK_FALSE(comments_only("N10 (NAMED)"));
    CHECK_FALSE(comments_only(std::string("(A\x01B)")));           // a control byte: the parser fails on it
    CHECK_FALSE(passes("CALL O100 PX=VC1 PTE=1"));            // a T inside the name
    // The look at the arguments takes the bytes the outline's scan takes
    // (may_hold_outline_item), but for the last letter of a `P?=` name, on
    // random arguments of every length.
    const auto holds_item = [](std::string_view args) {
        for (size_t k = 0; k < args.size(); ++k) {
            const char l = static_cast<char>(args[k] | 0x20);
            if (l == 'f' && k > 0 && (args[k - 1] | 0x20) == 'i') return true;
            if (l != 'o' && l != 'e' && l != 't' && l != 'w' && l != 'n') continue;
            if (!(k > 0 && k + 1 < args.size() && (args[k - 1] | 0x20) == 'p' && args[k + 1] == '=')) return true;
        }
        return false;
    };
    std::mt19937 rng(20261205);
    const std::string alphabet = "PXYZQRSTUVWOEINFD=.-+ 0123456789[]()*";
    for (int i = 0; i < 20000; ++i) {
        std::string args(rng() % 48, ' ');
        for (char& c : args) c = alphabet[rng() % alphabet.size()];
        const std::string text = (i % 5 == 0 ? "CALL OZAG" : i % 7 == 0 ? "CALL  OZAGR" : "CALL OZAGR") + args;
        const bool plain_args = p.plain_call(LineRef{text, "\n", 1, 0});
        // The name may run on into the arguments; the parser remembers the
        // head it found last, for the next line that starts with it.
        const uint32_t head = p.call_head_end(LineRef{text, "\n", 1, 0});
        REQUIRE(head >= 9);
        REQUIRE(head == FastLineParser().call_head_end(LineRef{text, "\n", 1, 0}));
        const std::string_view rest(text.data() + head, text.size() - head);
        const bool quiet = !holds_item(rest);
        const bool scan = may_hold_outline_item(rest.data(), rest.data() + rest.size(), false);
        REQUIRE_MESSAGE((quiet || scan), text);  // only bytes of a name are left out
        REQUIRE_MESSAGE((!quiet || !scan || rest.find('=') != std::string_view::npos), text);
        REQUIRE_MESSAGE(passes(text) == (quiet || plain_args), text);
    }
    CHECK_FALSE(passes("N10 CALL O100 PX=1"));
    CHECK_FALSE(passes("/CALL O100 PX=1"));
    CHECK_FALSE(passes("G0 X1"));
    // The numbers it passes over: what the parser reads as a number word.
    CHECK(plain_call("CALL O100 PX=5. PY=-.5 PZ=+0"));
    CHECK(plain_call("CALL O100 PX=123456789012345"));     // 15 digits
    CHECK(plain_call("CALL O100 PX=12345678901234.5"));    // 15 digits and a point
    CHECK_FALSE(plain_call("CALL O100 PX=1234567890123456"));  // 16 digits
    CHECK_FALSE(plain_call("CALL O100 PX=."));             // a point alone
    CHECK_FALSE(plain_call("CALL O100 PX=-"));
    CHECK_FALSE(plain_call("CALL O100 PX=1.2.3"));
    CHECK_FALSE(plain_call("CALL O100 PX=1A"));
    // The parser values such an argument as it checks it: the same word as
    // the general path gives (the differential tests compare every field).
    Block full;
    p.parse(LineRef{"CALL O100 PX=12345678901234.5 PY=-.5", "\n", 1, 0}, full);
    REQUIRE(full.words.size() == 2);
    CHECK(full.words[0].number == 12345678901234.5);
    CHECK(full.words[1].number == -0.5);
    CHECK(full.words[1].value_text == "-.5");
}

namespace {

// What the walk reads of a plain move read in part (FastLineParser::parse_moves):
// the block's shape and sequence name, each word's address, range and number.
std::string moves_view(const Block& b) {
    std::string v = std::to_string(static_cast<int>(b.kind)) + " line " + std::to_string(b.line) + " @" +
                    std::to_string(b.range.begin) + "-" + std::to_string(b.range.end) +
                    (b.is_empty() ? " empty" : "") + (b.errors.empty() ? "" : " errors") +
                    (b.block_delete ? " /" : "") + (is_plain_move_block(b) ? " plain" : "");
    if (b.sequence)
        v += " " + b.sequence->name + "@" + std::to_string(b.sequence->range.begin) + "-" +
             std::to_string(b.sequence->range.end);
    for (const auto& w : b.words) {
        std::ostringstream n;
        if (w.number) n << *w.number;
        v += " " + w.address + (w.equals ? "=" : "") + n.str() + "@" + std::to_string(w.range.begin) + "-" +
             std::to_string(w.range.end);
    }
    return v;
}

// Reads `text` line by line with parse_moves and compares with parse: a line
// kept in part must be a plain move and read the same, any other line must be
// the whole block. One parser takes both kinds of lines in turn, so nothing
// left from a line parsed whole may show in one read in part.
std::string compare_moves(const std::string& name, const std::string& text, size_t* partial = nullptr) {
    FastLineParser full, moves;
    Block a, b;
    std::string report;
    for_each_line(text, [&](const LineRef& line) {
        full.parse(line, a);
        const bool fast = moves.parse_moves(line, b);
        std::string why;
        if (moves.last_partial()) {
            if (partial) ++*partial;
            if (!fast || !moves.last_plain() || !is_plain_move_block(a)) why = "kept in part, not a plain move";
            else if (moves_view(a) != moves_view(b)) why = "differs";
        } else if (!(a == b)) {
            why = "not the whole block";
        }
        if (!why.empty() && report.size() < 4000)
            report += name + " line " + std::to_string(line.line) + ": '" + std::string(line.text) + "': " + why +
                      "\n  parse: " + moves_view(a) + "\n  moves: " + moves_view(b) + "\n";
    });
    return report;
}

// Reads `text` line by line with plain_move and compares with parse_moves:
// plain_move reads a line exactly when parse_moves keeps it in part with at
// most PlainMove::kMaxWords words and no sequence name but one written `N`
// and digits, and then reads the same addresses, numbers and ranges, and the
// same sequence name.
std::string compare_plain_move(const std::string& name, const std::string& text, size_t* read = nullptr,
                               size_t* named = nullptr) {
    FastLineParser moves, values;
    Block b;
    PlainMove m;
    std::string report;
    for_each_line(text, [&](const LineRef& line) {
        moves.parse_moves(line, b);
        const bool name_ok =
            !b.sequence || line.text.substr(b.sequence->range.begin - line.start, 1) == "N";
        const bool want = moves.last_partial() && name_ok && b.words.size() <= PlainMove::kMaxWords;
        const bool got = values.plain_move(line, m);
        std::string why;
        if (got != want) {
            why = got ? "read, not a plain move in part" : "not read";
        } else if (got) {
            if (read) ++*read;
            if (named && b.sequence) ++*named;
            bool same = m.count == b.words.size() &&
                        (b.sequence ? m.sequence == b.sequence->name && m.sequence_range == b.sequence->range
                                    : m.sequence.empty());
            for (size_t i = 0; same && i < m.count; ++i)
                same = b.words[i].address.size() == 1 && m.words[i].address == b.words[i].address[0] &&
                       b.words[i].number && m.words[i].number == *b.words[i].number &&
                       m.words[i].range == b.words[i].range;
            if (!same) why = "differs";
        }
        if (!why.empty() && report.size() < 4000)
            report += name + " line " + std::to_string(line.line) + ": '" + std::string(line.text) + "': " + why +
                      "\n  moves: " + moves_view(b) + "\n";
    });
    return report;
}

}  // namespace

TEST_CASE("fast front end: plain_move reads the lines parse_moves keeps in part, the same words") {
    size_t read = 0, named = 0;
    on_test_programs(20261202, [&](const std::string& name, const std::string& text) {
        // Counted on the corpus and the generated programs only: which files
        // are mutated changes with every file added to the corpus.
        const bool mutated = name.rfind("mut", 0) == 0;
        return compare_plain_move(name, text, mutated ? nullptr : &read, mutated ? nullptr : &named);
    });
    MESSAGE(read << " plain moves read, " << named << " with a sequence name");
    CHECK(read > 500);
    CHECK(named > 20);

    FastLineParser p;
    PlainMove m;
    const auto line = [](const char* text) { return LineRef{text, "\n", 7, 100}; };
    REQUIRE(p.plain_move(line(" G1 X-1.5 y+2. F300"), m));
    REQUIRE(m.count == 4);
    CHECK(m.words[2].address == 'Y');
    CHECK(m.words[2].number == 2);
    CHECK(m.words[2].range.begin == 110);
    CHECK(m.words[2].range.end == 114);
    CHECK(m.sequence.empty());
    REQUIRE(p.plain_move(line("N0120 X1"), m));
    CHECK(m.sequence == "N0120");
    CHECK(m.sequence_range == ByteRange{100, 105});
    REQUIRE(m.count == 1);
    for (const char* other : {"n12 X1", "N12", "NSTOP X1", "/N12 X1", "G81 X1 Z-2 R1 F9", "G-1 X1", "X1 (C)", "",
                              "X1 Y1 Z1 X1 Y1 Z1 X1 Y1 Z1"})
        CHECK_MESSAGE(!p.plain_move(line(other), m), other);
}

TEST_CASE("fast front end: parse_moves keeps what the walk reads of a plain move, and every other line whole") {
    size_t partial = 0;
    on_test_programs(20261128, [&](const std::string& name, const std::string& text) {
        // Mutated files are not counted: `partial` counts the plain moves of the others.
        return compare_moves(name, text, name.rfind("mut", 0) == 0 ? nullptr : &partial);
    });
    CHECK(partial > 500);  // the inputs hold plain moves enough (836 today)

    FastLineParser p;
    Block b;
    auto read = [&](const std::string& text) { return p.parse_moves(LineRef{text, "\n", 7, 100}, b) && p.last_partial(); };
    CHECK(read("N12 G1 X-1.5 Y+2. F300"));
    CHECK(b.sequence->name == "N12");
    REQUIRE(b.words.size() == 4);
    CHECK(b.words[1].address == "X");
    CHECK(*b.words[1].number == -1.5);
    CHECK(b.words[1].range.begin == 107);
    CHECK(b.words[1].range.end == 112);
    CHECK(b.exprs.empty());
    for (const char* whole : {"G81 X1 Z-2 R1 F9", "G1 X1 M3", "X=VC1", "G1 X[1+2]", "N5", "G-1 X1", "/X1", "X1 (C)"}) {
        CHECK_MESSAGE(!read(whole), whole);
        FastLineParser again;
        Block w;
        again.parse(LineRef{whole, "\n", 7, 100}, w);
        CHECK_MESSAGE(w == b, whole);
    }
    // Parsed whole again, the same line gives every field.
    CHECK(p.parse(LineRef{std::string_view("X1.5"), "\n", 7, 100}, b));
    CHECK_FALSE(p.last_partial());
    REQUIRE(b.words.size() == 1);
    CHECK(b.words[0].value_text == "1.5");
    CHECK(b.words[0].value != kNoExpr);
}

namespace {

// Whether plain_run may take the line: parse_moves keeps it in part with no
// sequence name, and it is of the strictest shape (upper case X Y Z F G
// words, spaces, G0 to G3 written with one or two digits, at most 15 digits
// in a value). `m` gets its words.
bool strict_plain_move(const std::string& line, std::vector<PlainMoveWord>& m) {
    FastLineParser p;
    Block b;
    p.parse_moves(LineRef{line, "\n", 1, 100}, b);
    if (!p.last_partial() || b.sequence) return false;
    m.clear();
    for (const Word& w : b.words) m.push_back(PlainMoveWord{w.address[0], *w.number, w.range});
    for (char c : line)
        if (!(c == ' ' || c == '.' || c == '+' || c == '-' || (c >= '0' && c <= '9') || c == 'X' || c == 'Y' ||
              c == 'Z' || c == 'F' || c == 'G'))
            return false;
    for (size_t i = 0; i < line.size(); ++i) {
        if (!std::isupper(static_cast<unsigned char>(line[i]))) continue;
        size_t j = i + 1, digits = 0;
        while (j < line.size() && !std::isupper(static_cast<unsigned char>(line[j])) && line[j] != ' ')
            digits += std::isdigit(static_cast<unsigned char>(line[j++])) ? 1 : 0;
        const std::string value = line.substr(i + 1, j - i - 1);
        if (line[i] == 'G' && !(!value.empty() && value.size() <= 2 && digits == value.size() && value.back() <= '3' &&
                                (value.size() == 1 || value[0] == '0')))
            return false;
        if (digits > 15) return false;
    }
    return true;
}

// A random line, most of them plain moves of the strictest shape, of 1 to
// about 45 bytes (the quick check of plain_run takes those under 32).
std::string random_move_line(std::mt19937& rng) {
    auto pick = [&](int n) { return static_cast<int>(rng() % static_cast<unsigned>(n)); };
    std::string line(static_cast<size_t>(pick(3) == 0 ? pick(3) : 0), ' ');
    const int words = 1 + (pick(10) == 0 ? pick(12) : pick(4));
    for (int w = 0; w < words; ++w) {
        line += "XYZFG"[pick(5)];
        if (line.back() == 'G') {
            line += pick(4) == 0 ? "0" : "";
            line += static_cast<char>('0' + pick(5));
        } else {
            if (pick(3) == 0) line += pick(2) ? '-' : '+';
            const int whole = pick(8) == 0 ? pick(18) : pick(4), fraction = pick(5) == 0 ? pick(18) : pick(4);
            for (int d = 0; d < whole; ++d) line += static_cast<char>('0' + pick(10));
            if (pick(4) != 0) line += '.';
            for (int d = 0; d < fraction; ++d) line += static_cast<char>('0' + pick(10));
        }
        line += std::string(static_cast<size_t>(pick(3) == 0 ? 0 : pick(3) == 0 ? 2 : 1), ' ');
    }
    if (pick(4) == 0) {  // something else somewhere
        const char* other = "xNM\t.+-A.G5 1";
        line.insert(static_cast<size_t>(pick(static_cast<int>(line.size()) + 1)), 1, other[pick(13)]);
    }
    return line;
}

}  // namespace

TEST_CASE("fast front end: plain_run reads the lines of the strictest plain-move shape, the last word of each") {
    std::mt19937 rng(20261203);
    FastLineParser p;
    size_t taken = 0, quick = 0;
    for (int i = 0; i < 200000; ++i) {
        const std::string line = random_move_line(rng);
        const char* terminator = i % 3 == 0 ? "\n" : i % 3 == 1 ? "\r\n" : "\r";
        std::vector<PlainMoveWord> want;
        const bool plain = strict_plain_move(line, want);
        // The line with 80 bytes of another line after it (the quick check
        // when it is short), and with one byte after it (byte by byte).
        for (const std::string& after : {std::string("M30") + std::string(80, ' '), std::string("M")}) {
            const std::string text = line + terminator + after;
            const auto run = p.plain_run(text, 100, 10, UINT64_MAX, UINT64_MAX, 1, 1, [](size_t, uint32_t) {});
            REQUIRE_MESSAGE(run.lines == (plain ? 1u : 0u), "'" << line << "'");
            if (!plain) continue;
            ++taken;
            quick += line.size() < 32 && after.size() > 1;
            CHECK(run.bytes == line.size() + std::strlen(terminator));
            // The last word of each address, in the order X Y Z F G.
            std::vector<PlainMoveWord> last;
            for (char a : std::string("XYZFG"))
                for (size_t k = want.size(); k-- > 0;)
                    if (want[k].address == a) {
                        last.push_back(want[k]);
                        break;
                    }
            REQUIRE_MESSAGE(run.last.count == last.size(), "'" << line << "'");
            for (size_t k = 0; k < last.size(); ++k) {
                CHECK_MESSAGE(run.last.words[k].address == last[k].address, "'" << line << "'");
                CHECK_MESSAGE(run.last.words[k].number == last[k].number, "'" << line << "'");
                CHECK_MESSAGE(run.last.words[k].range == last[k].range, "'" << line << "'");
            }
        }
    }
    CHECK(taken > 100000);
    CHECK(quick > 50000);

    // Runs of random lines, most of them plain moves, with different
    // terminators: the run ends before the first line of another shape.
    for (int i = 0; i < 20000; ++i) {
        std::string text;
        std::vector<size_t> starts;
        std::vector<std::string> lines;
        const int count = 1 + static_cast<int>(rng() % 12);
        for (int k = 0; k < count; ++k) {
            starts.push_back(text.size());
            lines.push_back(random_move_line(rng));
            text += lines.back();
            text += k % 4 == 3 ? "\r\n" : k % 5 == 4 ? "\r" : "\n";
        }
        text += "M30" + std::string(80, ' ');
        size_t plain = 0;
        std::array<std::optional<PlainMoveWord>, 5> last;
        for (; plain < lines.size(); ++plain) {
            std::vector<PlainMoveWord> words;
            if (!strict_plain_move(lines[plain], words)) break;
            for (PlainMoveWord w : words) {
                w.range = {static_cast<uint32_t>(w.range.begin - 100 + 1000 + starts[plain]),
                           static_cast<uint32_t>(w.range.end - 100 + 1000 + starts[plain])};
                last[std::string("XYZFG").find(w.address)] = w;
            }
        }
        const auto run = p.plain_run(text, 1000, 100, UINT64_MAX, UINT64_MAX, 1, 1, [](size_t, uint32_t) {});
        REQUIRE_MESSAGE(run.lines == plain, text);
        size_t k = 0;
        for (const auto& w : last) {
            if (!w) continue;
            REQUIRE_MESSAGE(k < run.last.count, text);
            CHECK_MESSAGE(run.last.words[k].address == w->address, text);
            CHECK_MESSAGE(run.last.words[k].number == w->number, text);
            CHECK_MESSAGE(run.last.words[k].range == w->range, text);
            ++k;
        }
        CHECK_MESSAGE(run.last.count == k, text);
    }

    // Several lines at once: the last word of each address over them, up to
    // the first line of another shape.
    const std::string text = "X1. Y2. Z3.\r\nX-4.5 F300\nG2 Y.5\nZ-0.25\nM30\n" + std::string(80, ' ');
    std::vector<size_t> starts;
    std::vector<uint32_t> numbers;
    const auto run = p.plain_run(text, 0, 100, UINT64_MAX, UINT64_MAX, 7, 1, [&](size_t s, uint32_t line) {
        starts.push_back(s);
        numbers.push_back(line);
    });
    CHECK(run.lines == 4);
    CHECK(starts == std::vector<size_t>{0, 13, 24, 31});
    CHECK(numbers == std::vector<uint32_t>{7, 8, 9, 10});
    // Only the lines whose number is a multiple of the step are told.
    starts.clear();
    numbers.clear();
    p.plain_run(text, 0, 100, UINT64_MAX, UINT64_MAX, 7, 2, [&](size_t s, uint32_t line) {
        starts.push_back(s);
        numbers.push_back(line);
    });
    CHECK(starts == std::vector<size_t>{13, 31});
    CHECK(numbers == std::vector<uint32_t>{8, 10});
    CHECK(run.last_start == 31);
    CHECK(run.bytes == 38);
    REQUIRE(run.last.count == 5);
    CHECK(run.last.words[0].number == -4.5);
    CHECK(run.last.words[1].number == 0.5);
    CHECK(run.last.words[2].number == -0.25);
    CHECK(run.last.words[3].number == 300);
    CHECK(run.last.words[4].number == 2);
    CHECK(run.last.words[4].range == ByteRange{24, 26});
}

TEST_CASE("fast front end: plain_run stops before a move with an axis word of more digits before its point than allowed") {
    // Both checks of a line (32 bytes at a time, and byte by byte) against
    // the digits of each X, Y and Z word counted here.
    std::mt19937 rng(20261205);
    FastLineParser p;
    size_t kept = 0, stopped = 0;
    for (int i = 0; i < 200000; ++i) {
        const std::string line = random_move_line(rng);
        std::vector<PlainMoveWord> want;
        if (!strict_plain_move(line, want)) continue;
        FastLineParser::IntDigits limit;
        for (auto& d : limit) d = rng() % 4 == 0 ? FastLineParser::kAnyDigits : static_cast<uint8_t>(rng() % 5);
        bool within = true;
        for (size_t q = 0; q < line.size(); ++q) {
            const char c = line[q];
            if (c != 'X' && c != 'Y' && c != 'Z') continue;
            size_t k = q + 1;
            if (k < line.size() && (line[k] == '-' || line[k] == '+')) ++k;
            size_t digits = 0;
            while (k < line.size() && line[k] >= '0' && line[k] <= '9') ++k, ++digits;
            if (digits > limit[static_cast<size_t>(c - 'X')]) within = false;
        }
        for (const std::string& after : {std::string("M30") + std::string(80, ' '), std::string("M")}) {
            const std::string text = line + "\n" + after;
            const auto run = p.plain_run(text, 0, 10, UINT64_MAX, UINT64_MAX, 1, 1, [](size_t, uint32_t) {}, limit);
            REQUIRE_MESSAGE(run.lines == (within ? 1u : 0u),
                            "'" << line << "' limits " << int(limit[0]) << " " << int(limit[1]) << " " << int(limit[2]));
        }
        ++(within ? kept : stopped);
    }
    CHECK(kept > 20000);
    CHECK(stopped > 20000);
    // A run goes on past the moves inside, up to the first one that may not be.
    const std::string text = "X12.5 Y-3.\nX99.999 Z-.5\nX100. Y1.\nX1.\nM30\n" + std::string(80, ' ');
    const auto run = p.plain_run(text, 0, 100, UINT64_MAX, UINT64_MAX, 1, 1, [](size_t, uint32_t) {}, {2, 2, 2});
    CHECK(run.lines == 2);
    CHECK(run.over);  // it stopped for the digits, not for the line's shape
    const auto all = p.plain_run(text, 0, 100, UINT64_MAX, UINT64_MAX, 1, 1, [](size_t, uint32_t) {}, {3, 1, 1});
    CHECK(all.lines == 4);
    CHECK_FALSE(all.over);
}

TEST_CASE("fast front end: parse_moves reads random plain moves, with or without a sequence name, as parse does") {
    // Numbers of 0 to 17 digits each side of the point, a sequence name
    // glued or not, other bytes put in at random.
    std::mt19937 rng(20261204);
    std::string text;
    for (int i = 0; i < 60000; ++i) {
        const unsigned prefix = rng() % 6;
        if (prefix == 1 || prefix == 2) {
            text += 'N';
            text += std::to_string(rng() % (prefix == 1 ? 100000 : 1000));
            if (prefix == 1) text += ' ';
        }
        if (prefix == 3) text += "n7 ";
        text += random_move_line(rng);
        text += i % 7 == 0 ? "\r\n" : "\n";
    }
    size_t partial = 0;
    CHECK(compare_moves("random", text, &partial) == "");
    CHECK(partial > 30000);
    CHECK(compare_plain_move("random", text) == "");
}

namespace {

// Reads `text` line by line with one parser into one block, as the walk does,
// and each line alone with the tree-sitter front end: the blocks must be
// equal, the call lines updated in place (again_lines) included.
std::string compare_again(const std::string& name, const std::string& text, uint64_t* again = nullptr) {
    FastLineParser parser;
    Block kept, alone;
    std::string report;
    for_each_line(text, [&](const LineRef& line) {
        parser.parse(line, kept);
        parse_line_tree_sitter(line, alone);
        if (!(kept == alone) && report.size() < 4000)
            report += name + " line " + std::to_string(line.line) + ": '" + std::string(line.text) +
                      "'\n-- tree-sitter:\n" + dump_block(alone) + "-- kept:\n" + dump_block(kept);
    });
    if (again) *again += parser.again_lines();
    return report;
}

// A number as posts and people write it: a sign or not, digits before and
// after a point or not, sometimes something else.
std::string random_value(std::mt19937& rng) {
    std::string v;
    switch (rng() % 8) {
        case 0: v = "-"; break;
        case 1: v = "+"; break;
        case 2: case 3: v = "-"; break;
        default: break;
    }
    const unsigned shape = rng() % 12;
    const auto digits = [&](unsigned count) {
        for (unsigned i = 0; i < count; ++i) v += static_cast<char>('0' + rng() % 10);
    };
    if (shape < 6) {
        digits(1 + rng() % 3);
        v += '.';
        digits(rng() % 4);
    } else if (shape < 8) {
        digits(1 + rng() % 4);
    } else if (shape == 8) {
        v += '.';
        digits(1 + rng() % 3);
    } else if (shape == 9) {
        digits(16 + rng() % 2);  // past what a plain argument holds
    } else if (shape == 10) {
        v += "VC" + std::to_string(rng() % 100);
    } else {
        digits(2);
        v += rng() % 2 ? "X" : ".5.";
    }
    return v;
}

}  // namespace

TEST_CASE("fast front end: a CALL that repeats the one before it but for its values gives the tree-sitter block") {
    // Lines of a few call heads and arguments, each line most often the one
    // before it with some values changed, else with an argument left out,
    // added or moved, other blanks, a comment, a repeat count, a sequence
    // name, or another line between.
    std::mt19937 rng(20261205);
    const std::vector<std::string> heads = {"CALL OZAGR", "CALL OZAGRX", "MODIN OG87C", "call ozagr", "CALL  OZAGR"};
    const std::vector<std::string> names = {"PX", "PY", "PR", "PZ", "PI", "PJ", "PF", "PFA", "px", "PS"};
    std::string head = heads[0];
    std::vector<std::pair<std::string, std::string>> args = {{"PX", "1."}, {"PY", "-2."}};
    std::string text;
    for (int i = 0; i < 20000; ++i) {
        const unsigned change = rng() % 40;
        if (change == 0) head = heads[rng() % heads.size()];
        else if (change == 1 && args.size() > 1) args.erase(args.begin() + static_cast<long>(rng() % args.size()));
        else if (change == 2 && args.size() < 12) args.emplace_back(names[rng() % names.size()], random_value(rng));
        else if (change == 3 && args.size() > 1) std::swap(args.front(), args.back());
        for (auto& [arg, value] : args) {
            if (rng() % 4 != 0) continue;
            if (rng() % 4 == 0) {
                value = random_value(rng);
            } else {  // another number, its sign kept
                const bool sign = !value.empty() && (value[0] == '-' || value[0] == '+');
                value = (sign ? value.substr(0, 1) : "") + std::to_string(rng() % 1000) + (rng() % 2 ? "." : ".25");
            }
        }
        std::string line = head;
        const unsigned extra = rng() % 60;
        for (const auto& [arg, value] : args) {
            line += extra == 0 ? "\t" : extra == 1 ? "  " : " ";
            line += arg + (extra == 2 ? " = " : "=") + value;
        }
        if (extra == 3) line += " (HOLE 3)";
        if (extra == 4) line += " Q2";
        if (extra == 5) line += "  ";
        if (extra == 6) line = "N" + std::to_string(i) + " " + line;
        if (extra == 7) line = "/" + line;
        if (extra == 8) text += "G0 X1. Y2.\n";
        text += line + (i % 9 == 0 ? "\r\n" : "\n");
    }
    uint64_t again = 0;
    CHECK(compare_again("calls", text, &again) == "");
    CHECK(again > 6000);
}

TEST_CASE("fast front end: one block taking every line of the test programs gives the tree-sitter blocks") {
    uint64_t again = 0;
    on_test_programs(20261206, [&](const std::string& name, const std::string& text) { return compare_again(name, text, &again); });
    CHECK(again > 0);
}

TEST_CASE("fast front end: plain_value_end takes a value where both front ends read a number word, that value") {
    // The walk tells a repeated call from its text with plain_value_end
    // (Walk::repeat_line): what it takes must be what the parser makes a
    // number of, over the same bytes.
    CHECK(FastLineParser::plain_value_end("-12.5 PY=1.", 0) == 5);
    CHECK(FastLineParser::plain_value_end("+.5", 0) == 3);
    CHECK(FastLineParser::plain_value_end("PX=7\tPY=1.", 3) == 4);
    CHECK(FastLineParser::plain_value_end("1234567890123456", 0) == 0);  // 16 digits
    CHECK(FastLineParser::plain_value_end("12345678901234.5", 0) == 16);
    CHECK(FastLineParser::plain_value_end("123456789012345.6", 0) == 0);
    CHECK(FastLineParser::plain_value_end("3.(C)", 0) == 0);  // a comment glued on
    CHECK(FastLineParser::plain_value_end("1.2.3", 0) == 0);
    CHECK(FastLineParser::plain_value_end("-.", 0) == 0);
    CHECK(FastLineParser::plain_value_end("-", 0) == 0);
    CHECK(FastLineParser::plain_value_end("VC1", 0) == 0);
    std::mt19937 rng(20261206);
    int taken = 0;
    for (int i = 0; i < 4000; ++i) {
        const std::string value = random_value(rng);
        // A call's argument, or a hole's axis word.
        const std::string head = i % 2 ? "CALL OZAGR PX=" : "X";
        const std::string line = head + value + (i % 3 ? (i % 2 ? " PY=1." : " Y1.") : "");
        const auto at = static_cast<uint32_t>(head.size());
        const uint32_t end = FastLineParser::plain_value_end(line, at);
        double value_read = 0;
        CHECK_MESSAGE(FastLineParser::plain_value(line, at, value_read) == end, line);
        if (end == at) continue;
        ++taken;
        CHECK_MESSAGE(end == at + value.size(), line);
        for (const ProgramFile& f : {parse_program_file("v.min", line + "\n"), parse_program_file_fast("v.min", line + "\n")}) {
            REQUIRE(f.blocks.size() == 1);
            const Block& b = f.blocks[0];
            const Word* w = b.find(i % 2 ? "PX" : "X");
            REQUIRE_MESSAGE(w, line);
            CHECK_MESSAGE(b.errors.empty(), line);
            CHECK_MESSAGE(w->number.has_value(), line);
            CHECK_MESSAGE(w->value_range.begin == at, line);
            CHECK_MESSAGE(w->value_range.end == end, line);
            if (w->number) CHECK_MESSAGE(*w->number == std::stod(value), line);
            if (w->number) CHECK_MESSAGE(*w->number == value_read, line);
        }
    }
    CHECK(taken > 2000);
}

TEST_CASE("outline: a line that repeats one it passed over but for its values is passed over too") {
    FastLineParser p;
    const auto passes = [&](const std::string& text) { return outline_passes_over(p, LineRef{text, "\n", 1, 0}); };
    const std::string om100 = "CALL OM100 PX=1. PY=2. PR=5. PT=35.";
    CHECK(passes(om100));
    CHECK(passes_like(om100, "CALL OM100 PX=-12.5 PY=2. PR=5. PT=35."));
    CHECK(passes_like(om100, "CALL OM100 PX=1. PY=+.5 PR=5. PT=35"));
    CHECK(passes_like("CALL OM100 PX= 1. PT=35.", "CALL OM100 PX= 7 PT=35."));
    CHECK_FALSE(passes_like(om100, "CALL OM100 PX=1.PY=2. PR=5. PT=35."));      // glued
    CHECK_FALSE(passes_like(om100, "CALL OM100 PX=1. PY=2.  PR=5. PT=35."));    // another blank
    CHECK_FALSE(passes_like(om100, "CALL OM101 PX=1. PY=2. PR=5. PT=35."));     // another macro
    CHECK_FALSE(passes_like(om100, "CALL OM100 PX=1. PY=2. PR=5. PT=35. N10"));
    CHECK_FALSE(passes_like(om100, "CALL OM100 PX=1.2.3 PY=2. PR=5. PT=35."));
    CHECK_FALSE(passes_like(om100, "CALL OM100 PX=1234567890123456 PY=2. PR=5. PT=35."));
    CHECK_FALSE(passes_like(om100, "CALL OM100 PX=VC1 PY=2. PR=5. PT=35."));
    CHECK_FALSE(passes_like("CALL O100 PX=1 (A=5 )", "CALL O100 PX=1 (A=5)"));
    // Random lines passed over, and random changes of them: every line it
    // says is like one passed over is passed over.
    std::mt19937 rng(20261207);
    const std::string value_bytes = "0123456789.+-";
    const std::string change_bytes = "0123456789.+-= PTNOEIF()V";
    const auto random_string = [&](const std::string& from, size_t max) {
        std::string s(rng() % (max + 1), ' ');
        for (char& c : s) c = from[rng() % from.size()];
        return s;
    };
    int like = 0;
    for (int i = 0; i < 20000; ++i) {
        std::string passed = "CALL OM100";
        for (int k = 0, n = 1 + static_cast<int>(rng() % 5); k < n; ++k)
            passed += std::string(" P") + "XYRTZ"[rng() % 5] + (rng() % 4 ? "=" : " = ") + random_string(value_bytes, 17);
        if (rng() % 8 == 0) passed += " (" + random_string(change_bytes, 6) + ")";
        if (!passes(passed)) continue;
        std::string text = passed;
        for (int k = 0, n = 1 + static_cast<int>(rng() % 3); k < n; ++k) {
            const size_t at = rng() % (text.size() + 1);
            text.replace(at, std::min<size_t>(rng() % 4, text.size() - at),
                         random_string(rng() % 3 ? value_bytes : change_bytes, 4));
        }
        if (!passes_like(passed, text)) continue;
        ++like;
        REQUIRE_MESSAGE(passes(text), passed << " -> " << text);
    }
    CHECK(like > 300);
}
