#include "support/io.h"

#include <fcntl.h>
#include <sys/stat.h>
#include <sys/statvfs.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <condition_variable>
#include <cstring>
#include <mutex>
#include <system_error>
#include <thread>

#if defined(__SSE2__)
#include <emmintrin.h>
#endif

namespace osplint {

std::string line_too_long_message(uint64_t line) {
    return "line " + std::to_string(line) + " is longer than " + std::to_string(kMaxLineLength) +
           " bytes (1 MiB): not a part program";
}

int64_t MemorySource::read(uint64_t offset, char* buf, size_t len) {
    if (offset >= text_.size()) return 0;
    const size_t n = std::min<uint64_t>(len, text_.size() - offset);
    std::memcpy(buf, text_.data() + offset, n);
    return static_cast<int64_t>(n);
}

int64_t pread_full(int fd, uint64_t offset, char* buf, size_t len) {
    size_t done = 0;
    while (done < len) {
        const ssize_t r = ::pread(fd, buf + done, len - done, static_cast<off_t>(offset + done));
        if (r < 0) {
            if (errno == EINTR) continue;
            return -1;
        }
        if (r == 0) break;
        done += static_cast<size_t>(r);
    }
    return static_cast<int64_t>(done);
}

namespace {
FileStamp stamp_of(const struct stat& st) {
    return FileStamp{static_cast<uint64_t>(st.st_dev), static_cast<uint64_t>(st.st_ino),
                     static_cast<uint64_t>(st.st_size), static_cast<int64_t>(st.st_mtim.tv_sec),
                     static_cast<int64_t>(st.st_mtim.tv_nsec)};
}
}  // namespace

std::optional<FileStamp> file_stamp(int fd) {
    struct stat st;
    if (::fstat(fd, &st) != 0) return std::nullopt;
    return stamp_of(st);
}

std::optional<FileStamp> file_stamp(const std::string& path) {
    struct stat st;
    if (::stat(path.c_str(), &st) != 0) return std::nullopt;
    return stamp_of(st);
}

int64_t FdSource::read(uint64_t offset, char* buf, size_t len) {
    const int64_t r = pread_full(fd_, offset, buf, len);
    if (r < 0) {
        error_ = std::string("read error: ") + std::strerror(errno);
        return r;
    }
    if (opened_) {
        // Short before the size the file had, or bytes past it: not the file opened.
        const uint64_t end = offset + static_cast<uint64_t>(r);
        if ((static_cast<size_t>(r) < len && end < opened_->size) || end > opened_->size) {
            error_ = kChangedMessage;
            return -1;
        }
    }
    return r;
}

std::string FdSource::changed() const {
    if (!opened_) return {};
    const std::optional<FileStamp> now = file_stamp(fd_);
    return now && *now == *opened_ ? std::string() : std::string(kChangedMessage);
}

SpoolSource::SpoolSource(int fd, uint64_t limit) : in_(fd), limit_(limit) {
    spool_ = std::tmpfile();
    if (spool_) spool_fd_ = fileno(spool_);
    else error_ = std::string("cannot create a temporary file: ") + std::strerror(errno);
}

SpoolSource::~SpoolSource() {
    if (spool_) std::fclose(spool_);
}

int64_t SpoolSource::read(uint64_t offset, char* buf, size_t len) {
    if (!spool_) return -1;
    while (offset + len > spooled_ && !in_eof_)
        if (!pull()) return -1;
    if (offset >= spooled_) return 0;
    const int64_t r = pread_full(spool_fd_, offset, buf, std::min<uint64_t>(len, spooled_ - offset));
    if (r < 0) error_ = std::string("cannot read the temporary copy of the input: ") + std::strerror(errno);
    return r;
}

bool SpoolSource::pull() {
    if (chunk_.empty()) chunk_.resize(size_t(1) << 20);
    ssize_t r;
    do {
        r = ::read(in_, chunk_.data(), chunk_.size());
    } while (r < 0 && errno == EINTR);
    if (r < 0) {
        error_ = std::string("read error: ") + std::strerror(errno);
        return false;
    }
    if (r == 0) {
        in_eof_ = true;
        return true;
    }
    if (spooled_ + static_cast<uint64_t>(r) > limit_) {
        error_ = kTooLargeMessage;
        return false;
    }
    size_t done = 0;
    while (done < static_cast<size_t>(r)) {
        const ssize_t w = ::pwrite(spool_fd_, chunk_.data() + done, static_cast<size_t>(r) - done,
                                   static_cast<off_t>(spooled_ + done));
        if (w < 0) {
            if (errno == EINTR) continue;
            error_ = std::string("cannot write the temporary copy of the input: ") + std::strerror(errno);
            return false;
        }
        done += static_cast<size_t>(w);
    }
    spooled_ += static_cast<uint64_t>(r);
    return true;
}

int spool_to_temporary_file(int fd, std::string& error, uint64_t limit) {
    FILE* f = std::tmpfile();
    if (!f) {
        error = std::string("cannot create a temporary file: ") + std::strerror(errno);
        return -1;
    }
    const int out = ::dup(fileno(f));
    std::fclose(f);  // the duplicate keeps the unlinked file open
    if (out < 0) {
        error = std::string("cannot create a temporary file: ") + std::strerror(errno);
        return -1;
    }
    auto fail = [&](std::string why) {
        error = std::move(why);
        ::close(out);
        return -1;
    };
    std::vector<char> buf(size_t(1) << 20);
    uint64_t total = 0;
    uint64_t line = 1;        // the line being copied
    uint64_t line_bytes = 0;  // its length so far
    bool after_cr = false;    // the last byte copied was a CR (a LF next ends no line)
    uint64_t next_room_check = 0;
    while (true) {
        const ssize_t r = ::read(fd, buf.data(), buf.size());
        if (r < 0) {
            if (errno == EINTR) continue;
            return fail(std::string("read error: ") + std::strerror(errno));
        }
        if (r == 0) break;
        total += static_cast<uint64_t>(r);
        if (total > limit) return fail(kTooLargeMessage);
        // Lines: a line longer than any osplint reads ends the copy.
        const char* p = buf.data();
        const char* const e = p + r;
        if (after_cr && *p == '\n') ++p;
        after_cr = false;
        while (const char* b = find_line_break(p, e)) {
            ++line;
            line_bytes = 0;
            p = b + 1;
            if (*b == '\r') {
                if (p == e) after_cr = true;
                else if (*p == '\n') ++p;
            }
        }
        line_bytes += static_cast<uint64_t>(e - p);
        if (line_bytes > kMaxLineLength) return fail(line_too_long_message(line));
        // Room on the disk: the copy stops before it fills the disk.
        if (total >= next_room_check) {
            struct statvfs vfs;
            if (::fstatvfs(out, &vfs) == 0 && uint64_t(vfs.f_bavail) * vfs.f_frsize < (uint64_t(256) << 20))
                return fail("not enough room left on the disk for a temporary copy of standard input (" +
                            std::to_string(total >> 20) + " MiB read)");
            next_room_check = total + (uint64_t(64) << 20);
        }
        for (ssize_t done = 0; done < r;) {
            const ssize_t w = ::write(out, buf.data() + done, static_cast<size_t>(r - done));
            if (w < 0) {
                if (errno == EINTR) continue;
                return fail(std::string("cannot write a temporary file: ") + std::strerror(errno));
            }
            done += w;
        }
    }
    ::lseek(out, 0, SEEK_SET);
    return out;
}

bool write_file_atomically(const std::string& path, std::string_view content, std::string& error) {
    return write_file_atomically(path, [&](const PieceWriter& put) { return put(content); }, error);
}

bool write_file_atomically(const std::string& path, const std::function<bool(const PieceWriter& put)>& produce,
                           std::string& error) {
    const size_t slash = path.rfind('/');
    const std::string dir = slash == std::string::npos ? std::string(".") : path.substr(0, slash + 1);
    const std::string name = slash == std::string::npos ? path : path.substr(slash + 1);
    std::string tmp = (slash == std::string::npos ? std::string() : dir) + "." + name + ".XXXXXX";
    const int fd = ::mkostemp(tmp.data(), O_CLOEXEC);  // O_CREAT | O_EXCL: never an existing file or link
    if (fd < 0) {
        error = std::string("cannot create a temporary file beside it: ") + std::strerror(errno);
        return false;
    }
    auto fail = [&](const char* what) {
        error = std::string(what) + ": " + std::strerror(errno);
        ::close(fd);
        ::unlink(tmp.c_str());
        return false;
    };
    struct stat st;
    mode_t mode;
    if (::stat(path.c_str(), &st) == 0) {
        mode = st.st_mode & 07777;
    } else {
        const mode_t mask = ::umask(0);
        ::umask(mask);
        mode = 0666 & ~mask;
    }
    if (::fchmod(fd, mode) != 0) return fail("cannot set the permissions of the temporary file");
    bool write_failed = false;
    const PieceWriter put = [&](std::string_view piece) {
        for (size_t done = 0; done < piece.size();) {
            const ssize_t w = ::write(fd, piece.data() + done, piece.size() - done);
            if (w < 0) {
                if (errno == EINTR) continue;
                write_failed = true;
                return false;
            }
            done += static_cast<size_t>(w);
        }
        return true;
    };
    if (!produce(put)) {
        if (write_failed) return fail("write error");
        const int saved = errno;
        ::close(fd);
        ::unlink(tmp.c_str());
        errno = saved;
        if (error.empty()) error = "the content could not be made";
        return false;
    }
    if (::fsync(fd) != 0) return fail("write error");
    if (::close(fd) != 0) {
        error = std::string("write error: ") + std::strerror(errno);
        ::unlink(tmp.c_str());
        return false;
    }
    if (::rename(tmp.c_str(), path.c_str()) != 0) {
        error = std::string("cannot replace it: ") + std::strerror(errno);
        ::unlink(tmp.c_str());
        return false;
    }
    // The rename itself on the disk.
    const int dfd = ::open(dir.c_str(), O_RDONLY | O_DIRECTORY | O_CLOEXEC);
    if (dfd >= 0) {
        ::fsync(dfd);
        ::close(dfd);
    }
    return true;
}

const char* find_line_break(const char* p, const char* e) {
#if defined(__SSE2__)
    const __m128i lf = _mm_set1_epi8('\n');
    const __m128i cr = _mm_set1_epi8('\r');
    const auto breaks = [&](const char* q) {
        const __m128i v = _mm_loadu_si128(reinterpret_cast<const __m128i*>(q));
        return static_cast<unsigned>(_mm_movemask_epi8(_mm_or_si128(_mm_cmpeq_epi8(v, lf), _mm_cmpeq_epi8(v, cr))));
    };
    // Thirty-two bytes at a time: most lines of a posted program end within
    // the first step, so whether a second one is needed is seldom guessed wrong.
    for (; e - p >= 32; p += 32) {
        const uint32_t hits = breaks(p) | (breaks(p + 16) << 16);
        if (hits) return p + __builtin_ctz(hits);
    }
    if (e - p >= 16) {
        if (const unsigned hits = breaks(p)) return p + __builtin_ctz(hits);
        p += 16;
    }
#endif
    for (; p < e; ++p)
        if (*p == '\n' || *p == '\r') return p;
    return nullptr;
}

const char* skip_lines(const char* p, const char* e, uint64_t n) {
    if (n == 0) return p;
#if defined(__SSE2__)
    // Sixteen bytes at a time, and the byte after them (a CR at the end of
    // the block ends a line unless an LF follows it).
    const __m128i lf = _mm_set1_epi8('\n');
    const __m128i cr = _mm_set1_epi8('\r');
    for (; e - p > 16; p += 16) {
        const __m128i v = _mm_loadu_si128(reinterpret_cast<const __m128i*>(p));
        const unsigned l = static_cast<unsigned>(_mm_movemask_epi8(_mm_cmpeq_epi8(v, lf)));
        const unsigned c = static_cast<unsigned>(_mm_movemask_epi8(_mm_cmpeq_epi8(v, cr)));
        if (!(l | c)) continue;
        const unsigned lf_next = (l >> 1) | (p[16] == '\n' ? 0x8000u : 0u);
        unsigned ends = l | (c & ~lf_next);
        const auto count = static_cast<uint64_t>(__builtin_popcount(ends));
        if (count < n) {
            n -= count;
            continue;
        }
        for (; n > 1; --n) ends &= ends - 1;  // the n-th line end of the block
        return p + __builtin_ctz(ends) + 1;
    }
#endif
    for (; p < e; ++p)
        if (ends_line(p, e) && --n == 0) return p + 1;
    return nullptr;
}

// One read at a time on a thread of its own, from another reader of the
// source: start() asks for it, wait() takes its result.
class ReadAhead {
public:
    explicit ReadAhead(std::unique_ptr<ByteSource> src) : src_(std::move(src)), thread_([this] { serve(); }) {}
    ~ReadAhead() {
        {
            const std::lock_guard<std::mutex> lock(mutex_);
            stop_ = true;
        }
        wake_.notify_all();
        thread_.join();  // after the read it may be doing: its buffer outlives it
    }
    ReadAhead(const ReadAhead&) = delete;
    ReadAhead& operator=(const ReadAhead&) = delete;

    void start(uint64_t offset, char* buf, size_t len) {
        {
            const std::lock_guard<std::mutex> lock(mutex_);
            offset_ = offset;
            buf_ = buf;
            len_ = len;
            state_ = State::Asked;
        }
        pending_ = true;
        wake_.notify_all();
    }
    // The count read (as ByteSource::read), once the read has ended.
    int64_t wait() {
        std::unique_lock<std::mutex> lock(mutex_);
        wake_.wait(lock, [&] { return state_ == State::Done; });
        state_ = State::Idle;
        pending_ = false;
        return result_;
    }
    bool pending() const { return pending_; }
    uint64_t offset() const { return offset_; }          // of the last read asked
    std::string error() const { return src_->error(); }  // after wait()

private:
    enum class State { Idle, Asked, Done };
    void serve() {
        std::unique_lock<std::mutex> lock(mutex_);
        while (true) {
            wake_.wait(lock, [&] { return stop_ || state_ == State::Asked; });
            if (stop_) return;
            const uint64_t offset = offset_;
            char* const buf = buf_;
            const size_t len = len_;
            lock.unlock();
            const int64_t r = src_->read(offset, buf, len);
            lock.lock();
            result_ = r;
            state_ = State::Done;
            wake_.notify_all();
        }
    }

    std::unique_ptr<ByteSource> src_;
    std::mutex mutex_;
    std::condition_variable wake_;
    State state_ = State::Idle;
    bool stop_ = false;
    uint64_t offset_ = 0;
    char* buf_ = nullptr;
    size_t len_ = 0;
    int64_t result_ = 0;
    bool pending_ = false;  // the owner's: a read was asked and not yet waited for
    std::thread thread_;    // last: it starts once the rest is ready
};

LineStream::LineStream(ByteSource& src, size_t chunk) : src_(&src), chunk_(chunk ? chunk : 1) {}
LineStream::~LineStream() = default;

void LineStream::read_ahead() {
    if (ahead_) return;
    const std::optional<uint64_t> size = src_->size();
    // Room before the chunk for the start of a line cut by the chunk's
    // start; a longer start is read again with the chunk (fill).
    const size_t headroom = std::min<size_t>(chunk_ / 4, size_t(64) << 10);
    if (!size || *size / 2 <= chunk_ || headroom == 0) return;
    std::unique_ptr<ByteSource> reader = src_->another_reader();
    if (!reader) return;
    try {
        ahead_ = std::make_unique<ReadAhead>(std::move(reader));
    } catch (const std::system_error&) {
        return;  // no thread: read here
    }
    headroom_ = headroom;
    if (!eof_ && !error_ && end_ > 0) start_ahead();
}

void LineStream::start_ahead() {
    const uint64_t at = buf_offset_ + end_;
    const std::optional<uint64_t> size = src_->size();
    if (size && at >= *size) return;  // the read here finds the end (or that the file grew)
    if (spare_.size() < headroom_ + chunk_) spare_.resize(headroom_ + chunk_);
    ahead_->start(at, spare_.data() + headroom_, chunk_);
}

bool LineStream::take_ahead(bool& ok) {
    ok = true;
    if (!ahead_ || !ahead_->pending()) return false;
    const int64_t r = ahead_->wait();  // even when it is dropped: the thread writes into spare_
    const uint64_t at = buf_offset_ + end_;
    const size_t left = end_ - pos_;
    if (ahead_->offset() != at || left > headroom_) return false;
    if (r < 0) {
        error_ = true;
        stop_reason_ = ahead_->error();
        ok = false;
        return true;
    }
    std::memcpy(spare_.data() + headroom_ - left, buf_.data() + pos_, left);
    buf_.swap(spare_);
    buf_offset_ = at - headroom_;
    begin_ = pos_ = headroom_ - left;
    end_ = headroom_ + static_cast<size_t>(r);
    if (r == 0) eof_ = true;
    else start_ahead();
    return true;
}

void LineStream::seek(uint64_t offset, uint32_t line) {
    line_ = line;
    if (offset >= buf_offset_ + begin_ && offset <= buf_offset_ + end_) {  // still in the buffer
        pos_ = static_cast<size_t>(offset - buf_offset_);
        return;
    }
    buf_offset_ = offset;
    begin_ = pos_ = end_ = 0;
    eof_ = false;
}

size_t line_buffer_size(const ByteSource& src, size_t chunk) {
    const std::optional<uint64_t> size = src.size();
    // One byte more than the source, so that the read that finds its end needs no second buffer.
    return size ? static_cast<size_t>(std::min<uint64_t>(chunk, std::max<uint64_t>(*size + 1, 256))) : chunk;
}

bool LineStream::next(LineRef& out) {
    while (true) {
        const char* p = buf_.data() + pos_;
        const size_t avail = end_ - pos_;
        const char* brk = find_line_break(p, p + avail);
        size_t text_len = 0, term_len = 0;
        bool found = false;
        if (brk && *brk == '\r') {
            text_len = static_cast<size_t>(brk - p);
            if (text_len + 1 < avail) {
                term_len = p[text_len + 1] == '\n' ? 2 : 1;
                found = true;
            } else if (eof_) {
                term_len = 1;
                found = true;
            }
        } else if (brk) {
            text_len = static_cast<size_t>(brk - p);
            term_len = 1;
            found = true;
        } else if (eof_) {
            if (avail == 0) return false;
            text_len = avail;
            found = true;
        }
        if (found) {
            if (text_len > kMaxLineLength) {
                error_ = true;
                stop_reason_ = line_too_long_message(line_);
                return false;
            }
            out.text = std::string_view(p, text_len);
            out.terminator = std::string_view(p + text_len, term_len);
            out.line = line_++;
            out.start = static_cast<uint32_t>(buf_offset_ + pos_);
            start64_ = buf_offset_ + pos_;
            pos_ += text_len + term_len;
            return true;
        }
        if (!fill()) return false;
    }
}

bool LineStream::fill() {
    bool ok = true;
    if (take_ahead(ok)) return ok;
    if (pos_ > 0) {
        std::memmove(buf_.data(), buf_.data() + pos_, end_ - pos_);
        end_ -= pos_;
        buf_offset_ += pos_;
        pos_ = 0;
    }
    begin_ = 0;
    if (end_ > kMaxLineLength) {  // the line in the buffer has no end in sight
        error_ = true;
        stop_reason_ = line_too_long_message(line_);
        return false;
    }
    if (buf_.size() < chunk_) {
        const size_t want = line_buffer_size(*src_, chunk_);
        if (buf_.size() < want) buf_.resize(want);
    }
    if (end_ == buf_.size()) buf_.resize(buf_.size() * 2);  // a line longer than the buffer
    const int64_t r = src_->read(buf_offset_ + end_, buf_.data() + end_, buf_.size() - end_);
    if (r < 0) {
        error_ = true;
        return false;
    }
    if (r == 0) eof_ = true;
    end_ += static_cast<size_t>(r);
    if (ahead_ && r > 0) start_ahead();
    return true;
}

}  // namespace osplint

namespace osplint {

Spool::~Spool() {
    if (file_) std::fclose(file_);
}

bool Spool::append(std::string_view bytes) {
    if (!error_.empty()) return false;
    memory_.append(bytes);
    if (memory_.size() <= limit_) return true;
    if (!file_) {
        file_ = std::tmpfile();
        if (!file_) {
            error_ = std::string("cannot create a temporary file: ") + std::strerror(errno);
            return false;
        }
    }
    if (std::fwrite(memory_.data(), 1, memory_.size(), file_) != memory_.size()) {
        error_ = std::string("cannot write a temporary file: ") + std::strerror(errno);
        return false;
    }
    file_bytes_ += memory_.size();
    memory_.clear();
    return true;
}

bool Spool::drain_file(const std::function<void(std::string_view)>& out) {
    if (std::fflush(file_) != 0 || std::fseek(file_, 0, SEEK_SET) != 0) {
        error_ = std::string("cannot read a temporary file: ") + std::strerror(errno);
        return false;
    }
    std::vector<char> buf(size_t(1) << 20);
    uint64_t left = file_bytes_;
    while (left > 0) {
        const size_t n = std::fread(buf.data(), 1, std::min<uint64_t>(buf.size(), left), file_);
        if (n == 0) {
            error_ = "cannot read a temporary file";
            return false;
        }
        out(std::string_view(buf.data(), n));
        left -= n;
    }
    return true;
}

void Spool::clear() {
    memory_.clear();
    if (file_) {
        std::fclose(file_);
        file_ = nullptr;
    }
    file_bytes_ = 0;
}

}  // namespace osplint
