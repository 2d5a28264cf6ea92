// The manuals and their sections (see citations.h). Headings are the
// manuals' own, in English; the Japanese heading is kept beside each for
// docs/manuals.md. Line spans follow the manuals as numbered by the catalog.
#include "catalog/citations.h"

#include <array>
#include <charconv>
#include <stdexcept>

namespace osplint {

namespace {

constexpr std::array kManuals = {
    Manual{"back-counterboring", "000", "Back counterboring macros manual", "OSP5020M 裏ザグリ用サブプログラム",
           "OG87EX", "2001-07-30",
           "back counterboring and back chamfering with special tools: OG87C, OG87N, OG87K, OG87M (MODIN), "
           "OZAGR and OM100 (CALL)"},
    Manual{"wall-finishing", "001", "Vertical wall finishing manual", "OSP5020M 縦壁仕上げ機能(２)", "OLAAPEX",
           "2003-08-30",
           "plunge-cut finishing of deep vertical walls: OLPEX and OLPEY, successors of OLAPX and OLAPY (which "
           "its example program calls)"},
    Manual{"keyway", "002", "Keyway macros manual", "OSP5020M キー溝加工用マクロ", "KEYMIL", "2001-08-30",
           "keyway milling with an end mill: OKYOX/OKYOY (closed long slot) and OKYLX/OKYLY (open through slot)"},
    Manual{"tap-cycle", "003", "Tap cycle (2) manual", "OSP5020M タップサイクル(２)", "OG84L", "2001-12-30",
           "the tapping cycle OG84L for tappers with a built-in automatic reverse, registered as G114 and "
           "cancelled by G80 or M204 (OC84L)"},
    Manual{"fixed-cycles", "004", "Fixed cycles manual", "固定サイクル", "", "",
           "the control's fixed cycles: the I, R and Z points, G77, G78, G81 to G88, G80, G98/G99 and G100"},
};

constexpr std::array kSections = {
    // Back counterboring macros manual (OG87EX)
    ManualSection{"back-counterboring/function", "Function", "機能", 1, 15},
    ManualSection{"back-counterboring/common", "Common rules", "共通規則", 16, 59},
    ManualSection{"back-counterboring/common-1", "Common rules (1)", "共通規則 (1)", 18, 20},
    ManualSection{"back-counterboring/common-2", "Common rules (2)", "共通規則 (2)", 22, 24},
    ManualSection{"back-counterboring/common-3", "Common rules (3)", "共通規則 (3)", 26, 30},
    ManualSection{"back-counterboring/common-4", "Common rules (4)", "共通規則 (4)", 32, 36},
    ManualSection{"back-counterboring/common-5", "Common rules (5)", "共通規則 (5)", 38, 40},
    ManualSection{"back-counterboring/common-6", "Common rules (6)", "共通規則 (6)", 42, 44},
    ManualSection{"back-counterboring/common-7", "Common rules (7)", "共通規則 (7)", 46, 46},
    ManualSection{"back-counterboring/common-8", "Common rules (8)", "共通規則 (8)", 48, 52},
    ManualSection{"back-counterboring/common-9", "Common rules (9)", "共通規則 (9)", 54, 56},
    ManualSection{"back-counterboring/plane", "Plane designation", "平面指定", 60, 76},
    ManualSection{"back-counterboring/errors", "Errors during program execution", "プログラム実行中のエラー", 77,
                  103},
    ManualSection{"back-counterboring/other-notes", "Other notes", "その他の注意事項", 104, 120},
    ManualSection{"back-counterboring/other-notes-1", "Other notes (1)", "その他の注意事項 (1)", 105, 107},
    ManualSection{"back-counterboring/other-notes-2", "Other notes (2)", "その他の注意事項 (2)", 108, 120},
    ManualSection{"back-counterboring/og87c", "OG87C (notched single-point cutter)", "切欠き付きシングルポイントカッタ用",
                  121, 242},
    ManualSection{"back-counterboring/og87c-overview", "OG87C: Overview", "概要", 121, 135},
    ManualSection{"back-counterboring/og87c-format", "OG87C: Command format", "指令フォーマット", 136, 144},
    ManualSection{"back-counterboring/og87c-args", "OG87C: Argument list", "引数リスト", 145, 183},
    ManualSection{"back-counterboring/og87c-notes", "OG87C: Argument list, notes", "注", 184, 192},
    ManualSection{"back-counterboring/og87c-action", "OG87C: Action sequence", "動作順序", 193, 242},
    ManualSection{"back-counterboring/og87n", "OG87N (Nikken back-counterbore cutter)", "", 243, 359},
    ManualSection{"back-counterboring/og87n-overview", "OG87N: Overview", "概要", 243, 255},
    ManualSection{"back-counterboring/og87n-format", "OG87N: Command format", "指令フォーマット", 256, 264},
    ManualSection{"back-counterboring/og87n-args", "OG87N: Argument list", "引数リスト", 265, 297},
    ManualSection{"back-counterboring/og87n-notes", "OG87N: Argument list, notes", "注", 298, 312},
    ManualSection{"back-counterboring/og87n-action", "OG87N: Action sequence", "動作順序", 313, 359},
    ManualSection{"back-counterboring/og87k", "OG87K (Kuroda back-counterbore cutter)", "", 360, 454},
    ManualSection{"back-counterboring/og87k-overview", "OG87K: Overview", "概要", 360, 374},
    ManualSection{"back-counterboring/og87k-format", "OG87K: Command format", "指令フォーマット", 375, 381},
    ManualSection{"back-counterboring/og87k-args", "OG87K: Argument list", "引数リスト", 382, 410},
    ManualSection{"back-counterboring/og87k-notes", "OG87K: Argument list, notes", "注", 411, 433},
    ManualSection{"back-counterboring/og87k-action", "OG87K: Action sequence", "動作順序", 434, 454},
    ManualSection{"back-counterboring/og87m", "OG87M (Kumeda back-counterbore cutter)", "", 455, 551},
    ManualSection{"back-counterboring/og87m-overview", "OG87M: Overview", "概要", 455, 469},
    ManualSection{"back-counterboring/og87m-format", "OG87M: Command format", "指令フォーマット", 470, 476},
    ManualSection{"back-counterboring/og87m-args", "OG87M: Argument list", "引数リスト", 477, 505},
    ManualSection{"back-counterboring/og87m-notes", "OG87M: Argument list, notes", "注", 506, 526},
    ManualSection{"back-counterboring/og87m-action", "OG87M: Action sequence", "動作順序", 527, 551},
    ManualSection{"back-counterboring/ozagr", "OZAGR (BIG back-counterbore bar)", "", 552, 648},
    ManualSection{"back-counterboring/ozagr-overview", "OZAGR: Overview", "概要", 552, 558},
    ManualSection{"back-counterboring/ozagr-format", "OZAGR: Command format", "指令フォーマット", 559, 565},
    ManualSection{"back-counterboring/ozagr-args", "OZAGR: Argument list", "引数リスト", 566, 596},
    ManualSection{"back-counterboring/ozagr-action", "OZAGR: Action sequence", "動作順序", 597, 628},
    ManualSection{"back-counterboring/ozagr-notes", "OZAGR: Notes", "注", 629, 648},
    ManualSection{"back-counterboring/om100", "OM100 (Burraway back chamfering)", "", 649, 747},
    ManualSection{"back-counterboring/om100-overview", "OM100: Overview", "概要", 649, 659},
    ManualSection{"back-counterboring/om100-format", "OM100: Command format", "指令フォーマット", 660, 669},
    ManualSection{"back-counterboring/om100-args", "OM100: Argument list", "引数リスト", 670, 700},
    ManualSection{"back-counterboring/om100-action", "OM100: Action sequence", "動作順序", 701, 747},

    // Vertical wall finishing manual (OLAAPEX)
    ManualSection{"wall-finishing/function", "Function", "機能", 1, 22},
    ManualSection{"wall-finishing/cautions", "Common rules: Cautions", "共通規則 注意事項", 23, 60},
    ManualSection{"wall-finishing/cautions-1", "Cautions (1)", "注意事項 (1)", 26, 26},
    ManualSection{"wall-finishing/cautions-2", "Cautions (2)", "注意事項 (2)", 27, 29},
    ManualSection{"wall-finishing/cautions-3", "Cautions (3)", "注意事項 (3)", 31, 33},
    ManualSection{"wall-finishing/cautions-4", "Cautions (4)", "注意事項 (4)", 35, 37},
    ManualSection{"wall-finishing/cautions-5", "Cautions (5)", "注意事項 (5)", 39, 41},
    ManualSection{"wall-finishing/cautions-6", "Cautions (6)", "注意事項 (6)", 43, 43},
    ManualSection{"wall-finishing/cautions-7", "Cautions (7)", "注意事項 (7)", 45, 47},
    ManualSection{"wall-finishing/cautions-8", "Cautions (8)", "注意事項 (8)", 49, 53},
    ManualSection{"wall-finishing/cautions-9", "Cautions (9)", "注意事項 (9)", 55, 57},
    ManualSection{"wall-finishing/plane", "Plane designation", "平面指定", 61, 87},
    ManualSection{"wall-finishing/errors", "Errors during program execution", "プログラム実行中のエラー", 88, 104},
    ManualSection{"wall-finishing/other-notes", "Other notes", "その他の注意事項", 105, 123},
    ManualSection{"wall-finishing/other-notes-1", "Other notes (1)", "その他の注意事項 (1)", 109, 111},
    ManualSection{"wall-finishing/other-notes-2", "Other notes (2)", "その他の注意事項 (2)", 112, 123},
    ManualSection{"wall-finishing/olpex", "OLPEX / OLPEY", "", 124, 275},
    ManualSection{"wall-finishing/olpex-overview", "OLPEX / OLPEY: Overview", "概要", 124, 138},
    ManualSection{"wall-finishing/olpex-format", "OLPEX / OLPEY: Command format", "指令フォーマット", 139, 158},
    ManualSection{"wall-finishing/olpex-args", "OLPEX / OLPEY: Argument list", "引数リスト", 159, 199},
    ManualSection{"wall-finishing/olpex-notes", "OLPEX / OLPEY: Argument list, notes", "注", 200, 266},
    ManualSection{"wall-finishing/olpex-travel", "OLPEX / OLPEY: Direction of travel on a horizontal spindle",
                  "横軸時の進行方向", 267, 275},
    ManualSection{"wall-finishing/reference", "Reference material: Example of subprogram use (OLAPX)",
                  "参考資料 サブプログラム使用例（ＯＬＡＰＸの場合）", 276, 349},

    // Keyway macros manual (KEYMIL)
    ManualSection{"keyway/function", "Function", "機能", 1, 30},
    ManualSection{"keyway/cautions", "Common rules: Cautions", "共通規則 注意事項", 31, 65},
    ManualSection{"keyway/cautions-1", "Cautions (1)", "注意事項 (1)", 34, 34},
    ManualSection{"keyway/cautions-2", "Cautions (2)", "注意事項 (2)", 36, 38},
    ManualSection{"keyway/cautions-3", "Cautions (3)", "注意事項 (3)", 40, 42},
    ManualSection{"keyway/cautions-4", "Cautions (4)", "注意事項 (4)", 44, 46},
    ManualSection{"keyway/cautions-5", "Cautions (5)", "注意事項 (5)", 48, 50},
    ManualSection{"keyway/cautions-6", "Cautions (6)", "注意事項 (6)", 52, 52},
    ManualSection{"keyway/cautions-7", "Cautions (7)", "注意事項 (7)", 54, 56},
    ManualSection{"keyway/cautions-8", "Cautions (8)", "注意事項 (8)", 58, 60},
    ManualSection{"keyway/plane", "Plane designation", "平面指定", 66, 85},
    ManualSection{"keyway/errors", "Errors during program execution", "プログラム実行中のエラー", 86, 106},
    ManualSection{"keyway/other-notes", "Other notes", "その他の注意事項", 107, 137},
    ManualSection{"keyway/other-notes-1", "Other notes (1)", "その他の注意事項 (1)", 109, 113},
    ManualSection{"keyway/other-notes-2", "Other notes (2)", "その他の注意事項 (2)", 114, 137},
    ManualSection{"keyway/okyox", "OKYOX / OKYOY (long slot)", "長穴用", 138, 250},
    ManualSection{"keyway/okyox-overview", "OKYOX / OKYOY: Overview", "概要", 138, 154},
    ManualSection{"keyway/okyox-format", "OKYOX / OKYOY: Command format", "指令フォーマット", 155, 176},
    ManualSection{"keyway/okyox-args", "OKYOX / OKYOY: Argument list", "引数リスト", 177, 205},
    ManualSection{"keyway/okyox-notes", "OKYOX / OKYOY: Argument list, notes", "注", 206, 227},
    ManualSection{"keyway/okyox-action", "OKYOX / OKYOY: Action sequence", "動作順序", 228, 250},
    ManualSection{"keyway/okylx", "OKYLX / OKYLY (through slot)", "抜き溝用", 251, 382},
    ManualSection{"keyway/okylx-overview", "OKYLX / OKYLY: Overview", "概要", 251, 289},
    ManualSection{"keyway/okylx-format", "OKYLX / OKYLY: Command format", "指令フォーマット", 290, 301},
    ManualSection{"keyway/okylx-args", "OKYLX / OKYLY: Argument list", "引数リスト", 302, 337},
    ManualSection{"keyway/okylx-notes", "OKYLX / OKYLY: Argument list, notes", "注", 338, 353},
    ManualSection{"keyway/okylx-action", "OKYLX / OKYLY: Action sequence", "動作順序", 354, 379},
    ManualSection{"keyway/okylx-caution", "OKYLX / OKYLY: Caution", "ご注意", 380, 382},
    ManualSection{"keyway/okyox-gcode", "OKYOX / OKYOY: Command format as a G-code macro", "", 383, 402},

    // Tap cycle (2) manual (OG84L)
    ManualSection{"tap-cycle/function", "Function", "機能", 1, 17},
    ManualSection{"tap-cycle/format", "Command format", "指令フォーマット", 18, 39},
    ManualSection{"tap-cycle/conditions", "Conditions of use", "使用条件等", 40, 49},
    ManualSection{"tap-cycle/args", "Argument list", "引数リスト", 50, 73},
    ManualSection{"tap-cycle/cautions", "Cautions", "注意事項", 74, 114},
    ManualSection{"tap-cycle/cautions-1", "Cautions (1)", "注意事項 (1)", 76, 83},
    ManualSection{"tap-cycle/cautions-2", "Cautions (2)", "注意事項 (2)", 84, 85},
    ManualSection{"tap-cycle/cautions-3", "Cautions (3)", "注意事項 (3)", 86, 89},
    ManualSection{"tap-cycle/cautions-4", "Cautions (4)", "注意事項 (4)", 90, 91},
    ManualSection{"tap-cycle/cautions-5", "Cautions (5)", "注意事項 (5)", 92, 96},
    ManualSection{"tap-cycle/cautions-6", "Cautions (6)", "注意事項 (6)", 97, 98},
    ManualSection{"tap-cycle/cautions-7", "Cautions (7)", "注意事項 (7)", 99, 102},
    ManualSection{"tap-cycle/cautions-8", "Cautions (8)", "注意事項 (8)", 103, 108},
    ManualSection{"tap-cycle/cautions-9", "Cautions (9)", "注意事項 (9)", 109, 114},
    ManualSection{"tap-cycle/action", "Action sequence", "動作順序", 115, 132},
    ManualSection{"tap-cycle/plane", "Plane designation", "平面指定", 133, 142},
    ManualSection{"tap-cycle/errors", "Errors during program execution", "プログラム実行中のエラー", 143, 164},
    ManualSection{"tap-cycle/differences", "Reference material: Differences from the fixed cycles",
                  "参考資料 固定サイクルとの相違点", 165, 195},
    ManualSection{"tap-cycle/technical", "Technical data", "技術資料", 196, 286},
    ManualSection{"tap-cycle/tappers", "Auto-reverse tappers: characteristics and cautions",
                  "自動逆転タッパーの特徴と本プログラムの使用時の注意事項", 287, 337},

    // Fixed cycles manual
    ManualSection{"fixed-cycles/about", "About fixed cycles", "固定サイクルについて", 1, 22},
    ManualSection{"fixed-cycles/basic", "Basic motion", "基本動作", 4, 10},
    ManualSection{"fixed-cycles/g91", "Cautions: programming in G91", "注意事項 G91インクレメンタル指令", 11, 16},
    ManualSection{"fixed-cycles/alarms", "Cautions: examples of resolving alarms", "注意事項 アラーム発生の解決事例", 17,
                  22},
    ManualSection{"fixed-cycles/list", "Fixed cycle list", "固定サイクル一覧", 23, 45},
    ManualSection{"fixed-cycles/g77", "G77 Step & pick cycle", "G77 ステップ&ピックサイクル", 46, 65},
    ManualSection{"fixed-cycles/g78", "G78 Variable pick cycle", "G78 可変ピックサイクル", 66, 84},
    ManualSection{"fixed-cycles/g81", "G81 Drill cycle (spot drill)", "G81 ドリルサイクル(スポットドリル)", 85, 100},
    ManualSection{"fixed-cycles/g82", "G82 Drill cycle (counterboring)", "G82 ドリルサイクル(カウンターボーリング)", 101,
                  118},
    ManualSection{"fixed-cycles/g83", "G83 Pick cycle", "G83 ピックサイクル", 119, 162},
    ManualSection{"fixed-cycles/g87", "G87 Step cycle", "G87 ステップサイクル", 163, 181},
    ManualSection{"fixed-cycles/g84", "G84 Tap cycle", "G84 タップサイクル", 182, 224},
    ManualSection{"fixed-cycles/g84-normal", "G84 Tap cycle: normal tap", "ノーマルタップ", 188, 201},
    ManualSection{"fixed-cycles/g84-sync", "G84 Tap cycle: synchronized tap", "同期タップ", 202, 224},
    ManualSection{"fixed-cycles/g85", "G85 Boring cycle (reamer)", "G85 ボーリングサイクル(リーマ)", 225, 242},
    ManualSection{"fixed-cycles/g86", "G86 Boring cycle", "G86 ボーリングサイクル", 243, 257},
    ManualSection{"fixed-cycles/g88", "G88 Fine boring cycle", "G88 (ファインボーリングサイクル)", 258, 282},
    ManualSection{"fixed-cycles/g100", "G100 Drilling ignore", "G100 穴あけ無視", 283, 287},
};

std::string_view manual_key(std::string_view section_key) {
    return section_key.substr(0, section_key.find('/'));
}

// The manual number and the first range of "004:L182-223" (or
// "000:L26-30, L42"); `last` is `line` when the first item is one line.
bool parse_source(std::string_view source, std::string_view& number, int& line, int& last) {
    std::size_t colon = source.find(':');
    if (colon == std::string_view::npos || colon + 2 > source.size() || source[colon + 1] != 'L') return false;
    number = source.substr(0, colon);
    const char* begin = source.data() + colon + 2;
    const char* end = source.data() + source.size();
    auto [ptr, ec] = std::from_chars(begin, end, line);
    if (ec != std::errc() || ptr == begin) return false;
    last = line;
    if (ptr != end && *ptr == '-') {
        auto [ptr2, ec2] = std::from_chars(ptr + 1, end, last);
        if (ec2 != std::errc() || last < line) last = line;
    }
    return true;
}

}  // namespace

std::span<const Manual> manuals() { return kManuals; }
std::span<const ManualSection> manual_sections() { return kSections; }

const Manual* find_manual(std::string_view key) {
    for (const auto& m : kManuals)
        if (m.key == key || m.number == key) return &m;
    return nullptr;
}

const ManualSection* find_section(std::string_view key) {
    for (const auto& s : kSections)
        if (s.key == key) return &s;
    return nullptr;
}

const Manual& manual_of(const ManualSection& section) {
    const Manual* m = find_manual(manual_key(section.key));
    if (!m) throw std::out_of_range("citation section of no manual: " + std::string(section.key));
    return *m;
}

std::string cite_heading(std::string_view key) {
    const ManualSection* s = find_section(key);
    if (!s) throw std::out_of_range("unknown citation key: " + std::string(key));
    return "\"" + std::string(s->heading) + "\"";
}

std::string cite(std::string_view key) {
    if (key.find('/') == std::string_view::npos) {
        if (const Manual* m = find_manual(key)) return std::string(m->title);
        throw std::out_of_range("unknown citation key: " + std::string(key));
    }
    const ManualSection* s = find_section(key);
    if (!s) throw std::out_of_range("unknown citation key: " + std::string(key));
    return std::string(manual_of(*s).title) + ", \"" + std::string(s->heading) + "\"";
}

std::string cite(std::initializer_list<std::string_view> keys) {
    // Sections of one manual in a row share its title:
    // `Fixed cycles manual, "Basic motion", "Cautions: ..."`.
    std::string out;
    std::string_view last_manual;
    for (auto k : keys) {
        const ManualSection* s = find_section(k);
        if (s && !out.empty() && manual_key(s->key) == last_manual) {
            out += ", " + cite_heading(k);
            continue;
        }
        out += (out.empty() ? "" : "; ") + cite(k);
        last_manual = s ? manual_key(s->key) : std::string_view();
    }
    return out;
}

const ManualSection* section_at(std::string_view source) {
    std::string_view number;
    int line = 0, last = 0;
    if (!parse_source(source, number, line, last)) return nullptr;
    const Manual* m = find_manual(number);
    if (!m) return nullptr;
    // The innermost section holding the whole first range. A range over
    // several sections (a whole manual) has none: the manual is cited alone.
    const ManualSection* best = nullptr;
    for (const auto& s : kSections) {
        if (manual_key(s.key) != m->key || line < s.first_line || last > s.last_line) continue;
        if (!best || s.last_line - s.first_line < best->last_line - best->first_line) best = &s;
    }
    return best;
}

std::string cite_source(std::string_view source) {
    const ManualSection* s = section_at(source);
    return s ? cite(s->key) : std::string();
}

}  // namespace osplint
