// The lexical layer of the fast front end (frontend_fast.h): character
// classes, numbers scanned and valued in one pass, the scanner's keyword
// classes, and the storage reuse of the parser. Shared by its files:
//
//   frontend_fast_parser.h     the parser's state and utilities (FastLineParser::Impl)
//   frontend_fast.cpp          block items, the line prefix, whole lines
//   frontend_fast_expr.cpp     expressions
//   frontend_fast_run.cpp      runs of plain moves (plain_run), with the quick
//                              check of frontend_fast_quick.h
//   frontend_fast_block.cpp    offsets of a block, the tree-sitter fallback
//                              for one line, dump_block, parse_program_file_fast
#pragma once

#include <array>
#include <cstdint>
#include <cstring>
#include <limits>
#include <optional>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

#include "syntax/frontend.h"
#include "syntax/model.h"

#if defined(__GNUC__)
#define OSPLINT_HOT inline __attribute__((always_inline))
#else
#define OSPLINT_HOT inline
#endif

namespace osplint::fast_detail {

inline constexpr uint32_t kNameMax = 32;  // NAME_MAX_LEN of the scanner

inline bool is_letter(char c) { return (c >= 'A' && c <= 'Z') || (c >= 'a' && c <= 'z'); }
inline bool is_digit(char c) { return c >= '0' && c <= '9'; }
inline bool is_alnum(char c) { return is_letter(c) || is_digit(c); }
inline bool is_blank(char c) { return c == ' ' || c == '\t' || c == '\f' || c == '\v'; }
inline char upper(char c) { return c >= 'a' && c <= 'z' ? static_cast<char>(c - 'a' + 'A') : c; }

// Character classes of simple_line.
inline constexpr uint8_t kBlankClass = 1;   // blank: space, tab, form feed, vertical tab (is_blank)
inline constexpr uint8_t kDigitClass = 2;   // 0-9
inline constexpr uint8_t kLetterClass = 4;  // A-Z, a-z
inline constexpr uint8_t kWordClass = 8;    // a letter that starts a glued word: not N, O or V (is_glued_word)
inline constexpr auto kClass = [] {
    std::array<uint8_t, 256> t{};
    for (int c : {' ', '\t', '\f', '\v'}) t[static_cast<unsigned char>(c)] = kBlankClass;
    for (int c = '0'; c <= '9'; ++c) t[static_cast<unsigned char>(c)] = kDigitClass;
    for (int c = 'A'; c <= 'Z'; ++c) {
        const bool word = c != 'N' && c != 'O' && c != 'V';
        t[static_cast<unsigned char>(c)] = t[static_cast<unsigned char>(c - 'A' + 'a')] =
            static_cast<uint8_t>(kLetterClass | (word ? kWordClass : 0));
    }
    return t;
}();

inline constexpr double kPow10[] = {1e0,  1e1,  1e2,  1e3,  1e4,  1e5,  1e6,  1e7,  1e8,  1e9,  1e10, 1e11,
                             1e12, 1e13, 1e14, 1e15, 1e16, 1e17, 1e18, 1e19, 1e20, 1e21, 1e22};

// Scans an unsigned number at t (`12`, `3.`, `.5`, `0404`), ending at e at the
// latest, and computes its value in the same pass: at most 15 digits take
// the exact path (the digits as an integer and the power of ten are exact
// doubles, so their quotient is the correctly rounded value), longer ones
// decimal_literal_value. Returns the end, or t when there is no number or it
// is too large for a double (the line then goes to the tree-sitter front end,
// which reports it). With
// kSentinel the byte at e is neither a digit nor a point (the line's
// terminator), so the scans need not compare with e.
template <bool kSentinel>
OSPLINT_HOT const char* scan_number(const char* t, const char* e, double& value) {
    const char* const start = t;
    uint64_t m = 0;
    while ((kSentinel || t < e) && static_cast<unsigned char>(*t - '0') < 10) m = m * 10 + static_cast<uint64_t>(*t++ - '0');
    size_t count = static_cast<size_t>(t - start);
    size_t fraction = 0;
    if ((kSentinel || t < e) && *t == '.') {
        const char* const f = t + 1;
        const char* u = f;
        while ((kSentinel || u < e) && static_cast<unsigned char>(*u - '0') < 10)
            m = m * 10 + static_cast<uint64_t>(*u++ - '0');
        fraction = static_cast<size_t>(u - f);
        if (count == 0 && fraction == 0) return start;  // a point alone
        count += fraction;
        t = u;
    } else if (count == 0) {
        return start;
    }
    if (count <= 15) {
        value = fraction ? static_cast<double>(m) / kPow10[fraction] : static_cast<double>(m);
        return t;
    }
    const std::optional<double> v = decimal_literal_value(std::string_view(start, static_cast<size_t>(t - start)));
    if (!v) return start;
    value = *v;
    return t;
}
// The same on s[p..n): returns the end offset, or p when there is no number.
OSPLINT_HOT uint32_t scan_number_at(const char* s, uint32_t p, uint32_t n, double& value) {
    return static_cast<uint32_t>(scan_number<false>(s + p, s + n, value) - s);
}

// Keyword classes of the scanner, for a name in upper case.
enum class Keyword : uint8_t { None, Call, Modin, Modout, Rts, Ncyl, Noex, Control, Function, Other };

// The tables hold string_views: their lengths are known when compiled, so a
// name of another length is passed over without reading the keyword.
inline bool equals(const char* name, uint32_t len, std::string_view kw) {
    if (kw.size() != len) return false;
    for (uint32_t i = 0; i < len; ++i)  // a few bytes: no call to memcmp
        if (name[i] != kw[i]) return false;
    return true;
}

// The first letters of a table's keywords, one bit each (A = bit 0): most
// names (PX, PZ, VC1) start with a letter no keyword of the table starts with,
// and are passed over without reading the table.
template <class Table, class Key>
constexpr uint32_t first_letters(const Table& table, Key key) {
    uint32_t mask = 0;
    for (const auto& entry : table) mask |= 1u << (key(entry)[0] - 'A');
    return mask;
}
inline bool may_start(uint32_t mask, const char* name, uint32_t len) {
    if (len == 0) return false;
    const unsigned k = static_cast<unsigned char>(name[0]) - 'A';
    return k >= 26 || (mask >> k & 1u);  // not a capital letter: read the table
}

// Names the scanner turns into keyword tokens whatever follows them (when the
// grammar expects them): the control keywords and the function names.
inline Keyword control_keyword(const char* name, uint32_t len) {
    static constexpr std::pair<std::string_view, Keyword> kControl[] = {
        {"CALL", Keyword::Call},    {"MODIN", Keyword::Modin},  {"MODOUT", Keyword::Modout},
        {"RTS", Keyword::Rts},      {"NCYL", Keyword::Ncyl},    {"NOEX", Keyword::Noex},
        {"GOTO", Keyword::Control}, {"IF", Keyword::Control},   {"WHILE", Keyword::Control},
        {"DO", Keyword::Control},   {"END", Keyword::Control},  {"EMPTY", Keyword::Control},
        {"NOT", Keyword::Control},  {"EQ", Keyword::Control},   {"NE", Keyword::Control},
        {"GT", Keyword::Control},   {"GE", Keyword::Control},   {"LT", Keyword::Control},
        {"LE", Keyword::Control},   {"AND", Keyword::Control},  {"OR", Keyword::Control},
        {"EOR", Keyword::Control},
    };
    static constexpr std::string_view kFunctions[] = {"SIN",   "COS", "TAN", "ATAN",   "ATAN2", "SQRT", "ABS",  "BIN",
                                             "BCD",   "ROUND", "FIX", "FUP", "DROUND", "DFIX", "DFUP", "MOD"};
    static constexpr auto kFirst = first_letters(kControl, [](const auto& e) { return e.first; }) |
                                   first_letters(kFunctions, [](std::string_view e) { return e; });
    if (!may_start(kFirst, name, len)) return Keyword::None;
    for (const auto& [kw, k] : kControl)
        if (equals(name, len, kw)) return k;
    for (std::string_view kw : kFunctions)
        if (equals(name, len, kw)) return Keyword::Function;
    return Keyword::None;
}

// The binary operators spelled with letters.
inline constexpr std::string_view kOperatorKeywords[] = {"EQ", "NE", "GT", "GE", "LT", "LE", "AND", "OR", "EOR"};
inline constexpr uint32_t kOperatorFirst = first_letters(kOperatorKeywords, [](std::string_view e) { return e; });
// Whether a name starting with `c` (any case) may be an operator keyword.
inline bool may_be_operator(char c) {
    const char u = upper(c);
    return may_start(kOperatorFirst, &u, 1);
}
inline bool operator_keyword(const char* name, uint32_t len) {
    if (!may_start(kOperatorFirst, name, len)) return false;
    for (std::string_view kw : kOperatorKeywords)
        if (equals(name, len, kw)) return true;
    return false;
}

// Names the scanner turns into command keywords unless `=` or `[` follows.
inline bool command_keyword(const char* name, uint32_t len) {
    static constexpr std::string_view kWords[] = {
        // coordinate calculation
        "BHC", "LAA", "ARC", "GRDX", "GRDY", "DGRDX", "DGRDY", "SQRX", "SQRY", "OMIT", "RSTRT",
        // mnemonics
        "MSG", "NMSG", "COPY", "COPYE", "CHFC", "CHFR", "RTMCR", "RTMDI", "FMILR", "FMILF", "PMIL", "PMILR",
        "RMILO", "RMILI", "TLFON", "TLFOFF", "TLID", "CLEAR", "LCLEAR", "DRAW",
        // commands with free-form operands
        "DEF", "PT", "PUT", "FWRITC", "FOPENA", "FOPENB", "WRITE", "READ", "CLOSE", "PRNT", "SAVE", "EIN", "DIN",
        "RTI", "CYLNDR", "DIREC"};
    static constexpr auto kFirst = first_letters(kWords, [](std::string_view e) { return e; });
    if (!may_start(kFirst, name, len)) return false;
    for (std::string_view kw : kWords)
        if (equals(name, len, kw)) return true;
    return false;
}

// Assignments to the strings of recycled model objects: most blocks of a
// program repeat the previous block's shape, so the text often has the same
// length (or is the same) and the generic assign can be skipped.
OSPLINT_HOT void set_text(std::string& dst, const char* p, size_t n) {
    // A length change within the capacity: erase to shorten, push_back to
    // lengthen by one, resize by more (assign() would copy again).
    if (dst.size() > n) {
        dst.erase(n);
    } else if (dst.size() + 1 == n && n <= dst.capacity()) {
        dst.push_back('\0');
    } else if (dst.size() < n && n <= dst.capacity()) {
        dst.resize(n);  // one call for a string made again (Recycler), not a push_back per byte
    }
    if (dst.size() == n) {
        char* d = dst.data();
        if (n >= 4 && n <= 8) {  // two overlapping 4-byte moves
            uint32_t a, z;
            std::memcpy(&a, p, 4);
            std::memcpy(&z, p + n - 4, 4);
            std::memcpy(d, &a, 4);
            std::memcpy(d + n - 4, &z, 4);
        } else {
            for (size_t i = 0; i < n; ++i) d[i] = p[i];
        }
    } else {
        dst.assign(p, n);
    }
}
// Sets a node's only child.
inline void set_child(std::vector<ExprId>& children, ExprId id) {
    if (children.size() == 1) {
        children[0] = id;
    } else {
        children.clear();
        children.push_back(id);
    }
}
OSPLINT_HOT void set_char(std::string& dst, char c) {
    if (dst.size() == 1) dst[0] = c;
    else dst.assign(1, c);
}

// Whether an element holds storage of its own (heap memory of a string or a
// vector) that is worth keeping for a later line; an element that holds none
// is cheaper to make again than to move twice.
inline bool holds_storage(const std::string& s) { return s.capacity() > std::string().capacity(); }
inline bool holds_storage(const Word& w) { return holds_storage(w.address) || holds_storage(w.value_text); }
inline bool holds_storage(const ExprNode& e) {
    return e.children.capacity() > 0 || holds_storage(e.op) || holds_storage(e.text);
}

// Storage reuse: elements beyond what a block needs are parked here when
// they hold storage (moved, so their strings and vectors keep their
// capacity) and taken back later.
template <class T>
class Recycler {
public:
    T& take(std::vector<T>& v, size_t& used) {
        if (used == v.size()) {
            if (!spare_.empty()) {
                v.push_back(std::move(spare_.back()));
                spare_.pop_back();
            } else {
                v.emplace_back();
            }
        }
        return v[used++];
    }
    void finish(std::vector<T>& v, size_t used) {
        while (v.size() > used) {
            if (holds_storage(v.back())) spare_.push_back(std::move(v.back()));
            v.pop_back();
        }
    }

private:
    std::vector<T> spare_;
};

inline constexpr uint32_t kFail = std::numeric_limits<uint32_t>::max();

}  // namespace osplint::fast_detail
