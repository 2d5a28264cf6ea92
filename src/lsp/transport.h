// Language server, layer 1: the byte transport and LSP base-protocol framing.
//
// A message is `Content-Length: N\r\n` (other headers allowed and ignored)
// `\r\n` and N bytes of JSON. The reader never trusts its input: a length that
// is not a number or larger than kMaxContentLength is refused without
// allocating it, a header block without a length is refused, and bytes that
// are not a header (garbage, the body of a refused message) are skipped until
// the next `Content-Length:` appears. Each refusal is reported once, so the
// server can answer it with a parse error; none of them ends the session.
//
// Sources and sinks are abstract so that tests run the server over memory
// (lsp_test_transport in tests/unit) and `osplint lsp` over stdin/stdout.
#pragma once

#include <condition_variable>
#include <cstddef>
#include <cstdint>
#include <deque>
#include <mutex>
#include <string>
#include <string_view>

namespace osplint::lsp {

// Largest body accepted (64 MiB): a 1 MB part program is one message.
inline constexpr std::size_t kMaxContentLength = 64u << 20;
// Longest header line kept while looking for the end of a header line.
inline constexpr std::size_t kMaxHeaderLine = 4096;

class InputStream {
public:
    virtual ~InputStream() = default;
    // Reads up to `n` bytes into `buf`; blocks until at least one byte is
    // available. Returns 0 at end of input.
    virtual std::size_t read(char* buf, std::size_t n) = 0;
};

class OutputStream {
public:
    virtual ~OutputStream() = default;
    // Writes all of `bytes` (and flushes). Returns false when the peer is gone.
    virtual bool write(std::string_view bytes) = 0;
};

// A file descriptor (stdin/stdout of `osplint lsp`). Retries on EINTR.
class FdInput final : public InputStream {
public:
    explicit FdInput(int fd) : fd_(fd) {}
    std::size_t read(char* buf, std::size_t n) override;

private:
    int fd_;
};

class FdOutput final : public OutputStream {
public:
    explicit FdOutput(int fd) : fd_(fd) {}
    bool write(std::string_view bytes) override;

private:
    int fd_;
};

// An in-memory pipe: one thread pushes bytes, the reader blocks until bytes
// arrive or the pipe is closed (then reads return 0). Used by tests.
class PipeInput final : public InputStream {
public:
    void push(std::string_view bytes);
    void close();
    std::size_t read(char* buf, std::size_t n) override;

private:
    std::mutex m_;
    std::condition_variable cv_;
    std::deque<char> data_;
    bool closed_ = false;
};

// Collects what the server writes and hands it back one message body at a
// time (tests, the benchmark). The server's output is always well framed.
class MemoryOutput final : public OutputStream {
public:
    bool write(std::string_view bytes) override;
    // The next body, waiting up to `timeout_ms`; empty string on timeout.
    std::string next(int timeout_ms);
    void close();  // later writes fail (a client that went away)

private:
    bool take(std::string& body);
    std::mutex m_;
    std::condition_variable cv_;
    std::string buf_;
    bool closed_ = false;
};

// Frames one message body for writing.
std::string frame(std::string_view body);

struct ReadResult {
    enum Kind { Message, Error, Eof } kind = Eof;
    std::string body;     // Message: the body
    std::string problem;  // Error: what was refused
};

// Splits a byte stream into message bodies.
class FrameReader {
public:
    explicit FrameReader(InputStream& source) : src_(source) {}
    ReadResult next();

private:
    bool fill();  // reads more bytes; false at end of input
    void compact();
    ReadResult refuse(std::string problem);
    std::size_t find_content_length(std::size_t from, std::size_t to) const;

    InputStream& src_;
    std::string buf_;
    std::size_t pos_ = 0;
    bool eof_ = false;
    bool skipping_ = false;  // inside garbage: skip silently to the next header
};

}  // namespace osplint::lsp
