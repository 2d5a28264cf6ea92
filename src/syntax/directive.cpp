#include "syntax/directive.h"

#include <cctype>

#include <fmt/format.h>

#include "support/text.h"

namespace osplint {
namespace {

// A cursor over the inside of one comment, with absolute offsets.
class Reader {
public:
    Reader(std::string_view text, uint32_t begin, uint32_t end) : text_(text), pos_(begin), end_(end) {}

    void skip_blanks() {
        while (pos_ < end_ && is_blank(text_[pos_])) ++pos_;
    }
    bool at_end() const { return pos_ >= end_; }
    uint32_t pos() const { return pos_; }
    char peek() const { return at_end() ? '\0' : text_[pos_]; }
    bool starts_with(std::string_view s) const {
        return end_ - pos_ >= s.size() && text_.substr(pos_, s.size()) == s;
    }
    bool take(char c) {
        if (peek() != c) return false;
        ++pos_;
        return true;
    }
    // Letters, digits, '_' and single '-' (a "--" ends the token: it starts the reason).
    ByteRange token() {
        uint32_t b = pos_;
        while (!at_end()) {
            char c = text_[pos_];
            if (c == '-' && starts_with("--")) break;
            if (!(std::isalnum(static_cast<unsigned char>(c)) || c == '_' || c == '-')) break;
            ++pos_;
        }
        return {b, pos_};
    }
    std::string_view slice(ByteRange r) const { return text_.substr(r.begin, r.size()); }
    void to_end() { pos_ = end_; }
    uint32_t end() const { return end_; }

private:
    std::string_view text_;
    uint32_t pos_, end_;
};

}  // namespace

bool suppression_target(const Block& b) {
    return b.kind == LineKind::Block && (!b.is_empty() || !b.errors.empty());
}

DirectiveParse parse_directive(std::string_view text, ByteRange comment) {
    DirectiveParse out;
    if (comment.end > text.size() || comment.empty() || text[comment.begin] != '(') return out;
    uint32_t inner_end = comment.end;
    if (text[inner_end - 1] == ')' && inner_end - 1 > comment.begin) --inner_end;
    Reader r(text, comment.begin + 1, inner_end);
    r.skip_blanks();
    ByteRange head = r.token();
    if (!iequals(r.slice(head), "osplint")) return out;
    r.skip_blanks();
    if (!r.take(':')) return out;
    out.is_directive = true;
    auto fail = [&](std::string message, ByteRange where) {
        out.error = std::move(message);
        out.error_range = where.empty() ? ByteRange{where.begin, std::min(where.begin + 1, comment.end)} : where;
        return out;
    };

    SuppressionDirective d;
    d.comment = comment;
    r.skip_blanks();
    ByteRange action = r.token();
    std::string_view act = r.slice(action);
    if (iequals(act, "disable")) {
        d.action = SuppressionDirective::Action::Disable;
    } else if (iequals(act, "disable-file")) {
        d.action = SuppressionDirective::Action::DisableFile;
    } else if (act.empty()) {
        return fail("malformed osplint directive: expected disable=<rule IDs> or disable-file=<rule IDs>",
                    {r.pos(), r.pos()});
    } else {
        return fail(fmt::format("unknown osplint directive '{}': the directives are disable=<rule IDs> and "
                                "disable-file=<rule IDs>",
                                act),
                    action);
    }
    r.skip_blanks();
    if (!r.take('='))
        return fail(fmt::format("malformed osplint directive: expected '=' and rule IDs after '{}'", act),
                    {r.pos(), r.pos()});
    while (true) {
        r.skip_blanks();
        ByteRange id = r.token();
        if (id.empty()) {
            return fail("malformed osplint directive: expected a rule ID such as OSP104", {r.pos(), r.pos()});
        }
        d.ids.push_back({std::string(r.slice(id)), id});
        r.skip_blanks();
        if (!r.take(',')) break;
    }
    if (r.starts_with("--")) {
        r.take('-');
        r.take('-');
        r.skip_blanks();
        uint32_t b = r.pos();
        uint32_t e = r.end();
        while (e > b && is_blank(text[e - 1])) --e;
        d.reason = std::string(text.substr(b, e - b));
        r.to_end();
    }
    if (!r.at_end()) {
        uint32_t b = r.pos();
        ByteRange junk = r.token();
        if (junk.empty()) junk = {b, b + 1};
        return fail(fmt::format("malformed osplint directive: unexpected '{}': separate rule IDs with ',' and "
                                "write the reason after '--'",
                                r.slice(junk)),
                    junk);
    }
    out.directive = std::move(d);
    return out;
}

bool has_directive(const Block& b, std::string_view line_text) {
    for (const auto& c : b.comments) {
        const ByteRange rel{c.range.begin - b.line_start, c.range.end - b.line_start};
        if (parse_directive(line_text, rel).is_directive) return true;
    }
    return false;
}

}  // namespace osplint
