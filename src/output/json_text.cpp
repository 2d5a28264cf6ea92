#include "output/json_text.h"

#include <fmt/format.h>
#include <nlohmann/json.hpp>

namespace osplint {

void JsonText::separate() {
    if (after_key_) {
        after_key_ = false;
        return;
    }
    if (first_.empty()) return;
    if (!first_.back()) out_ += ',';
    first_.back() = false;
}

JsonText& JsonText::open(char c) {
    separate();
    out_ += c;
    first_.push_back(true);
    return *this;
}

JsonText& JsonText::close(char c) {
    out_ += c;
    first_.pop_back();
    return *this;
}

JsonText& JsonText::key(std::string_view name) {
    separate();
    append_string(out_, name);
    out_ += ':';
    after_key_ = true;
    return *this;
}

JsonText& JsonText::value(std::string_view s) {
    separate();
    append_string(out_, s);
    return *this;
}

JsonText& JsonText::value(uint64_t n) {
    separate();
    out_ += fmt::format_int(n).str();
    return *this;
}

JsonText& JsonText::value(int64_t n) {
    separate();
    out_ += fmt::format_int(n).str();
    return *this;
}

JsonText& JsonText::value(bool b) {
    separate();
    out_ += b ? "true" : "false";
    return *this;
}

JsonText& JsonText::raw(std::string_view text) {
    separate();
    out_ += text;
    return *this;
}

void JsonText::append_string(std::string& out, std::string_view s) {
    // Printable ASCII with nothing to escape (nearly every message, rule and
    // path) is copied as it is; anything else goes through nlohmann::json, so
    // that escapes and the replacement of invalid UTF-8 stay its own.
    bool plain = true;
    for (char c : s) {
        const auto u = static_cast<unsigned char>(c);
        if (u < 0x20 || u >= 0x7f || c == '"' || c == '\\') {
            plain = false;
            break;
        }
    }
    if (!plain) {
        out += nlohmann::json(std::string(s)).dump(-1, ' ', false, nlohmann::json::error_handler_t::replace);
        return;
    }
    out += '"';
    out += s;
    out += '"';
}

}  // namespace osplint
