// Differential tests of the streaming front end and check (analyzer/frontend_fast.h,
// analyzer/stream.h) against the tree-sitter front end and check_text:
//
//   * every corpus and example program, the grammar's corpus inputs, generated
//     programs and randomly mutated programs (seeded): both front ends give
//     the same Blocks (operator==) and the same programs;
//   * the same inputs checked both ways give the same diagnostics, every field
//     (dump_result), whatever the chunk size the stream is read with;
//   * the streaming cases that need a program read again (a program name after
//     comment lines, RTS, jumps, N references, CALLs of later programs) and the
//     positions of CR LF / lone CR / non-ASCII text.
//
// No difference is tolerated. Lines with syntax errors agree because both
// front ends parse such a line on its own (frontend.h), so that tree-sitter's
// error recovery does not depend on the neighbouring lines.
#include <doctest/doctest.h>
#include <fcntl.h>
#include <unistd.h>

#include <algorithm>
#include <cstring>
#include <filesystem>
#include <map>
#include <fstream>
#include <random>
#include <sstream>
#include <string>
#include <vector>

#include "engine/analyzer.h"
#include "semantics/config.h"
#include "syntax/frontend.h"
#include "syntax/frontend_fast.h"
#include "osplint/osplint.h"
#include "engine/stream.h"

namespace fs = std::filesystem;
using namespace osplint;

namespace {

std::string read_all(const fs::path& p) {
    std::ifstream in(p, std::ios::binary);
    std::ostringstream ss;
    ss << in.rdbuf();
    return ss.str();
}

bool is_program_file(const fs::path& p) {
    std::string ext = p.extension().string();
    for (auto& c : ext) c = static_cast<char>(std::toupper(static_cast<unsigned char>(c)));
    return ext == ".MIN" || ext == ".SSB" || ext == ".SUB" || ext == ".LIB" || ext == ".NC" || ext == ".SDF" ||
           ext == ".MSB";
}

// Every program of the corpus, the examples, the rule fixtures and the
// front-end fixtures.
std::vector<fs::path> corpus_files() {
    std::vector<fs::path> out;
    const fs::path root(OSPLINT_SOURCE_DIR);
    for (const char* dir : {"tests/programs", "examples", "tests/rules", "tests/frontend"}) {
        if (!fs::exists(root / dir)) continue;
        for (const auto& e : fs::recursive_directory_iterator(root / dir))
            if (e.is_regular_file() && is_program_file(e.path())) out.push_back(e.path());
    }
    std::sort(out.begin(), out.end());
    return out;
}

// The inputs of the grammar's corpus tests (grammar/test/corpus/*.txt).
std::vector<std::string> grammar_inputs() {
    std::vector<std::string> out;
    const fs::path dir = fs::path(OSPLINT_SOURCE_DIR) / "grammar" / "test" / "corpus";
    if (!fs::exists(dir)) return out;
    std::vector<fs::path> files;
    for (const auto& e : fs::directory_iterator(dir))
        if (e.path().extension() == ".txt") files.push_back(e.path());
    std::sort(files.begin(), files.end());
    for (const auto& f : files) {
        const std::string text = read_all(f);
        std::istringstream in(text);
        std::string line;
        enum { Outside, Name, Input } state = Outside;
        std::string input;
        while (std::getline(in, line)) {
            const bool rule = line.size() >= 3 && line.find_first_not_of('=') == std::string::npos;
            const bool dashes = line.size() >= 3 && line.find_first_not_of('-') == std::string::npos;
            if (state == Outside && rule) {
                state = Name;
            } else if (state == Name && rule) {
                state = Input;
                input.clear();
            } else if (state == Input && dashes) {
                // The blank line before the dashes separates the input from them.
                if (!input.empty() && input.back() == '\n') input.pop_back();
                out.push_back(input);
                state = Outside;
            } else if (state == Input) {
                input += line + "\n";
            }
        }
    }
    return out;
}

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

Config config_for(const fs::path& file) {
    fs::path dir = file.parent_path();
    if (dir.empty()) dir = ".";
    if (auto f = find_config(dir)) return load_config(*f);
    return Config{};
}

// check_text and the streaming check, with several chunk sizes; every field
// of the results must agree.
void compare_checks(const std::string& name, const std::string& text, const Config& config,
                    const AnalysisOptions& options = {}, StreamStats* stats = nullptr) {
    const std::string expected = dump_result(check_text(name, text, config, options));
    for (size_t chunk : {size_t(1) << 20, size_t(1), size_t(7), size_t(4096)}) {
        StreamStats st;
        StreamOptions so;
        so.chunk_size = chunk;
        so.stats = &st;
        const std::string got = dump_result(check_text_fast(name, text, config, options, so));
        if (got != expected) {
            FAIL_CHECK(name << " (chunk " << chunk << ") differs\n-- check_text:\n"
                            << expected << "-- streaming:\n"
                            << got);
            return;
        }
        if (stats && chunk == (size_t(1) << 20)) *stats = st;
    }
}

// ------------------------------------------------------------- generation

// A deterministic generator of programs that use everything the streaming
// check handles differently: several programs, jumps and loops, RTS, N
// references, CALLs of programs defined later, directives, error lines, line
// ends of every kind, non-ASCII comments.
class Generator {
public:
    explicit Generator(uint32_t seed) : rng_(seed) {}

    std::string program() {
        std::string out;
        eol_ = pick({"\n", "\n", "\n", "\r\n", "\r"});
        if (chance(20)) line(out, "%");
        if (chance(15)) line(out, "$PART" + num(1, 99) + ".MIN%");
        for (int i = 0, n = static_cast<int>(range(0, 3)); i < n; ++i) line(out, comment());
        const int programs = static_cast<int>(range(1, 3));
        for (int p = 0; p < programs; ++p) {
            if (p > 0 || !chance(15)) line(out, "O" + pick({"1000", "SUB" + num(1, 3), "TEST", "8800", "ABC"}) +
                                                     (chance(30) ? " " + comment() : ""));
            const int blocks = static_cast<int>(range(3, 40));
            for (int b = 0; b < blocks; ++b) block(out);
            line(out, chance(50) ? "M30" : chance(50) ? "RTS" : chance(50) ? "M02" : "G0 Z100.");
        }
        if (chance(20)) line(out, "%");
        if (chance(25) && !out.empty()) out.erase(out.size() - eol_.size());  // no final line end
        return out;
    }

private:
    std::mt19937 rng_;
    std::string eol_ = "\n";

    uint32_t range(uint32_t lo, uint32_t hi) { return lo + rng_() % (hi - lo + 1); }
    bool chance(int percent) { return static_cast<int>(rng_() % 100) < percent; }
    std::string pick(std::initializer_list<std::string> options) {
        auto it = options.begin();
        std::advance(it, rng_() % options.size());
        return *it;
    }
    std::string num(int lo, int hi) { return std::to_string(range(static_cast<uint32_t>(lo), static_cast<uint32_t>(hi))); }
    std::string coord() {
        const int v = static_cast<int>(range(0, 200000)) - 100000;
        std::string s = std::to_string(std::abs(v) / 1000) + "." + std::to_string(std::abs(v) % 1000);
        if (chance(20)) s = std::to_string(std::abs(v) / 1000) + ".";
        if (chance(10)) s = "." + std::to_string(std::abs(v) % 1000);
        return (v < 0 ? "-" : "") + s;
    }
    std::string comment() {
        return pick({"(ROUGHING)", "(T1 D10 BALL)", "(\xE5\x88\x87\xE5\x89\x8A)", "(\x90\xD8\x8D\xED)",
                     "(osplint: disable=OSP004 -- ends elsewhere)", "(osplint: disable=OSP005)",
                     "(osplint: disable-file=OSP004)", "(osplint: disable=OSP999)", "(OPEN COMMENT", "()"});
    }
    void line(std::string& out, const std::string& l) { out += l + eol_; }

    void block(std::string& out) {
        std::string b;
        if (chance(10)) b += "/";
        if (chance(15)) b += "N" + pick({num(1, 50), "AT" + num(1, 3), "LOOP", "END" + num(1, 2)}) + " ";
        switch (rng_() % 22) {
            case 0: b += "G0 X" + coord() + " Y" + coord(); break;
            case 1: b += "G1 X" + coord() + " Y" + coord() + " Z" + coord() + " F" + num(100, 3000); break;
            case 2: b += "X" + coord() + "Y" + coord() + "Z" + coord(); break;
            case 3: b += "T" + num(1, 20) + " M6"; break;
            case 4: b += "G56 Z50. H" + num(1, 20) + " " + pick({"HA", "M8", ""}); break;
            case 5: b += "S" + num(100, 9000) + " M3"; break;
            case 6: b += "G81 Z" + coord() + " R3. F200"; break;
            case 7: b += "G80"; break;
            case 8: b += "CALL O" + pick({"SUB1", "SUB2", "KYOY", "ZAGR", "NOPE"}) + " PX=" + coord() + " PY=" + coord() +
                         " PR=2. PZ=-5." + (chance(30) ? " M52" : "");
                break;
            case 9: b += "MODIN OKYOY PR=2. PZ=-4. PI=20. PJ=8. PD=15 PF=250"; break;
            case 10: b += "MODOUT"; break;
            case 11: b += "VC" + num(1, 200) + "=" + pick({coord(), "VC1+1", "[VC2-3]*2", "-VC3/4", "PX"}); break;
            case 12: b += "X=VC1+" + coord() + " Y=-VC2"; break;
            case 13: b += "GOTO N" + num(1, 50); break;
            case 14: b += "IF [VC1 LT " + num(1, 9) + "] N" + num(1, 50); break;
            case 15: b += "WHILE [VC1 LT 3] DO1"; break;
            case 16: b += "END1"; break;
            case 17: b += "G85 N" + num(1, 50) + " D7"; break;
            case 18: b += comment(); break;
            case 19: b += pick({"G1 X10..5", "S15O0 M3", "X", "G1 X5 @", "CALL", "PX=", "#", "G0 X1 (C"}); break;
            case 20: b += "M" + pick({"5", "9", "1", "0", "843", "845", "204"}); break;
            default: b += "G" + pick({"17", "90", "91", "98", "99", "40", "41 D1", "15 H1", "30 P1"}); break;
        }
        if (chance(15)) b += " " + comment();
        if (chance(5)) b += "  ";
        line(out, b);
    }
};

// Random edits of a text: characters and tokens inserted, deleted, replaced;
// lines doubled, joined and split.
std::string mutate(std::string text, std::mt19937& rng) {
    static const char* const kTokens[] = {"G", "X", "N", "O", "V", "(", ")", "[", "]", "=", "-", "+", ".", "/",
                                          "*", ",", " ", "\t", "\n", "\r", "\r\n", "%", "$", "'", "#", "0", "5",
                                          "CALL ", "GOTO ", "IF ", "END", "DO", "RTS", "NCYL", "VC1", "PX", "EQ",
                                          "\xE3\x81\x82", "\x82\xA0", "\x01", "M30", "O1", "HA", "EMPTY", "SIN["};
    const int edits = 1 + static_cast<int>(rng() % 4);
    for (int k = 0; k < edits; ++k) {
        const size_t at = text.empty() ? 0 : rng() % (text.size() + 1);
        switch (rng() % 6) {
            case 0:
            case 1: text.insert(at, kTokens[rng() % (sizeof kTokens / sizeof *kTokens)]); break;
            case 2:
                if (at < text.size()) text.erase(at, 1 + rng() % 3);
                break;
            case 3:
                if (at < text.size()) text[at] = "GXYZ0123456789.-+=()[] \n"[rng() % 24];
                break;
            case 4: {  // double a line
                const size_t b = text.rfind('\n', at == 0 ? 0 : at - 1);
                const size_t s = b == std::string::npos ? 0 : b + 1;
                const size_t e = text.find('\n', s);
                if (e != std::string::npos) text.insert(s, text.substr(s, e - s + 1));
                break;
            }
            default: {  // join two lines
                const size_t nl = text.find('\n', at);
                if (nl != std::string::npos) text.erase(nl, 1);
                break;
            }
        }
    }
    return text;
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
          "(COMMENT ONLY)", "", "  \t", "n10 g1 x1 y2 z3 f100", "$HDR.MIN%"}) {
        const std::string text(line);
        CHECK_MESSAGE(p.parse_fast_only(LineRef{text, "\n", 1, 0}, b), line);
        const ProgramFile ts = parse_program_file("t.min", text + "\n");
        REQUIRE(ts.blocks.size() == 1);
        CHECK_MESSAGE(b == ts.blocks[0], line << "\n-- tree-sitter:\n" << dump_block(ts.blocks[0]) << "-- fast:\n"
                                              << dump_block(b));
    }
    // Outside the subset: parsed by tree-sitter, with the same result.
    for (const char* line : {"IF [VC1 LT 3] N10", "GOTO NSTOP", "X=SIN[30]", "PUT 'TEXT'", "S15O0 M3", "G1 X10..5",
                             "VUACM[1]='NO DATA'", "X5 @"}) {
        const std::string text(line);
        CHECK_FALSE_MESSAGE(p.parse(LineRef{text, "\n", 7, 100}, b), line);
        Block alone;
        parse_line_tree_sitter(LineRef{text, "\n", 7, 100}, alone);
        CHECK(b == alone);
        CHECK(b.line == 7);
        CHECK(b.range == ByteRange{100, 100 + static_cast<uint32_t>(text.size())});
    }
}

TEST_CASE("fast front end: generated programs") {
    size_t blocks = 0, files = 0;
    for (uint32_t seed = 1; seed <= 300; ++seed) {
        Generator g(seed);
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

TEST_CASE("streaming check: corpus, examples and fixtures give check_text's result") {
    const auto files = corpus_files();
    std::map<std::string, int> fixes;
    for (const auto& f : files) {
        const Config config = config_for(f);
        const std::string text = read_all(f);
        StreamStats stats;
        compare_checks(f.string(), text, config, {}, &stats);
        // Findings with fixes and notes read only the lines in hand.
        CHECK_MESSAGE(stats.source_loads == 0, f.string());
        for (const auto& d : check_text(f.string(), text, config).diagnostics)
            if (!d.fixes.empty()) ++fixes[d.rule];
        // With the program names of the directory, as the CLI passes them.
        ProgramNames names;
        for (const auto& e : fs::directory_iterator(f.parent_path()))
            if (e.is_regular_file() && is_program_file(e.path())) collect_program_names(read_all(e.path()), names);
        AnalysisOptions options;
        options.known_programs = &names;
        compare_checks(f.string(), text, config, options);
    }
    // The rules that read source text for their fixes had findings.
    for (const char* id : {"OSP104", "OSP207"}) CHECK_MESSAGE(fixes[id] > 0, id);
}

TEST_CASE("streaming check: a fix on the last line, without a line end, reads no more than the file") {
    for (const char* text : {"O1\r\nG0 X1. M843", "O1\nS500 M843\r\nM30", "O1\nS500 M843"}) {
        StreamStats stats;
        compare_checks("fix.min", text, Config{}, {}, &stats);
        CHECK(stats.source_loads == 0);
    }
}

TEST_CASE("streaming check: files, descriptors and pipes") {
    const fs::path file = fs::path(OSPLINT_SOURCE_DIR) / "examples" / "KEYWAY.MIN";
    const Config config = config_for(file);
    const std::string text = read_all(file);
    const std::string expected = dump_result(check_text(file.string(), text, config));
    CHECK(dump_result(check_file_fast(file.string(), config)) == expected);

    int fds[2];
    REQUIRE(::pipe(fds) == 0);
    REQUIRE(::write(fds[1], text.data(), text.size()) == static_cast<ssize_t>(text.size()));
    ::close(fds[1]);
    CHECK(dump_result(check_fd_fast(fds[0], file.string(), config)) == expected);
    ::close(fds[0]);

    REQUIRE(::pipe(fds) == 0);
    REQUIRE(::write(fds[1], text.data(), text.size()) == static_cast<ssize_t>(text.size()));
    ::close(fds[1]);
    std::string error;
    const int spooled = spool_to_temporary_file(fds[0], error);
    ::close(fds[0]);
    REQUIRE(spooled >= 0);
    ProgramNames names;
    CHECK(collect_program_names_fd(spooled, names));
    ProgramNames expected_names;
    collect_program_names(text, expected_names);
    CHECK(names == expected_names);
    CHECK(dump_result(check_fd_fast(spooled, file.string(), config)) == expected);
    ::close(spooled);

    const FileResult missing = check_file_fast("/nonexistent/NOPE.MIN", config);
    CHECK(missing.io_error == check_file("/nonexistent/NOPE.MIN", config).io_error);
    const FileResult dir = check_file_fast(OSPLINT_SOURCE_DIR, config);
    CHECK(dir.io_error == "is a directory");
}

TEST_CASE("streaming check: programs read again") {
    const Config config;
    StreamStats st;

    SUBCASE("a program name after the opening comment lines") {
        compare_checks("a.min", "(HEADER)\n\n%\nO1234\nG0 X1\nM30\n", config, {}, &st);
        CHECK(st.restarts == 1);
        CHECK(st.buffered_programs == 0);
    }
    SUBCASE("a file without a program name") {
        compare_checks("a.min", "(HEADER)\nG0 X1\nG0 X-1 (osplint: disable=OSP004)\n", config, {}, &st);
        CHECK(st.restarts == 0);
    }
    SUBCASE("an RTS makes the first program a subprogram") {
        compare_checks("a.min", "O1\nG81 Z-5. R2. F100\nX1.\nRTS\nO2\nG0 X0\nG81 Z-5. R2. F100\nM30\n", config, {},
                       &st);
        CHECK(st.restarts == 1);
    }
    SUBCASE("jumps and loops need the fixpoint") {
        compare_checks("a.min",
                       "O1\nVC1=0\nN1 G81 Z-5. R2. F100\nVC1=VC1+1\nIF [VC1 LT 3] N1\nG80\nGOTO NEND\nG0 X1\n"
                       "NEND M30\nO2\nWHILE [VC2 LT 2] DO1\nVC2=VC2+1\nEND1\nRTS\n",
                       config, {}, &st);
        CHECK(st.buffered_programs == 2);
    }
    SUBCASE("an N reference to a sequence name further down") {
        compare_checks("a.min", "O1\nG85 N10 D7\nG0 X0\nN10 G1 X5\nG85 NAT2 D7\nM30\n", config, {}, &st);
        CHECK(st.buffered_programs == 1);
    }
    SUBCASE("a CALL of a program defined later in the file") {
        compare_checks("a.min", "O1\nCALL OSUB1 PX=1\nCALL OMISSING\nM30\nOSUB1\nG0 X1\nRTS\n", config, {}, &st);
        CHECK(st.buffered_programs == 0);
    }
    SUBCASE("programs with the same name") {
        compare_checks("a.min", "O1\nX1 Y1 @\nM30\nO1\nX1 Y1 @\nRTS\nO1\nGOTO N9\nX1 Y1 @\nRTS\n", config);
    }
    SUBCASE("a subprogram library") {
        compare_checks("a.ssb", "OA\nG0 X1\nOB\nG81 Z-1. R1. F1\nRTS\n", config);
    }
    SUBCASE("findings on earlier lines, found again from a checkpoint") {
        std::string text = "O1\nG81 Z-5. R2. F100\n";
        for (int i = 0; i < 3000; ++i) text += "X" + std::to_string(i % 50) + ". Y1.\n";
        text += "M30\n";
        compare_checks("a.min", text, config);
    }
}

TEST_CASE("streaming check: suppression directives") {
    const Config config;
    compare_checks("s.min",
                   "(osplint: disable-file=OSP004 -- ends elsewhere)\nO1\n(osplint: disable=OSP005 -- on the control)\n"
                   "\nCALL OMISSING\nCALL ONOPE (osplint: disable=OSP005,OSP104)\n(osplint: disable=OSP999)\n"
                   "(osplint: disable=syntax-error)\n(osplint: enable=OSP1)\n(osplint: disable=OSP001)\nG1 X5 @\n"
                   "(osplint: disable=OSP104)\n",
                   config);
    Config all;
    all.rule_severity["OSP902"] = Severity::Info;
    compare_checks("s.min",
                   "O1 (osplint: disable=OSP004)\nG0 X1 (osplint: disable=OSP005, OSP104 -- not needed)\n"
                   "(osplint: disable=OSP104)\n",
                   all);
}

TEST_CASE("streaming check: positions on any line ending and text") {
    const Config config;
    for (const char* eol : {"\n", "\r\n", "\r"}) {
        std::string text;
        for (const char* l : {"O1 (\xE5\x88\x87\xE5\x89\x8A \xF0\x9F\x94\xA7)", "(\x90\xD8\x8D\xED) G81 Z-5. R2. F100",
                              "X1 Y1 @ (\xE3\x81\x82)", "CALL OMISSING PX=1", "\t G1 X5 (open"})
            text += std::string(l) + eol;
        compare_checks("p.min", text, config);
        compare_checks("p.min", text.substr(0, text.size() - std::strlen(eol)), config);  // no final line end
    }
    compare_checks("e.min", "", config);
    compare_checks("e.min", "\n\n\n", config);
    compare_checks("e.min", "\r\n", config);
}

TEST_CASE("streaming check: generated programs") {
    const Config config;
    for (uint32_t seed = 1; seed <= 300; ++seed) {
        Generator g(seed);
        const std::string text = g.program();
        compare_checks("gen" + std::to_string(seed) + (seed % 3 ? ".min" : ".ssb"), text, config);
    }
}

TEST_CASE("streaming check: randomly mutated corpus programs") {
    const auto files = corpus_files();
    std::vector<std::pair<fs::path, std::string>> texts;
    for (const auto& f : files) texts.emplace_back(f, read_all(f));
    std::mt19937 rng(11221);
    int compared = 0;
    for (int i = 0; i < 400; ++i) {
        const auto& [path, original] = texts[rng() % texts.size()];
        const std::string text = mutate(original, rng);
        compare_checks(path.string(), text, config_for(path));
        ++compared;
    }
    MESSAGE(compared << " mutated programs checked both ways");
}

// ------------------------------------------------------------- plain moves

namespace {

// Programs made mostly of plain moves (analyzer.h) in every modal state the
// streaming check treats differently: before and after G114/M204 and G80
// (spindle stopped), in and out of fixed cycles and MODIN, under G90 and G91,
// with sequence names (some repeated), moves beyond the travel limits, block
// delete, comments and shapes that are almost plain.
std::string plain_move_program(std::mt19937& rng) {
    auto pick = [&](std::initializer_list<std::string> options) {
        auto it = options.begin();
        std::advance(it, rng() % options.size());
        return *it;
    };
    auto coord = [&] {
        const int v = static_cast<int>(rng() % 900000) - 450000;
        return (v < 0 ? "-" : "") + std::to_string(std::abs(v) / 1000) + "." + std::to_string(std::abs(v) % 1000);
    };
    // Sometimes no program name: the first block with content, perhaps a plain
    // move, is then where the program starts (OSP004).
    std::string out = rng() % 5 ? "O" + pick({"1000", "2000", "TEST"}) + "\n" : "(NO NAME)\n";
    const int blocks = 20 + static_cast<int>(rng() % 80);
    for (int i = 0; i < blocks; ++i) {
        std::string b;
        if (rng() % 6 == 0) b += "N" + std::to_string(1 + rng() % 30) + pick({" ", ""});
        switch (rng() % 24) {
            case 0: b += "G114 R10. Z-21.5 P.7 F1200 FA=1320"; break;
            case 1: b += "M204"; break;
            case 2: b += "G80"; break;
            case 3: b += pick({"M3", "M4", "M5", "S1000 M3"}); break;
            case 4: b += pick({"G90", "G91", "G17", "G18", "G20", "G21"}); break;
            case 5: b += "G81 Z" + coord() + " R3. F200"; break;
            case 6: b += "MODIN OKYOY PR=2. PZ=-4. PI=20. PJ=8. PD=15 PF=250"; break;
            case 7: b += "MODOUT"; break;
            case 8: b += "CALL OZAGR PX=" + coord() + " PR=2. PZ=-5."; break;
            case 9: b += pick({"G56 Z50. H1", "G15 H1", "G53", "NCYL X1.", "G60 X2.", "VC1=" + coord()}); break;
            case 10: b += pick({"X=VC1", "/X" + coord(), "X" + coord() + " (MOVE)", "x" + coord() + " y" + coord(),
                                "G1 X" + coord() + " S500", "G4 X1.", "G02 X1 I2", "G01X1.Y2.Z3.", "X1.2.3",
                                "G1.5 X1", "G+1 X" + coord(), "G-1 X1", "M8 X1"});
                break;
            default:
                b += pick({"", "", "G0 ", "G1 ", "G2 ", "G3 ", "G01 ", "G00 "});
                for (const char* a : {"X", "Y", "Z"})
                    if (rng() % 3) b += std::string(a) + coord() + pick({" ", "", "  ", "\t"});
                if (rng() % 4 == 0) b += "F" + std::to_string(100 + rng() % 3000);
                if (b.empty() || b.back() == ' ') b += "Z" + coord();
                break;
        }
        out += b + "\n";
    }
    out += pick({"M30", "G0 Z100.", "M02"}) + "\n";
    return out;
}

}  // namespace

TEST_CASE("plain moves: apply_plain_move is apply_block on them") {
    std::mt19937 rng(4242);
    FastLineParser parser;
    Block b;
    Config config;
    int plain = 0;
    for (int i = 0; i < 3000; ++i) {
        const std::string text = plain_move_program(rng);
        size_t start = 0;
        uint32_t line = 1;
        while (start < text.size()) {
            const size_t end = text.find('\n', start);
            const LineRef l{std::string_view(text).substr(start, end - start), "\n", line++,
                            static_cast<uint32_t>(start)};
            start = end + 1;
            parser.parse(l, b);
            const bool is_plain = is_plain_move_block(b);
            // The parser's answer is never wrong when it says yes.
            if (parser.last_plain()) CHECK_MESSAGE(is_plain, l.text);
            if (!is_plain) continue;
            ++plain;
            ModalState s = initial_state(config, rng() % 4 == 0);
            s.cycle = Val<std::optional<ActiveCycle>>::of(std::nullopt);
            s.modin = Val<std::optional<ActiveModin>>::of(std::nullopt);
            switch (rng() % 3) {
                case 0: s.distance = Val<Distance>::of(Distance::Absolute); break;
                case 1: s.distance = Val<Distance>::of(Distance::Incremental); break;
                default: s.distance = {}; break;
            }
            if (rng() % 2) s.x = Val<double>::of(static_cast<double>(rng() % 100));
            if (rng() % 2) s.z = Val<double>::of(-static_cast<double>(rng() % 100));
            if (rng() % 2) s.motion = Val<int>::of(60);
            REQUIRE(plain_move_state(s));
            ModalState full = s, fast = s;
            apply_block(b, nullptr, config.catalog, full);
            apply_plain_move(b, fast);
            CHECK_MESSAGE(full == fast, l.text);
            CHECK_FALSE(resolve_call(b, s, config.catalog).has_value());
        }
    }
    CHECK(plain > 10000);
}

TEST_CASE("streaming check: plain moves in every modal state give check_text's result") {
    Config config;
    config.travel['X'] = TravelLimit{-300, 300};
    config.travel['Y'] = TravelLimit{-200, 200};
    config.travel['Z'] = TravelLimit{-300, 100};
    std::mt19937 rng(777);
    std::map<std::string, int> seen;
    for (int i = 0; i < 400; ++i) {
        const std::string text = plain_move_program(rng);
        compare_checks("plain" + std::to_string(i) + ".min", text, config);
        for (const auto& d : check_text("p.min", text, config).diagnostics) ++seen[d.rule];
    }
    // The rules that look at plain moves had findings to compare.
    for (const char* id : {"OSP003", "OSP004", "OSP212", "OSP301"}) CHECK_MESSAGE(seen[id] > 0, id);
}

TEST_CASE("plain moves: a G0..G3 registered as a macro turns the shortcut off") {
    Config config;
    CHECK(plain_moves_possible(config.catalog));
    Config shop = parse_config("[macros.gcode]\nG1 = \"OZAGR\"\n", "osplint.toml");
    CHECK_FALSE(plain_moves_possible(shop.catalog));
    // `G1 X20.` has the shape of a plain move, but here it calls OZAGR (OSP101).
    compare_checks("shop.min", "O1\nG0 X0 Y0 Z50.\nG1 X10. PR=2. PZ=-5.\nG1 X20.\nM30\n", shop);
    CHECK_FALSE(check_text("shop.min", "O1\nG0 X0 Y0 Z50.\nG1 X20.\nM30\n", shop).diagnostics.empty());
}

TEST_CASE("OSP003: beyond the names it keeps, numeric duplicates are still found") {
    // 100,010 numbered blocks: the first 100,000 names keep their place for
    // the note, later numeric ones only a bit.
    std::string text = "O1\n";
    for (int i = 1; i <= 100010; ++i) text += "N" + std::to_string(i) + " G0 X" + std::to_string(i % 50) + ".\n";
    text += "N5 X1.\nN100005 X2.\nNSTOP X3.\nNSTOP X4.\nN00005 X5.\nN100011 X6.\nM30\n";
    AnalysisOptions options;
    options.only_rules = {"OSP003"};
    const FileResult r = check_text_fast("dup.min", text, Config{}, options);
    REQUIRE(r.diagnostics.size() == 3);
    CHECK(r.diagnostics[0].message.find("N5 ") != std::string::npos);
    REQUIRE(r.diagnostics[0].notes.size() == 1);
    REQUIRE(r.diagnostics[0].notes[0].range.has_value());
    CHECK(r.diagnostics[0].notes[0].range->start.line == 6);
    CHECK(r.diagnostics[1].message.find("N100005 ") != std::string::npos);
    REQUIRE(r.diagnostics[1].notes.size() == 1);
    CHECK_FALSE(r.diagnostics[1].notes[0].range.has_value());
    CHECK(r.diagnostics[2].message.find("NSTOP ") != std::string::npos);
    REQUIRE(r.diagnostics[2].notes[0].range.has_value());
    CHECK(r.diagnostics[2].notes[0].range->start.line == 100014);
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
