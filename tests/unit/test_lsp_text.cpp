// Language server, the layers below the session: framing, JSON-RPC
// classification, LSP positions in UTF-8 and UTF-16, content changes and the
// incremental re-parse (checked against a full parse on random edits).
#include <doctest/doctest.h>

#include <filesystem>
#include <fstream>
#include <random>
#include <sstream>

#include "syntax/frontend.h"
#include "lsp/features.h"
#include "lsp/jsonrpc.h"
#include "lsp/text.h"
#include "lsp/transport.h"

using namespace osplint;
using namespace osplint::lsp;

namespace {

// A source that hands out its bytes in pieces of a fixed size.
class ChunkSource final : public InputStream {
public:
    ChunkSource(std::string data, std::size_t chunk) : data_(std::move(data)), chunk_(chunk) {}
    std::size_t read(char* buf, std::size_t n) override {
        const std::size_t k = std::min({n, chunk_, data_.size() - pos_});
        std::copy_n(data_.data() + pos_, k, buf);
        pos_ += k;
        reads_ += k ? 1 : 0;
        return k;
    }
    std::size_t consumed() const { return pos_; }

private:
    std::string data_;
    std::size_t chunk_;
    std::size_t pos_ = 0;
    std::size_t reads_ = 0;
};

std::vector<ReadResult> read_all(const std::string& bytes, std::size_t chunk = 7) {
    ChunkSource src(bytes, chunk);
    FrameReader reader(src);
    std::vector<ReadResult> out;
    for (;;) {
        ReadResult r = reader.next();
        if (r.kind == ReadResult::Eof) break;
        out.push_back(std::move(r));
    }
    return out;
}

std::string read_file(const std::filesystem::path& p) {
    std::ifstream in(p, std::ios::binary);
    std::stringstream ss;
    ss << in.rdbuf();
    return ss.str();
}

// The line of the text with the emoji and the Japanese comment used below.
const std::string kLine = "CALL OZAGR (\xE8\xA3\x8F\xE3\x82\xB6\xE3\x82\xB0\xE3\x83\xAA \xF0\x9F\x94\xA7) PR=5";
//                                     裏 (3 bytes)  ザ        グ        リ          🔧 (4 bytes, 2 UTF-16 units)

}  // namespace

TEST_CASE("lsp: framing: messages split across reads, extra headers, blank lines between messages") {
    const std::string a = R"({"jsonrpc":"2.0","id":1,"method":"a"})";
    const std::string b = R"({"jsonrpc":"2.0","method":"b","params":{"t":"\r\n\r\n"}})";
    std::string bytes = frame(a) + "\r\n" + "Content-Type: application/vscode-jsonrpc; charset=utf-8\r\n" +
                        "content-length:" + std::to_string(b.size()) + "\r\n\r\n" + b;
    for (std::size_t chunk : {1u, 3u, 7u, 4096u}) {
        auto rs = read_all(bytes, chunk);
        REQUIRE(rs.size() == 2);
        CHECK(rs[0].kind == ReadResult::Message);
        CHECK(rs[0].body == a);
        CHECK(rs[1].body == b);
    }
}

TEST_CASE("lsp: framing: bad headers are refused once and the next message still arrives") {
    const std::string ok = R"({"jsonrpc":"2.0","id":2,"method":"x"})";
    SUBCASE("length not a number") {
        auto rs = read_all("Content-Length: abc\r\n\r\n{\"x\":1}" + frame(ok));
        REQUIRE(rs.size() == 2);
        CHECK(rs[0].kind == ReadResult::Error);
        CHECK(rs[0].problem.find("abc") != std::string::npos);
        CHECK(rs[1].body == ok);
    }
    SUBCASE("absurd length: refused, nothing allocated, nothing waited for") {
        ChunkSource src("Content-Length: 99999999999999\r\n\r\n" + frame(ok), 64);
        FrameReader reader(src);
        ReadResult r1 = reader.next();
        CHECK(r1.kind == ReadResult::Error);
        ReadResult r2 = reader.next();
        REQUIRE(r2.kind == ReadResult::Message);
        CHECK(r2.body == ok);
    }
    SUBCASE("just above the limit") {
        auto rs = read_all("Content-Length: " + std::to_string(kMaxContentLength + 1) + "\r\n\r\n" + frame(ok));
        REQUIRE(rs.size() == 2);
        CHECK(rs[0].kind == ReadResult::Error);
        CHECK(rs[1].body == ok);
    }
    SUBCASE("no Content-Length at all") {
        auto rs = read_all("Content-Type: x\r\n\r\n{}" + frame(ok));
        REQUIRE(rs.size() == 2);
        CHECK(rs[0].kind == ReadResult::Error);
        CHECK(rs[1].body == ok);
    }
    SUBCASE("garbage glued to the next header") {
        auto rs = read_all("hello world, this is not LSP" + frame(ok));
        REQUIRE(rs.size() == 2);
        CHECK(rs[0].kind == ReadResult::Error);
        CHECK(rs[1].body == ok);
    }
    SUBCASE("an endless line without a newline") {
        auto rs = read_all(std::string(100000, 'x') + frame(ok), 4096);
        REQUIRE(rs.size() == 2);
        CHECK(rs[0].kind == ReadResult::Error);
        CHECK(rs[1].body == ok);
    }
    SUBCASE("a truncated body is the end of input") {
        auto rs = read_all("Content-Length: 100\r\n\r\n{\"a\":");
        CHECK(rs.empty());
    }
}

TEST_CASE("lsp: JSON-RPC classification") {
    CHECK(classify(R"({"jsonrpc":"2.0","id":1,"method":"m","params":{}})").kind == Incoming::Request);
    CHECK(classify(R"({"jsonrpc":"2.0","id":"s","method":"m"})").kind == Incoming::Request);
    CHECK(classify(R"({"jsonrpc":"2.0","method":"m"})").kind == Incoming::Notification);
    CHECK(classify(R"({"jsonrpc":"2.0","id":3,"result":null})").kind == Incoming::Response);
    auto bad_json = classify("{\"jsonrpc\":");
    CHECK(bad_json.kind == Incoming::Invalid);
    CHECK(bad_json.error_code == error::kParseError);
    CHECK(classify("[1,2]").error_code == error::kInvalidRequest);
    CHECK(classify(R"({"id":1,"method":"m"})").error_code == error::kInvalidRequest);
    CHECK(classify(R"({"jsonrpc":"2.0","id":1.5,"method":"m"})").kind == Incoming::Invalid);
    CHECK(classify(R"({"jsonrpc":"2.0","id":1,"method":7})").kind == Incoming::Invalid);
    CHECK(classify(R"({"jsonrpc":"2.0","id":1,"method":"m","params":3})").kind == Incoming::Invalid);
    CHECK(classify("\xFF\xFE").error_code == error::kParseError);
    CHECK(classify("").error_code == error::kParseError);
}

TEST_CASE("lsp: MessageWriter: invalid UTF-8 in a string never breaks the output") {
    MemoryOutput sink;
    MessageWriter w(sink);
    CHECK(w.send(make_notification("m", {{"s", std::string("a\xFF")}})));
    std::string body = sink.next(1000);
    auto msg = json::parse(body);
    CHECK(msg["params"]["s"] == "a\xEF\xBF\xBD");
}

TEST_CASE("lsp: encoding negotiation") {
    CHECK(negotiate_encoding(json::object()) == Encoding::Utf16);
    CHECK(negotiate_encoding({{"general", {{"positionEncodings", {"utf-16"}}}}}) == Encoding::Utf16);
    CHECK(negotiate_encoding({{"general", {{"positionEncodings", {"utf-32", "utf-8", "utf-16"}}}}}) == Encoding::Utf8);
    CHECK(negotiate_encoding({{"general", {{"positionEncodings", "utf-8"}}}}) == Encoding::Utf16);
}

TEST_CASE("lsp: positions: byte offsets <-> LSP positions in both encodings, non-ASCII comments") {
    const SourceText src("O1\n" + kLine + "\r\nM30");
    const uint32_t pr = static_cast<uint32_t>(src.text().find("PR=5"));
    // Line 1 (0-based): the comment holds 4 three-byte characters and one four-byte emoji.
    const auto u8 = to_lsp_position(src, pr, Encoding::Utf8);
    const auto u16 = to_lsp_position(src, pr, Encoding::Utf16);
    CHECK(u8 == json{{"line", 1}, {"character", kLine.find("PR=5")}});
    // 11 ASCII + "(" ... : CALL OZAGR ( = 12 units, 4 kana/kanji = 4, space = 1, emoji = 2, ") " = 2
    CHECK(u16 == json{{"line", 1}, {"character", 12 + 4 + 1 + 2 + 2}});
    CHECK(from_lsp_position(src, u8, Encoding::Utf8) == pr);
    CHECK(from_lsp_position(src, u16, Encoding::Utf16) == pr);
    // Past the end of a line: its end; past the last line: the end of the text.
    CHECK(from_lsp_position(src, {{"line", 0}, {"character", 99}}, Encoding::Utf16) == 2);
    CHECK(from_lsp_position(src, {{"line", 9}, {"character", 0}}, Encoding::Utf8) == src.size());
    // Inside the surrogate pair: stays before the emoji.
    const uint32_t emoji = static_cast<uint32_t>(src.text().find("\xF0\x9F"));
    const uint32_t emoji_u16 = 12 + 4 + 1;
    CHECK(from_lsp_position(src, {{"line", 1}, {"character", emoji_u16 + 1}}, Encoding::Utf16) == emoji);
    CHECK(from_lsp_position(src, {{"line", 1}, {"character", emoji_u16 + 2}}, Encoding::Utf16) == emoji + 4);
    CHECK_THROWS(from_lsp_position(src, {{"line", "x"}}, Encoding::Utf8));
}

TEST_CASE("lsp: content changes: applied in order, incremental and full, in both encodings") {
    for (Encoding enc : {Encoding::Utf8, Encoding::Utf16}) {
        const std::string base = "O1\n" + kLine + "\nM30\n";
        std::string text = base;
        const SourceText src(text);
        const uint32_t pr = static_cast<uint32_t>(text.find("PR=5"));
        json pos = to_lsp_position(src, pr, enc);
        json end = to_lsp_position(src, pr + 4, enc);
        // Replace PR=5 by PR=7, then insert at the start of the line, then delete line 0.
        json changes = json::array({
            {{"range", {{"start", pos}, {"end", end}}}, {"text", "PR=7"}},
            {{"range", {{"start", {{"line", 1}, {"character", 0}}}, {"end", {{"line", 1}, {"character", 0}}}}},
             {"text", "N1 "}},
            {{"range", {{"start", {{"line", 0}, {"character", 0}}}, {"end", {{"line", 1}, {"character", 0}}}}},
             {"text", ""}},
        });
        for (const auto& c : changes) apply_change(text, c, enc);
        std::string expected = "N1 " + kLine + "\nM30\n";
        expected.replace(expected.find("PR=5"), 4, "PR=7");
        CHECK(text == expected);
        // An edit right after the emoji, positions counted in the encoding.
        const SourceText now(text);
        const uint32_t after_emoji = static_cast<uint32_t>(text.find("\xF0\x9F\x94\xA7") + 4);
        apply_change(
            text,
            {{"range",
              {{"start", to_lsp_position(now, after_emoji, enc)}, {"end", to_lsp_position(now, after_emoji, enc)}}},
             {"text", "!"}},
            enc);
        CHECK(text.find("\xF0\x9F\x94\xA7!") != std::string::npos);
        apply_change(text, {{"text", "M30"}}, enc);  // full replacement
        CHECK(text == "M30");
        CHECK_THROWS(apply_change(text, {{"range", {{"start", 1}}}, {"text", "x"}}, enc));
        CHECK_THROWS(apply_change(text, {{"range", nullptr}}, enc));
    }
}

TEST_CASE("lsp: a change lands at the offset of its position on every kind of line end") {
    // Lines shorter and longer than the 16 bytes a line break is looked for at a time.
    std::string text;
    const char* const ends[] = {"\n", "\r\n", "\r"};
    for (int i = 0; i < 40; ++i) {
        text += std::string(static_cast<size_t>(i * 7 % 37), 'X');
        text += ends[i % 3];
    }
    text += "M30";  // an unterminated last line
    const SourceText src(text);
    for (const Encoding enc : {Encoding::Utf8, Encoding::Utf16}) {
        for (uint32_t off = 0; off <= text.size(); ++off) {
            if (off > 0 && text[off - 1] == '\r' && off < text.size() && text[off] == '\n') continue;  // inside a CR LF
            const json pos = to_lsp_position(src, off, enc);
            std::string edited = text;
            apply_change(edited, {{"range", {{"start", pos}, {"end", pos}}}, {"text", "#"}}, enc);
            std::string expected = text;
            expected.insert(off, "#");
            REQUIRE_MESSAGE(edited == expected, "offset " << off);
        }
        // A line past the last one: the end of the text.
        std::string edited = text;
        const json past = {{"line", 1000}, {"character", 0}};
        apply_change(edited, {{"range", {{"start", past}, {"end", past}}}, {"text", "#"}}, enc);
        CHECK(edited == text + "#");
    }
}

TEST_CASE("lsp: file URIs") {
    CHECK(uri_to_path("file:///home/a%20b/P%C3%A9.MIN") == std::optional<std::string>("/home/a b/P\xC3\xA9.MIN"));
    CHECK(uri_to_path("file://localhost/x.MIN") == std::optional<std::string>("/x.MIN"));
    CHECK(!uri_to_path("untitled:Untitled-1"));
    CHECK(!uri_to_path("file://otherhost/x"));
    CHECK(uri_to_path(path_to_uri("/tmp/a b/#1.MIN")) == std::optional<std::string>("/tmp/a b/#1.MIN"));
}

namespace {

std::string publish_whole(const std::string& uri, int64_t version, const std::vector<Diagnostic>& diags) {
    json list = json::array();
    for (const auto& d : diags) list.push_back(to_lsp_diagnostic(d, uri, Encoding::Utf16, version));
    json params = {{"uri", uri}, {"diagnostics", std::move(list)}};
    if (version >= 0) params["version"] = version;
    return make_notification("textDocument/publishDiagnostics", params)
        .dump(-1, ' ', false, json::error_handler_t::replace);
}

}  // namespace

TEST_CASE("lsp: publishDiagnostics written from the texts of the findings published before is the notification itself") {
    auto at = [](uint32_t line, uint32_t col, uint32_t byte) {
        return SourceRange{ByteRange{byte, byte + 2}, Position{line, col, col, col}, Position{line, col + 2, col + 2, col + 2}};
    };
    Diagnostic a;
    a.rule = "OSP104";
    a.severity = Severity::Warning;
    a.message = "M52 on a \"call\" line\tand \xff a bad byte";
    a.range = at(3, 4, 40);
    a.notes.push_back({"set here", at(1, 0, 3)});
    a.notes.push_back({"no place", std::nullopt});
    Fix f;
    f.title = "Replace M52 by PM=52";
    f.safe = true;
    f.edits.push_back({at(3, 4, 40), "PM=52"});
    a.fixes.push_back(f);
    Diagnostic b = a;
    b.rule = "OSP001";
    b.severity = Severity::Error;
    b.message = "unterminated comment";
    b.fixes.clear();
    b.range = at(7, 1, 90);
    const std::string uri = "file:///w/a%20b.min";
    DiagnosticTexts texts;
    for (const int64_t version : {int64_t{3}, int64_t{-1}, int64_t{12}}) {
        const std::vector<Diagnostic> diags = {a, b, a};
        CHECK(publish_text(uri, version, diags, Encoding::Utf16, texts) == publish_whole(uri, version, diags));
        CHECK(texts.size() == 2);
        // The next publication: the same findings at other bytes of the same lines and columns.
        a.range.bytes.begin += 5;
        a.range.bytes.end += 5;
    }
    // A finding that moved to another column is written again.
    b.range.start.utf16_col += 1;
    const std::vector<Diagnostic> moved = {b};
    CHECK(publish_text(uri, 4, moved, Encoding::Utf16, texts) == publish_whole(uri, 4, moved));
    CHECK(texts.size() == 1);
}
