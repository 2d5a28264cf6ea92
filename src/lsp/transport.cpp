#include "lsp/transport.h"

#include <unistd.h>

#include <algorithm>
#include <cctype>
#include <cerrno>
#include <chrono>
#include <optional>

namespace osplint::lsp {

std::size_t FdInput::read(char* buf, std::size_t n) {
    for (;;) {
        const ssize_t r = ::read(fd_, buf, n);
        if (r >= 0) return static_cast<std::size_t>(r);
        if (errno == EINTR) continue;
        return 0;
    }
}

bool FdOutput::write(std::string_view bytes) {
    while (!bytes.empty()) {
        const ssize_t r = ::write(fd_, bytes.data(), bytes.size());
        if (r < 0) {
            if (errno == EINTR) continue;
            return false;
        }
        bytes.remove_prefix(static_cast<std::size_t>(r));
    }
    return true;
}

void PipeInput::push(std::string_view bytes) {
    {
        std::lock_guard lock(m_);
        data_.insert(data_.end(), bytes.begin(), bytes.end());
    }
    cv_.notify_all();
}

void PipeInput::close() {
    {
        std::lock_guard lock(m_);
        closed_ = true;
    }
    cv_.notify_all();
}

std::size_t PipeInput::read(char* buf, std::size_t n) {
    std::unique_lock lock(m_);
    cv_.wait(lock, [&] { return closed_ || !data_.empty(); });
    const std::size_t k = std::min(n, data_.size());
    std::copy_n(data_.begin(), k, buf);
    data_.erase(data_.begin(), data_.begin() + static_cast<std::ptrdiff_t>(k));
    return k;
}

bool MemoryOutput::write(std::string_view bytes) {
    {
        std::lock_guard lock(m_);
        if (closed_) return false;
        buf_.append(bytes);
    }
    cv_.notify_all();
    return true;
}

void MemoryOutput::close() {
    std::lock_guard lock(m_);
    closed_ = true;
}

bool MemoryOutput::take(std::string& body) {
    const std::size_t end = buf_.find("\r\n\r\n");
    if (end == std::string::npos) return false;
    const std::string_view header(buf_.data(), end);
    const std::size_t colon = header.find(':');
    if (colon == std::string_view::npos) return false;
    const std::size_t n = std::stoul(std::string(header.substr(colon + 1)));
    if (buf_.size() < end + 4 + n) return false;
    body = buf_.substr(end + 4, n);
    buf_.erase(0, end + 4 + n);
    return true;
}

std::string MemoryOutput::next(int timeout_ms) {
    std::unique_lock lock(m_);
    std::string body;
    cv_.wait_for(lock, std::chrono::milliseconds(timeout_ms), [&] { return take(body); });
    return body;
}

std::string frame(std::string_view body) {
    std::string out = "Content-Length: " + std::to_string(body.size()) + "\r\n\r\n";
    out.append(body);
    return out;
}

namespace {

constexpr std::string_view kContentLength = "content-length:";

bool is_token_char(char c) {
    const auto u = static_cast<unsigned char>(c);
    if (std::isalnum(u)) return true;
    return std::string_view("!#$%&'*+-.^_`|~").find(c) != std::string_view::npos;
}

bool iequals(std::string_view a, std::string_view b) {
    if (a.size() != b.size()) return false;
    for (std::size_t i = 0; i < a.size(); ++i)
        if (std::tolower(static_cast<unsigned char>(a[i])) != std::tolower(static_cast<unsigned char>(b[i])))
            return false;
    return true;
}

std::string_view trim(std::string_view s) {
    while (!s.empty() && (s.front() == ' ' || s.front() == '\t')) s.remove_prefix(1);
    while (!s.empty() && (s.back() == ' ' || s.back() == '\t')) s.remove_suffix(1);
    return s;
}

// A printable excerpt of refused header text for the error message.
std::string excerpt(std::string_view s) {
    std::string out;
    for (char c : s.substr(0, 40)) {
        const auto u = static_cast<unsigned char>(c);
        out += (u >= 0x20 && u < 0x7F) ? c : '?';
    }
    if (s.size() > 40) out += "...";
    return out;
}

}  // namespace

bool FrameReader::fill() {
    if (eof_) return false;
    compact();
    char chunk[65536];
    const std::size_t n = src_.read(chunk, sizeof chunk);
    if (n == 0) {
        eof_ = true;
        return false;
    }
    buf_.append(chunk, n);
    return true;
}

void FrameReader::compact() {
    if (pos_ > 0 && (pos_ == buf_.size() || pos_ >= (1u << 16))) {
        buf_.erase(0, pos_);
        pos_ = 0;
    }
}

std::size_t FrameReader::find_content_length(std::size_t from, std::size_t to) const {
    if (to < from + kContentLength.size()) return std::string::npos;
    for (std::size_t i = from; i + kContentLength.size() <= to; ++i) {
        if (buf_[i] != 'C' && buf_[i] != 'c') continue;
        if (iequals(std::string_view(buf_).substr(i, kContentLength.size()), kContentLength)) return i;
    }
    return std::string::npos;
}

ReadResult FrameReader::refuse(std::string problem) {
    skipping_ = true;
    ReadResult r;
    r.kind = ReadResult::Error;
    r.problem = std::move(problem);
    return r;
}

namespace {
// The value of a Content-Length header: decimal digits, at most
// kMaxContentLength; nullopt for anything else.
std::optional<std::size_t> content_length(std::string_view value) {
    if (value.empty() || value.size() > 12) return std::nullopt;
    std::size_t n = 0;
    for (char c : value) {
        if (c < '0' || c > '9') return std::nullopt;
        n = n * 10 + static_cast<std::size_t>(c - '0');
    }
    if (n > kMaxContentLength) return std::nullopt;
    return n;
}
}  // namespace

ReadResult FrameReader::next() {
    bool have_headers = false;
    bool have_length = false;
    std::size_t length = 0;
    std::string bad_length;  // the refused value, when there was one
    auto reset_block = [&] {
        have_headers = have_length = false;
        length = 0;
        bad_length.clear();
    };

    for (;;) {
        const std::size_t eol = buf_.find('\n', pos_);
        if (eol == std::string::npos) {
            if (buf_.size() - pos_ > kMaxHeaderLine) {
                // An overlong line: never a header. Resume at a later
                // `Content-Length:` or keep only a tail that could start one.
                const std::size_t k = find_content_length(pos_ + 1, buf_.size());
                const bool was_skipping = skipping_;
                reset_block();
                if (k != std::string::npos) {
                    pos_ = k;
                } else {
                    pos_ = buf_.size() - (kContentLength.size() - 1);
                }
                if (!was_skipping)
                    return refuse("header line longer than " + std::to_string(kMaxHeaderLine) + " bytes");
                continue;
            }
            if (!fill()) return ReadResult{};
            continue;
        }
        std::string_view line(buf_.data() + pos_, eol - pos_);
        if (!line.empty() && line.back() == '\r') line.remove_suffix(1);

        if (line.empty()) {
            pos_ = eol + 1;
            if (skipping_ || !have_headers) continue;  // blank lines between messages
            if (!bad_length.empty()) return refuse("Content-Length '" + excerpt(bad_length) + "' refused");
            if (!have_length) return refuse("header block without Content-Length");
            // The body: exactly `length` bytes.
            while (buf_.size() - pos_ < length)
                if (!fill()) return ReadResult{};
            ReadResult r;
            r.kind = ReadResult::Message;
            r.body = buf_.substr(pos_, length);
            pos_ += length;
            compact();
            return r;
        }

        // `Name: value` with a token name?
        const std::size_t colon = line.find(':');
        bool header = colon != std::string_view::npos && colon > 0;
        for (std::size_t i = 0; header && i < colon; ++i)
            if (!is_token_char(line[i])) header = false;
        const bool is_length = header && iequals(line.substr(0, colon + 1), kContentLength);

        if (!header || (skipping_ && !is_length)) {
            // Garbage (or the body of a refused message): resume at a
            // `Content-Length:` inside this line, else drop the line.
            const std::size_t k = find_content_length(pos_ + 1, eol);
            const bool was_skipping = skipping_;
            reset_block();
            pos_ = k != std::string::npos ? k : eol + 1;
            if (!was_skipping) return refuse("not a header: '" + excerpt(line) + "'");
            continue;
        }
        skipping_ = false;
        have_headers = true;
        if (is_length) {
            const std::string_view value = trim(line.substr(colon + 1));
            const std::optional<std::size_t> n = content_length(value);
            have_length = n.has_value();
            length = n.value_or(0);
            if (n) bad_length.clear();
            else bad_length = value.empty() ? std::string("(empty)") : std::string(value);
        }
        pos_ = eol + 1;
    }
}

}  // namespace osplint::lsp
