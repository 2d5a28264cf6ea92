// Compact JSON written straight into a string, member by member, for the
// reports that write one object per finding (json, sarif): the same bytes as
// nlohmann::json's dump() of the same document, without building the document
// first (a million findings made a million trees of small allocations).
#pragma once

#include <cstdint>
#include <string>
#include <string_view>
#include <vector>

namespace osplint {

class JsonText {
public:
    explicit JsonText(std::string& out) : out_(out) {}

    JsonText& begin_object() { return open('{'); }
    JsonText& end_object() { return close('}'); }
    JsonText& begin_array() { return open('['); }
    JsonText& end_array() { return close(']'); }
    // The name of the next member of the object being written.
    JsonText& key(std::string_view name);
    JsonText& value(std::string_view s);
    JsonText& value(const char* s) { return value(std::string_view(s)); }
    JsonText& value(uint64_t n);
    JsonText& value(int64_t n);
    JsonText& value(uint32_t n) { return value(static_cast<uint64_t>(n)); }
    JsonText& value(int n) { return value(static_cast<int64_t>(n)); }
    JsonText& value(bool b);
    // `text`, already JSON (a value dumped by nlohmann::json), as the next value.
    JsonText& raw(std::string_view text);

    // `s` as a JSON string, escaped as nlohmann::json's dump() does with
    // invalid UTF-8 replaced (U+FFFD), appended to `out`.
    static void append_string(std::string& out, std::string_view s);

private:
    JsonText& open(char c);
    JsonText& close(char c);
    void separate();  // the comma before a value of an array or a member of an object

    std::string& out_;
    std::vector<bool> first_;  // per open object or array: nothing written in it yet
    bool after_key_ = false;
};

}  // namespace osplint
