// Programs for the differential tests and the fuzzer's seeds: the corpus,
// generated programs, random mutations.
#pragma once

#include <algorithm>
#include <filesystem>
#include <fstream>
#include <random>
#include <sstream>
#include <string>
#include <vector>

#include "support/text.h"

namespace osplint::testing {

namespace fs = std::filesystem;

inline std::string read_all(const fs::path& p) {
    std::ifstream in(p, std::ios::binary);
    std::ostringstream ss;
    ss << in.rdbuf();
    return ss.str();
}

inline bool is_program_path(const fs::path& p) { return is_program_file(p.string()); }

// Every program of the corpus, the examples, the rule fixtures and the
// front-end fixtures.
inline std::vector<fs::path> corpus_files() {
    std::vector<fs::path> out;
    const fs::path root(OSPLINT_SOURCE_DIR);
    for (const char* dir : {"tests/programs", "examples", "tests/rules", "tests/frontend"}) {
        if (!fs::exists(root / dir)) continue;
        for (const auto& e : fs::recursive_directory_iterator(root / dir))
            if (e.is_regular_file() && is_program_path(e.path())) out.push_back(e.path());
    }
    std::sort(out.begin(), out.end());
    return out;
}

// The inputs of the grammar's corpus tests (grammar/test/corpus/*.txt).
inline std::vector<std::string> grammar_inputs() {
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

// A deterministic generator of programs that use everything the streaming
// check handles differently: several programs, jumps and loops, RTS, N
// references, CALLs of programs defined later, directives, error lines, line
// ends of every kind, non-ASCII comments.
class Generator {
public:
    // `conditions`: jumps and loops in every form the front ends read (keyword
    // operators, IF ... GOTO, DO/END with and without a blank); otherwise
    // the few forms the engine's differential tests were tuned with.
    explicit Generator(uint32_t seed, bool conditions = false) : rng_(seed), conditions_(conditions) {}

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
    bool conditions_ = false;
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
            case 14:
                if (!conditions_) {
                    b += "IF [VC1 LT " + num(1, 9) + "] N" + num(1, 50);
                    break;
                }
                b += "IF [" + pick({"VC1 LT " + num(1, 9), "VC2 GE VC1*2 AND VC3 NE 0", "[VC1 EQ 1] OR [VC2 GT -1]",
                                   "VC1 EOR VC2", "-VC4 LE 2 OR VC5 EQ VC6 AND VC7 GT 1"}) +
                     "] " + pick({"", "GOTO "}) + "N" + num(1, 50);
                break;
            case 15: b += "WHILE [VC1 LT 3] " + (conditions_ ? pick({"DO1", "DO 1", "DO 2"}) : "DO1"); break;
            case 16: b += conditions_ ? pick({"END1", "END 1", "END 2", "DO 2", "END"}) : "END1"; break;
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
inline std::string mutate(std::string text, std::mt19937& rng) {
    static const char* const kTokens[] = {"G", "X", "N", "O", "V", "(", ")", "[", "]", "=", "-", "+", ".", "/",
                                          "*", ",", " ", "\t", "\n", "\r", "\r\n", "%", "$", "'", "#", "0", "5",
                                          "CALL ", "GOTO ", "IF ", "END", "DO", "RTS", "NCYL", "VC1", "PX", "EQ", " LT ", " AND ",
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

// Programs made mostly of plain moves (analyzer.h) in every modal state the
// streaming check treats differently: before and after G114/M204 and G80
// (spindle stopped), in and out of fixed cycles and MODIN, under G90 and G91,
// with sequence names (some repeated), moves beyond the travel limits, block
// delete, comments and shapes that are almost plain.
inline std::string plain_move_program(std::mt19937& rng) {
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

}  // namespace osplint::testing
