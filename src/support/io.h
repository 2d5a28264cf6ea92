// Reading input: random access to a file's bytes and the lines of them.
//
// Every entry point reads a program through a ByteSource: a buffer in memory
// (the library's check_text, the language server's open documents), a
// regular file read with pread, or a pipe copied to an unlinked temporary
// file as it is read (standard input). A program is never held whole: lines
// are read in chunks by a LineStream, and read again from their offset when
// the analysis needs them a second time (a loop body, a finding's line).
#pragma once

#include <algorithm>
#include <cstddef>
#include <cstdint>
#include <cstdio>
#include <functional>
#include <memory>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

namespace osplint {

// The largest input osplint checks: byte offsets are 32-bit.
inline constexpr uint64_t kMaxInputSize = 0xFFFFFFF0ull;
inline constexpr const char* kTooLargeMessage = "file too large (osplint checks files up to 4 GiB)";
inline constexpr const char* kUtf16Message =
    "the file is UTF-16 (it starts with a UTF-16 byte order mark): save it as ASCII, UTF-8 or Shift-JIS";
// The longest line osplint reads: a block is a line, and a longer one is not
// a part program (it would only make the memory of the check grow with it).
inline constexpr size_t kMaxLineLength = size_t(1) << 20;
// "line N is longer than 1 MiB ...".
std::string line_too_long_message(uint64_t line);

// One line of a file: its text without the terminator, the terminator itself
// ("\n", "\r\n", "\r" or "" for an unterminated last line), its 1-based number
// and the byte offset where it starts.
struct LineRef {
    std::string_view text;
    std::string_view terminator;
    uint32_t line = 1;
    uint32_t start = 0;
    uint32_t end() const { return start + static_cast<uint32_t>(text.size() + terminator.size()); }
};

// What tells that a file is no longer the one that was read: its device,
// inode, size and modification time. A file replaced (a new inode), cut,
// extended or written in place does not keep its stamp.
struct FileStamp {
    uint64_t device = 0;
    uint64_t inode = 0;
    uint64_t size = 0;
    int64_t mtime_sec = 0;
    int64_t mtime_nsec = 0;
    friend bool operator==(const FileStamp&, const FileStamp&) = default;
};
// The stamp of an open file (fstat), or of the file a path names (stat,
// through symbolic links); nullopt when it cannot be had.
std::optional<FileStamp> file_stamp(int fd);
std::optional<FileStamp> file_stamp(const std::string& path);
// What a file that changed while it was read is reported with (an I/O error:
// its findings may be wrong, at the place it was cut above all).
inline constexpr const char* kChangedMessage = "the file changed while it was being checked: check it again";

class ByteSource {
public:
    virtual ~ByteSource() = default;
    // Reads up to `len` bytes at `offset`: the count, 0 at the end, -1 on error.
    virtual int64_t read(uint64_t offset, char* buf, size_t len) = 0;
    // The size when it is known before reading to the end.
    virtual std::optional<uint64_t> size() const { return std::nullopt; }
    // Why the last read failed.
    virtual std::string error() const { return "read error"; }
    // After reading: kChangedMessage when the input is known to be no longer
    // what was read (a file that changed meanwhile), else "".
    virtual std::string changed() const { return {}; }
    // Another reader of the same bytes, which another thread may read while
    // this one is read (each keeps its own error); nullptr when the source
    // cannot make one (a pipe being copied as it is read).
    virtual std::unique_ptr<ByteSource> another_reader() const { return nullptr; }
};

class MemorySource final : public ByteSource {
public:
    explicit MemorySource(std::string_view text) : text_(text) {}
    int64_t read(uint64_t offset, char* buf, size_t len) override;
    std::optional<uint64_t> size() const override { return text_.size(); }
    std::unique_ptr<ByteSource> another_reader() const override { return std::make_unique<MemorySource>(text_); }
    std::string_view text() const { return text_; }

private:
    std::string_view text_;
};

// The bytes [begin, end) of another source, as a source of their own (one
// program of a file, walked alone). The other source must outlive it.
class WindowSource final : public ByteSource {
public:
    WindowSource(ByteSource& inner, uint64_t begin, uint64_t end) : inner_(inner), begin_(begin), end_(end) {}
    int64_t read(uint64_t offset, char* buf, size_t len) override {
        if (offset >= end_ - begin_) return 0;
        return inner_.read(begin_ + offset, buf, std::min<uint64_t>(len, end_ - begin_ - offset));
    }
    std::optional<uint64_t> size() const override { return end_ - begin_; }
    std::string error() const override { return inner_.error(); }

private:
    ByteSource& inner_;
    uint64_t begin_, end_;
};

// Reads `len` bytes at `offset` of a descriptor with pread, retrying short
// reads: the count (short only at the end), or -1 with errno set.
int64_t pread_full(int fd, uint64_t offset, char* buf, size_t len);

// A regular file (or anything pread works on). The descriptor is not owned.
// With the file's stamp when it was opened, a read that finds the file
// shorter or longer than it was fails with kChangedMessage (so a cut line is
// never taken for the program's last line), and changed() compares the stamp
// with the file's at the end.
class FdSource final : public ByteSource {
public:
    FdSource(int fd, std::optional<uint64_t> size) : fd_(fd), size_(size) {}
    FdSource(int fd, const FileStamp& opened) : fd_(fd), size_(opened.size), opened_(opened) {}
    int64_t read(uint64_t offset, char* buf, size_t len) override;
    std::optional<uint64_t> size() const override { return size_; }
    std::string error() const override { return error_; }
    std::string changed() const override;
    // pread does not move the descriptor's offset: two threads may read it.
    std::unique_ptr<ByteSource> another_reader() const override { return std::make_unique<FdSource>(*this); }

private:
    int fd_;
    std::optional<uint64_t> size_;
    std::optional<FileStamp> opened_;
    std::string error_ = "read error";
};

// A pipe or terminal: what is read from it is appended to an unlinked
// temporary file, from which every read is served, so that lines can be read
// again. At most `limit` bytes are taken.
class SpoolSource final : public ByteSource {
public:
    explicit SpoolSource(int fd, uint64_t limit = kMaxInputSize);
    ~SpoolSource() override;
    SpoolSource(const SpoolSource&) = delete;
    SpoolSource& operator=(const SpoolSource&) = delete;
    bool ok() const { return spool_ != nullptr; }
    int64_t read(uint64_t offset, char* buf, size_t len) override;
    std::string error() const override { return error_; }

private:
    bool pull();
    int in_;
    uint64_t limit_;
    FILE* spool_ = nullptr;
    int spool_fd_ = -1;
    uint64_t spooled_ = 0;
    bool in_eof_ = false;
    std::string error_;
    std::vector<char> chunk_;
};

// Copies everything readable from `fd` (at most `limit` bytes) to an unlinked
// temporary file and returns a descriptor of it positioned at its start; -1
// with `error` set on failure. For standard input read by several passes.
int spool_to_temporary_file(int fd, std::string& error, uint64_t limit = kMaxInputSize);

// Replaces `path` with `content` atomically: written to a new temporary file
// in the same directory (created exclusively, so a planted file or symbolic
// link is never followed), flushed to the disk, then renamed over `path`.
// On any failure the temporary file is removed, `path` is left as it was,
// and `error` says why (false is returned). The file keeps the permissions of
// the one it replaces (new: 0666 less the umask).
bool write_file_atomically(const std::string& path, std::string_view content, std::string& error);
// The same, with the content handed over in pieces by `produce`, which
// calls `put` for each and returns false to give up (nothing is replaced;
// `error` is left to `produce` to set when it is not a write error).
using PieceWriter = std::function<bool(std::string_view)>;
bool write_file_atomically(const std::string& path, const std::function<bool(const PieceWriter& put)>& produce,
                           std::string& error);

// The first LF or CR in [p, e), or nullptr.
const char* find_line_break(const char* p, const char* e);
// Whether the byte at `p` (in [p, e)) ends a line: an LF, or a CR that no LF
// follows. A CR at `e - 1` counts as a line end: a caller whose text goes on
// past `e` reads the next byte first.
inline bool ends_line(const char* p, const char* e) {
    return *p == '\n' || (*p == '\r' && !(p + 1 < e && p[1] == '\n'));
}
// The start of the line `n` lines after the one at `p`, each ended as
// ends_line says; nullptr when [p, e) ends fewer than `n` lines.
const char* skip_lines(const char* p, const char* e, uint64_t n);

// The size of a line-reading buffer for `src`: `chunk`, or less when the
// source is known to be smaller (one subprogram of a file must not clear a
// whole chunk). The readers grow it for a line longer than that.
size_t line_buffer_size(const ByteSource& src, size_t chunk);

// Lines of a ByteSource (terminators LF, CRLF and a lone CR). A LineRef stays
// valid until the next call of next() or seek().
class ReadAhead;

class LineStream {
public:
    LineStream(ByteSource& src, size_t chunk);
    ~LineStream();
    LineStream(const LineStream&) = delete;
    LineStream& operator=(const LineStream&) = delete;

    // From now on, the chunk after the buffer is read on another thread while
    // the lines of the buffer are taken, into a second buffer of the same
    // size. Only for a source that can give another reader (a file, a text in
    // memory) and holds more than two chunks; otherwise, or when no thread can
    // be started, reading stays as it was. The lines and errors are the same
    // either way: an error of the other reader is the stream's stop_reason().
    void read_ahead();
    bool reads_ahead() const { return ahead_ != nullptr; }

    // Continues at `offset`, numbering that line `line`.
    void seek(uint64_t offset, uint32_t line);
    // The next line; false at the end of the input or on a read error.
    bool next(LineRef& out);
    bool error() const { return error_; }
    // Why reading stopped when the stream itself stopped it (a line longer
    // than kMaxLineLength, a read of the other thread that failed); empty
    // when the source failed (its error()).
    const std::string& stop_reason() const { return stop_reason_; }
    // Offset (64-bit) of the line next() returned last.
    uint64_t last_start() const { return start64_; }
    // Offset and number of the line next() will return.
    uint64_t next_offset() const { return buf_offset_ + pos_; }
    uint32_t next_line() const { return line_; }
    // The bytes read ahead, from the next line on (its last line may not be whole).
    std::string_view buffered() const { return {buf_.data() + pos_, end_ - pos_}; }
    // Passes over the first `bytes` of buffered(): `lines` whole lines, the
    // last of them starting at `last_start` (an offset into buffered()).
    void skip_buffered(size_t bytes, uint32_t lines, size_t last_start) {
        start64_ = buf_offset_ + pos_ + last_start;
        pos_ += bytes;
        line_ += lines;
    }

private:
    bool fill();
    // Takes the chunk the other thread read, behind the part of a line left
    // in the buffer; false when it cannot (it is dropped and read again).
    bool take_ahead(bool& ok);
    void start_ahead();

    ByteSource* src_;
    size_t chunk_;
    std::vector<char> buf_;
    size_t begin_ = 0;  // the first byte of buf_ that holds input (before it: room for a line's start)
    size_t pos_ = 0, end_ = 0;
    uint64_t buf_offset_ = 0;  // the offset of buf_[0]
    uint64_t start64_ = 0;
    bool eof_ = false;
    bool error_ = false;
    std::string stop_reason_;
    uint32_t line_ = 1;
    std::vector<char> spare_;  // what ahead_ reads into (declared before it: ahead_ ends first)
    size_t headroom_ = 0;      // bytes of spare_ before the chunk ahead_ reads
    std::unique_ptr<ReadAhead> ahead_;
};

}  // namespace osplint

namespace osplint {

// Bytes kept in order: in memory up to `memory_limit`, then in an unlinked
// temporary file. For output that must wait (the findings of a file checked
// in parallel with the one being printed, the JSON report's suppressed list).
class Spool {
public:
    explicit Spool(size_t memory_limit = size_t(4) << 20) : limit_(memory_limit) {}
    ~Spool();
    Spool(const Spool&) = delete;
    Spool& operator=(const Spool&) = delete;

    // False when the temporary file could not be written (the bytes are lost; error() says why).
    bool append(std::string_view bytes);
    bool empty() const { return memory_.empty() && file_bytes_ == 0; }
    uint64_t size() const { return file_bytes_ + memory_.size(); }
    // Hands every byte to `out` in pieces, in order, then empties the spool.
    template <class F>
    bool drain(F&& out) {
        if (file_) {
            if (!drain_file([&](std::string_view piece) { out(piece); })) return false;
        }
        if (!memory_.empty()) out(std::string_view(memory_));
        clear();
        return error_.empty();
    }
    void clear();
    const std::string& error() const { return error_; }

private:
    bool drain_file(const std::function<void(std::string_view)>& out);
    size_t limit_;
    std::string memory_;
    FILE* file_ = nullptr;
    uint64_t file_bytes_ = 0;
    std::string error_;
};

}  // namespace osplint
