// Reading input (support/io.h): a line longer than kMaxLineLength stops the
// reading with a message naming the line, in the line stream, the outline,
// the copy of standard input and a whole check; memory never grows with it.
// Writing a file atomically: replaced whole or not at all.
#include <doctest/doctest.h>

#include <fcntl.h>
#include <signal.h>
#include <sys/resource.h>
#include <sys/stat.h>
#include <unistd.h>

#include <cstdio>
#include <fstream>
#include <optional>
#include <random>
#include <filesystem>
#include <string>
#include <thread>
#include <vector>

#include "api/check.h"
#include "api/fix.h"
#include "engine/workspace.h"
#include "support/io.h"
#include "syntax/outline.h"

using namespace osplint;

TEST_CASE("skip_lines: the start of the line n lines on, on every kind of line end") {
    // The byte-by-byte definition.
    auto naive = [](const std::string& t, uint64_t n) -> std::optional<size_t> {
        if (n == 0) return 0;
        for (size_t i = 0; i < t.size(); ++i)
            if (ends_line(t.data() + i, t.data() + t.size()) && --n == 0) return i + 1;
        return std::nullopt;
    };
    std::mt19937 rng(77);
    for (int k = 0; k < 2000; ++k) {
        std::string t;
        const size_t size = rng() % 120;
        // Runs of text long and short, so that line ends fall on every place of a 16-byte block.
        while (t.size() < size) t += rng() % 4 ? "XYZ\r\n"[rng() % 5] : 'X';
        for (uint64_t n = 0; n <= t.size() + 1; ++n) {
            const char* got = skip_lines(t.data(), t.data() + t.size(), n);
            const std::optional<size_t> want = naive(t, n);
            REQUIRE_MESSAGE((got != nullptr) == want.has_value(), "n " << n << " in '" << t << "'");
            if (got) REQUIRE_MESSAGE(static_cast<size_t>(got - t.data()) == *want, "n " << n << " in '" << t << "'");
            if (!want) break;
        }
    }
}

TEST_CASE("find_line_break: the first CR or LF, wherever it falls in a 32-byte step") {
    std::mt19937 rng(78);
    for (int k = 0; k < 5000; ++k) {
        std::string t;
        const size_t size = rng() % 100;
        // Mostly text, so that the first line end falls on every place of both 16-byte halves.
        while (t.size() < size) t += rng() % 24 ? 'X' : "\r\n"[rng() % 2];
        for (size_t from = 0; from <= t.size(); from += 1 + rng() % 7) {
            const char* got = find_line_break(t.data() + from, t.data() + t.size());
            const size_t want = t.find_first_of("\r\n", from);
            if (want == std::string::npos) REQUIRE_MESSAGE(got == nullptr, "from " << from << " in '" << t << "'");
            else REQUIRE_MESSAGE(got == t.data() + want, "from " << from << " in '" << t << "'");
        }
    }
}

TEST_CASE("a line longer than kMaxLineLength stops the line stream") {
    for (size_t chunk : {size_t(7), size_t(64) << 10, size_t(4) << 20}) {
        const std::string ok_line(kMaxLineLength, 'X');
        const std::string text = "G0\r\n" + ok_line + "\n" + std::string(kMaxLineLength + 1, 'Y') + "\nG1\n";
        MemorySource src(text);
        LineStream ls(src, chunk);
        LineRef l;
        REQUIRE(ls.next(l));
        REQUIRE(ls.next(l));
        CHECK(l.text.size() == kMaxLineLength);
        CHECK_FALSE(ls.next(l));
        CHECK(ls.error());
        CHECK(ls.stop_reason() == line_too_long_message(3));
    }
}

TEST_CASE("a line longer than kMaxLineLength is an input error of the outline and of the check") {
    const std::string text = "O1\nG0\n" + std::string(3 * kMaxLineLength, '\0');
    MemorySource src(text);
    const FileOutline o = outline_file(src);
    CHECK(o.error == line_too_long_message(3));
    const FileResult r = check_text("LONG.MIN", text, Config{});
    CHECK(r.io_error == line_too_long_message(3));
    CHECK(line_too_long_message(3).find("line 3 is longer than") == 0);
}

TEST_CASE("the copy of standard input stops at a line longer than kMaxLineLength") {
    ::signal(SIGPIPE, SIG_IGN);  // the writer finds the pipe closed
    int fds[2];
    REQUIRE(::pipe(fds) == 0);
    // Lines end with LF, CRLF and a lone CR (the CR of a CRLF at the end of a read too).
    std::thread writer([w = fds[1]] {
        const std::string head = "A\r\nB\rC\n";
        (void)!::write(w, head.data(), head.size());
        const std::string zeros(64 << 10, '\0');
        for (size_t sent = 0; sent < 4 * kMaxLineLength; sent += zeros.size())
            if (::write(w, zeros.data(), zeros.size()) < 0) break;
        ::close(w);
    });
    std::string error;
    const int fd = spool_to_temporary_file(fds[0], error);
    ::close(fds[0]);  // the writer then fails, and ends
    writer.join();
    CHECK(fd < 0);
    CHECK(error == line_too_long_message(4));
}

namespace {

std::string slurp(const std::string& path) {
    std::string out;
    FILE* f = std::fopen(path.c_str(), "rb");
    if (!f) return "(missing)";
    char buf[4096];
    for (size_t n; (n = std::fread(buf, 1, sizeof buf, f)) > 0;) out.append(buf, n);
    std::fclose(f);
    return out;
}

// The names in a directory other than `keep`.
std::vector<std::string> others(const std::filesystem::path& dir, const std::string& keep) {
    std::vector<std::string> names;
    for (const auto& e : std::filesystem::directory_iterator(dir))
        if (e.path().filename() != keep) names.push_back(e.path().filename().string());
    return names;
}

}  // namespace

TEST_CASE("write_file_atomically: replaces the file, keeps its permissions, leaves nothing behind") {
    const auto dir = std::filesystem::temp_directory_path() / ("osplint-atomic-" + std::to_string(::getpid()));
    std::filesystem::remove_all(dir);
    std::filesystem::create_directories(dir);
    const std::string path = (dir / "b.json").string();
    std::string error;
    REQUIRE(write_file_atomically(path, "first", error));
    CHECK(slurp(path) == "first");
    ::chmod(path.c_str(), 0640);
    REQUIRE(write_file_atomically(path, "second", error));
    CHECK(slurp(path) == "second");
    struct stat st;
    REQUIRE(::stat(path.c_str(), &st) == 0);
    CHECK((st.st_mode & 0777) == 0640);
    CHECK(others(dir, "b.json").empty());

    SUBCASE("a planted link where a temporary file could be is never followed") {
        const std::string victim = (dir / "victim").string();
        for (const char* name : {"b.json.tmp", ".b.json.tmp"})
            std::filesystem::create_symlink(victim, dir / name);
        REQUIRE(write_file_atomically(path, "third", error));
        CHECK(slurp(path) == "third");
        CHECK_FALSE(std::filesystem::exists(victim));
    }
    SUBCASE("a write that fails leaves the file as it was and no temporary file") {
        ::signal(SIGXFSZ, SIG_IGN);
        struct rlimit old;
        REQUIRE(::getrlimit(RLIMIT_FSIZE, &old) == 0);
        struct rlimit small = old;
        small.rlim_cur = 3;
        REQUIRE(::setrlimit(RLIMIT_FSIZE, &small) == 0);
        const bool ok = write_file_atomically(path, "a longer text than the limit", error);
        ::setrlimit(RLIMIT_FSIZE, &old);
        CHECK_FALSE(ok);
        CHECK(error.find("write error") == 0);
        CHECK(slurp(path) == "second");
        CHECK(others(dir, "b.json").empty());
    }
    SUBCASE("a directory in the way: an error, and no temporary file") {
        const std::string sub = (dir / "sub").string();
        std::filesystem::create_directories(dir / "sub" / "inner");
        CHECK_FALSE(write_file_atomically(sub, "x", error));
        CHECK(error.find("cannot replace it") == 0);
        CHECK(others(dir, "b.json") == std::vector<std::string>{"sub"});
        CHECK_FALSE(write_file_atomically((dir / "missing" / "b.json").string(), "x", error));
        CHECK(error.find("cannot create a temporary file") == 0);
    }
    std::filesystem::remove_all(dir);
}

TEST_CASE("a UTF-16 file is said to be UTF-16, not a syntax error on every line") {
    const std::string le("\xFF\xFEO\0001\0\n\0G\0000\0 \0X\0001\0\n\0", 18);
    const std::string be("\xFE\xFF\0O\0001\0\n", 8);
    for (const std::string& text : {le, be}) {
        const FileResult r = check_text("U16.MIN", text, Config{});
        CHECK(r.io_error == kUtf16Message);
        CHECK(r.diagnostics.empty());
    }
    // A UTF-8 byte order mark is read as usual.
    CHECK(check_text("U8.MIN", "\xEF\xBB\xBFO1\nG0 X1\nM30\n", Config{}).io_error.empty());
}

namespace {

// A program of `lines` moves, with a cycle block whose line a cut splits.
std::string long_program(int lines) {
    std::string text = "O1000\nG0 X0 Z10\n";
    for (int i = 0; i < lines; ++i) text += "G1 X" + std::to_string(i % 50) + ". F100\n";
    return text + "G81 Z-5. R2. F100\nG80\nM30\n";
}

struct ScratchFile {
    std::string path;
    int fd = -1;
    explicit ScratchFile(const std::string& text) {
        path = (std::filesystem::temp_directory_path() /
                ("osplint-changed-" + std::to_string(::getpid()) + ".MIN"))
                   .string();
        std::string error;
        REQUIRE(write_file_atomically(path, text, error));
        fd = ::open(path.c_str(), O_RDWR | O_CLOEXEC);
        REQUIRE(fd >= 0);
    }
    ~ScratchFile() {
        ::close(fd);
        std::filesystem::remove(path);
    }
};

FileResult check_source_collected(const std::string& path, ByteSource& src, const AnalysisOptions& options = {}) {
    ResultCollector collect;
    check_source(path, src, Config{}, options, collect);
    return collect.take();
}

size_t syntax_errors(const FileResult& r) {
    size_t n = 0;
    for (const auto& d : r.diagnostics) n += d.rule == "OSP001";
    return n;
}

// Cuts the file at `cut_at` the first time it is read after a read reached
// its end (the outline's pass): the walk then finds it shorter.
class CutDuringWalk final : public ByteSource {
public:
    CutDuringWalk(FdSource& inner, int fd, uint64_t cut_at) : inner_(inner), fd_(fd), cut_at_(cut_at) {}
    int64_t read(uint64_t offset, char* buf, size_t len) override {
        if (outline_read_ && !cut_) {
            REQUIRE(::ftruncate(fd_, static_cast<off_t>(cut_at_)) == 0);
            cut_ = true;
        }
        const int64_t r = inner_.read(offset, buf, len);
        if (r >= 0 && static_cast<size_t>(r) < len) outline_read_ = true;
        return r;
    }
    std::string error() const override { return inner_.error(); }
    std::string changed() const override { return inner_.changed(); }
    bool cut() const { return cut_; }

private:
    FdSource& inner_;
    int fd_;
    uint64_t cut_at_;
    bool outline_read_ = false;
    bool cut_ = false;
};

}  // namespace

TEST_CASE("a file that changes while it is checked is an I/O error, with no syntax error at the cut") {
    const std::string text = long_program(200);
    const uint64_t cut = text.find("G81 Z-5.") + 6;  // "G81 Z-" is left: a syntax error if it were the file
    ScratchFile file(text);
    const std::optional<FileStamp> opened = file_stamp(file.fd);
    REQUIRE(opened);
    CHECK(opened->size == text.size());

    SUBCASE("unchanged: no error") {
        FdSource src(file.fd, *opened);
        const FileResult r = check_source_collected(file.path, src);
        CHECK(r.io_error.empty());
        CHECK(syntax_errors(r) == 0);
        CHECK(src.changed().empty());
    }
    SUBCASE("cut after it was opened, before it is read") {
        REQUIRE(::ftruncate(file.fd, static_cast<off_t>(cut)) == 0);
        FdSource src(file.fd, *opened);
        const FileResult r = check_source_collected(file.path, src);
        CHECK(r.io_error == kChangedMessage);
        CHECK(syntax_errors(r) == 0);
    }
    SUBCASE("cut while the walk reads it") {
        FdSource inner(file.fd, *opened);
        CutDuringWalk src(inner, file.fd, cut);
        AnalysisOptions options;
        options.chunk_size = 256;
        const FileResult r = check_source_collected(file.path, src, options);
        CHECK(src.cut());
        CHECK(r.io_error == kChangedMessage);
        CHECK(syntax_errors(r) == 0);
    }
    SUBCASE("longer than when it was opened") {
        REQUIRE(::pwrite(file.fd, "G0 X1\n", 6, static_cast<off_t>(text.size())) == 6);
        FdSource src(file.fd, *opened);
        CHECK(check_source_collected(file.path, src).io_error == kChangedMessage);
    }
    SUBCASE("written in place with the same size") {
        const std::string same = "O1001";  // as long as "O1000"
        REQUIRE(::pwrite(file.fd, same.data(), same.size(), 0) == static_cast<ssize_t>(same.size()));
        const struct timespec times[2] = {{1, 0}, {1, 0}};  // a modification time unlike the one opened
        REQUIRE(::futimens(file.fd, times) == 0);
        FdSource src(file.fd, *opened);
        CHECK(check_source_collected(file.path, src).io_error == kChangedMessage);
    }
    SUBCASE("check_fd and check_path take the stamp when they open the file") {
        CHECK(check_file(file.path, Config{}).io_error.empty());
    }
}

TEST_CASE("--fix writes over a file only when it is the one that was read") {
    const std::string text = "O1000\nG0 X0\nM30\n";
    const std::vector<Edit> edits = {{6, 8, "G00"}};
    ScratchFile file(text);
    const std::optional<FileStamp> opened = file_stamp(file.fd);
    REQUIRE(opened);
    std::string error;

    SUBCASE("unchanged: written") {
        FdSource src(file.fd, *opened);
        CHECK(write_fixes(file.path, *opened, src, edits, error));
        CHECK(slurp(file.path) == "O1000\nG00 X0\nM30\n");
    }
    SUBCASE("changed while it was checked: refused, and left as it is") {
        REQUIRE(::pwrite(file.fd, "G0 X1\n", 6, static_cast<off_t>(text.size())) == 6);
        FdSource src(file.fd, *opened);
        CHECK_FALSE(write_fixes(file.path, *opened, src, edits, error));
        CHECK(error == "it changed while it was being checked");
        CHECK(slurp(file.path) == text + "G0 X1\n");
    }
    SUBCASE("replaced by another file: refused") {
        REQUIRE(write_file_atomically(file.path, text, error));  // the same text, a new inode
        FdSource src(file.fd, *opened);
        CHECK_FALSE(write_fixes(file.path, *opened, src, edits, error));
        CHECK(error == "it changed while it was being checked");
        CHECK(slurp(file.path) == text);
    }
}

TEST_CASE("subprogram names: a folder of 2,000 subprogram files is read once, then one stat answers") {
    namespace fs = std::filesystem;
    const fs::path dir = fs::temp_directory_path() / ("osplint-subdirs-" + std::to_string(::getpid()));
    fs::remove_all(dir);
    fs::create_directories(dir);
    for (int i = 0; i < 2000; ++i)
        std::ofstream(dir / ("P" + std::to_string(i) + ".SSB")) << "O" << (1000 + i) << "\nG0 X1\nRTS\n";
    SubprogramDirectories dirs;
    ProgramNames names;
    dirs.add_names(dir, names);
    CHECK(dirs.files_read() == 2000);
    CHECK(names.size() == 2000);
    CHECK(names.count("O2999"));
    // Asked again (every edit of a document in that folder): nothing is read.
    for (int k = 0; k < 10; ++k) {
        ProgramNames again;
        dirs.add_names(dir, again);
        CHECK(again == names);
    }
    CHECK(dirs.files_read() == 2000);
    // After the files changed on disk, each is read again once.
    dirs.invalidate();
    ProgramNames after;
    dirs.add_names(dir, after);
    CHECK(dirs.files_read() == 4000);
    fs::remove_all(dir);
}

namespace {

// Lines of every length up to a few hundred bytes, some far longer than the
// room a chunk read ahead keeps for a line's start, ended by LF, CR LF or CR.
std::string mixed_lines(std::mt19937& rng, size_t size) {
    std::string t;
    while (t.size() < size) {
        const size_t len = rng() % 16 == 0 ? 200 + rng() % 3000 : rng() % 90;
        for (size_t i = 0; i < len; ++i) t += "GXYZ0123456789. ("[rng() % 17];
        t += rng() % 5 == 0 ? (rng() % 2 ? "\r\n" : "\r") : "\n";
    }
    return t;
}

// A source that fails every read that reaches `fail_at`, as does every other reader it gives.
class FailingSource final : public ByteSource {
public:
    FailingSource(std::string_view text, uint64_t fail_at) : text_(text), fail_at_(fail_at) {}
    int64_t read(uint64_t offset, char* buf, size_t len) override {
        if (offset + len > fail_at_) return -1;
        return MemorySource(text_).read(offset, buf, len);
    }
    std::optional<uint64_t> size() const override { return text_.size(); }
    std::string error() const override { return "read error: the disk went away"; }
    std::unique_ptr<ByteSource> another_reader() const override {
        return std::make_unique<FailingSource>(text_, fail_at_);
    }

private:
    std::string_view text_;
    uint64_t fail_at_;
};

struct SeenLine {
    std::string text, terminator;
    uint32_t line;
    uint32_t start;
    friend bool operator==(const SeenLine&, const SeenLine&) = default;
};

SeenLine seen(const LineRef& l) { return {std::string(l.text), std::string(l.terminator), l.line, l.start}; }

}  // namespace

TEST_CASE("read_ahead: the same lines as reading here, across chunk ends, long lines, seeks and skips") {
    std::mt19937 rng(4711);
    for (int round = 0; round < 40; ++round) {
        const size_t chunk = size_t(64) << (rng() % 6);  // 64 bytes to 2 KiB: room of 16 to 512 bytes
        const std::string text = mixed_lines(rng, 40 * chunk + rng() % 1000);
        MemorySource a(text), b(text);
        LineStream here(a, chunk), ahead(b, chunk);
        ahead.read_ahead();
        REQUIRE(ahead.reads_ahead());
        CHECK_FALSE(here.reads_ahead());
        std::vector<std::pair<uint64_t, uint32_t>> starts;  // of lines taken, to seek back to
        LineRef x, y;
        for (int step = 0; step < 20000; ++step) {
            const unsigned op = rng() % 64;
            if (op == 0 && !starts.empty()) {  // back to a line taken before, near or far
                const auto [offset, line] = starts[rng() % starts.size()];
                here.seek(offset, line);
                ahead.seek(offset, line);
                continue;
            }
            if (op == 1) {  // pass over the first whole line in both buffers, as a run of repeats does
                const std::string_view p = here.buffered(), q = ahead.buffered();
                const size_t lf = p.find('\n');
                if (lf != std::string_view::npos && p.substr(0, lf).find('\r') == std::string_view::npos &&
                    q.size() > lf && q.substr(0, lf + 1) == p.substr(0, lf + 1)) {
                    here.skip_buffered(lf + 1, 1, 0);
                    ahead.skip_buffered(lf + 1, 1, 0);
                    REQUIRE(here.next_offset() == ahead.next_offset());
                    continue;
                }
            }
            const bool got_here = here.next(x);
            const bool got_ahead = ahead.next(y);
            REQUIRE(got_here == got_ahead);
            if (!got_here) break;
            REQUIRE(seen(x) == seen(y));
            REQUIRE(here.next_offset() == ahead.next_offset());
            REQUIRE(text.compare(y.start, y.text.size(), y.text) == 0);
            starts.emplace_back(y.start, y.line);
        }
        CHECK_FALSE(here.error());
        CHECK_FALSE(ahead.error());
    }
}

TEST_CASE("read_ahead: only for a source of more than two chunks that gives another reader") {
    const std::string text = "G0 X1\nG1 Y2\n";
    MemorySource small(text);
    LineStream a(small, 8);
    a.read_ahead();
    CHECK_FALSE(a.reads_ahead());  // 12 bytes: not more than two chunks of 8
    MemorySource large(text + text + text);
    LineStream b(large, 8);
    b.read_ahead();
    CHECK(b.reads_ahead());
    FdSource unsized(-1, std::nullopt);  // size unknown (a pipe)
    LineStream c(unsized, 8);
    c.read_ahead();
    CHECK_FALSE(c.reads_ahead());
}

TEST_CASE("read_ahead: a read that fails on the other thread stops the stream with its error") {
    std::mt19937 rng(99);
    const std::string text = mixed_lines(rng, 64 << 10);
    for (uint64_t fail_at : {uint64_t(10), uint64_t(5000), uint64_t(40000)}) {
        FailingSource src(text, fail_at);
        LineStream ls(src, 1024);
        ls.read_ahead();
        REQUIRE(ls.reads_ahead());
        LineRef l;
        uint64_t end = 0;
        while (ls.next(l)) {
            REQUIRE(text.compare(l.start, l.text.size(), l.text) == 0);
            end = l.end();
        }
        CHECK(ls.error());
        CHECK(end <= fail_at);
        // The walk reports the stream's reason, else the source's error (Walk::fetch).
        const std::string why = ls.stop_reason().empty() ? src.error() : ls.stop_reason();
        CHECK(why == "read error: the disk went away");
    }
}

TEST_CASE("read_ahead: a file cut while it is read ahead is reported as changed") {
    std::mt19937 rng(5);
    const std::string text = mixed_lines(rng, 256 << 10);
    ScratchFile file(text);
    const std::optional<FileStamp> opened = file_stamp(file.fd);
    REQUIRE(opened);
    FdSource src(file.fd, *opened);
    LineStream ls(src, 4096);
    ls.read_ahead();
    REQUIRE(ls.reads_ahead());
    LineRef l;
    for (int i = 0; i < 100; ++i) REQUIRE(ls.next(l));
    const uint64_t cut = text.size() / 2;
    REQUIRE(::ftruncate(file.fd, static_cast<off_t>(cut)) == 0);
    while (ls.next(l)) REQUIRE(text.compare(l.start, l.text.size(), l.text) == 0);
    CHECK(ls.error());
    CHECK(ls.next_offset() <= cut + 4096 * 2);
    const std::string why = ls.stop_reason().empty() ? src.error() : ls.stop_reason();
    CHECK(why == kChangedMessage);
}
