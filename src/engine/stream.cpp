// The streaming check (see stream.h).
//
// Structure:
//   ByteSource      random access to the input (memory, a regular file, a pipe
//                   copied to a temporary file as it is read)
//   LineStream      lines from a ByteSource, read in chunks
//   Positions       byte offset -> line and columns without a whole-file index:
//                   the lines in hand answer directly, older ones are found
//                   again from a checkpoint every kCheckpointLines lines
//   StreamContext   the RuleContext of the streaming analysis (diagnostics are
//                   made exactly as the analyzer's Context makes them)
//   Suppressions    the directives of analyzer/suppress.h, collected block by
//                   block and applied at the end as apply_suppressions does
//   Checker         programs, one at a time: streamed block by block, or
//                   buffered and analysed with the control-flow fixpoint
#include "engine/stream.h"

#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>

#include <algorithm>
#include <cctype>
#include <cerrno>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <functional>
#include <map>
#include <memory>
#include <optional>
#include <set>
#include <unordered_map>
#include <vector>

#if defined(__SSE2__)
#include <emmintrin.h>
#endif

#include <fmt/format.h>

#include "catalog/catalog.h"
#include "semantics/eval.h"
#include "syntax/frontend.h"
#include "syntax/frontend_fast.h"
#include "rules/registry.h"
#include "engine/suppress.h"

namespace osplint {
namespace {

constexpr uint64_t kMaxSize = 0xFFFFFFF0ull;  // check_text's limit
constexpr const char* kTooLarge = "file too large (osplint checks files up to 4 GiB)";
constexpr uint32_t kCheckpointLines = 1024;

// ------------------------------------------------------------------ input

class ByteSource {
public:
    virtual ~ByteSource() = default;
    // Reads up to `len` bytes at `offset`: the count, 0 at the end, -1 on error.
    virtual int64_t read(uint64_t offset, char* buf, size_t len) = 0;
};

class MemorySource final : public ByteSource {
public:
    explicit MemorySource(std::string_view text) : text_(text) {}
    int64_t read(uint64_t offset, char* buf, size_t len) override {
        if (offset >= text_.size()) return 0;
        const size_t n = std::min<uint64_t>(len, text_.size() - offset);
        std::memcpy(buf, text_.data() + offset, n);
        return static_cast<int64_t>(n);
    }

private:
    std::string_view text_;
};

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

// A regular file (or anything pread works on).
class FdSource final : public ByteSource {
public:
    explicit FdSource(int fd) : fd_(fd) {}
    int64_t read(uint64_t offset, char* buf, size_t len) override { return pread_full(fd_, offset, buf, len); }

private:
    int fd_;
};

// A pipe: what is read from it is appended to an unlinked temporary file, from
// which every read is served (so that lines can be read again).
class PipeSource final : public ByteSource {
public:
    explicit PipeSource(int fd) : in_(fd) {
        spool_ = std::tmpfile();
        if (spool_) spool_fd_ = fileno(spool_);
    }
    ~PipeSource() override {
        if (spool_) std::fclose(spool_);
    }
    bool ok() const { return spool_ != nullptr; }
    int64_t read(uint64_t offset, char* buf, size_t len) override {
        while (offset + len > spooled_ && !in_eof_)
            if (!pull()) return -1;
        if (offset >= spooled_) return 0;
        return pread_full(spool_fd_, offset, buf, std::min<uint64_t>(len, spooled_ - offset));
    }

private:
    bool pull() {
        if (chunk_.empty()) chunk_.resize(size_t(1) << 20);
        ssize_t r;
        do {
            r = ::read(in_, chunk_.data(), chunk_.size());
        } while (r < 0 && errno == EINTR);
        if (r < 0) return false;
        if (r == 0) {
            in_eof_ = true;
            return true;
        }
        size_t done = 0;
        while (done < static_cast<size_t>(r)) {
            const ssize_t w = ::pwrite(spool_fd_, chunk_.data() + done, static_cast<size_t>(r) - done,
                                       static_cast<off_t>(spooled_ + done));
            if (w < 0) {
                if (errno == EINTR) continue;
                return false;
            }
            done += static_cast<size_t>(w);
        }
        spooled_ += static_cast<uint64_t>(r);
        return true;
    }

    int in_;
    FILE* spool_ = nullptr;
    int spool_fd_ = -1;
    uint64_t spooled_ = 0;
    bool in_eof_ = false;
    std::vector<char> chunk_;
};

// The first LF or CR in [p, e), or nullptr.
inline const char* find_break(const char* p, const char* e) {
#if defined(__SSE2__)
    const __m128i lf = _mm_set1_epi8('\n');
    const __m128i cr = _mm_set1_epi8('\r');
    for (; e - p >= 16; p += 16) {
        const __m128i v = _mm_loadu_si128(reinterpret_cast<const __m128i*>(p));
        const int hits = _mm_movemask_epi8(_mm_or_si128(_mm_cmpeq_epi8(v, lf), _mm_cmpeq_epi8(v, cr)));
        if (hits) return p + __builtin_ctz(static_cast<unsigned>(hits));
    }
#endif
    for (; p < e; ++p)
        if (*p == '\n' || *p == '\r') return p;
    return nullptr;
}

// Lines of a ByteSource (the lines SourceText makes: terminators LF, CRLF and
// a lone CR). A LineRef stays valid until the next call of next() or seek().
class LineStream {
public:
    LineStream(ByteSource& src, size_t chunk) : src_(&src), chunk_(std::max<size_t>(chunk, 1)) {}

    void seek(uint64_t offset, uint32_t line) {
        line_ = line;
        if (offset >= buf_offset_ && offset <= buf_offset_ + end_) {  // still in the buffer
            pos_ = static_cast<size_t>(offset - buf_offset_);
            return;
        }
        buf_offset_ = offset;
        pos_ = end_ = 0;
        eof_ = false;
    }

    // The next line; false at the end of the input or on a read error.
    bool next(LineRef& out) {
        while (true) {
            const char* p = buf_.data() + pos_;
            const size_t avail = end_ - pos_;
            const char* brk = find_break(p, p + avail);
            const char* lf = brk && *brk == '\n' ? brk : nullptr;
            const char* cr = brk && *brk == '\r' ? brk : nullptr;
            size_t text_len = 0, term_len = 0;
            bool found = false;
            if (cr) {
                text_len = static_cast<size_t>(cr - p);
                if (text_len + 1 < avail) {
                    term_len = p[text_len + 1] == '\n' ? 2 : 1;
                    found = true;
                } else if (eof_) {
                    term_len = 1;
                    found = true;
                }
            } else if (lf) {
                text_len = static_cast<size_t>(lf - p);
                term_len = 1;
                found = true;
            } else if (eof_) {
                if (avail == 0) return false;
                text_len = avail;
                found = true;
            }
            if (found) {
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

    bool error() const { return error_; }
    // Offset (64-bit) of the line next() returned last.
    uint64_t last_start() const { return start64_; }
    // Offset and number of the line next() will return.
    uint64_t next_offset() const { return buf_offset_ + pos_; }
    uint32_t next_line() const { return line_; }

private:
    bool fill() {
        if (pos_ > 0) {
            std::memmove(buf_.data(), buf_.data() + pos_, end_ - pos_);
            end_ -= pos_;
            buf_offset_ += pos_;
            pos_ = 0;
        }
        if (buf_.size() < chunk_) buf_.resize(chunk_);
        if (end_ == buf_.size()) buf_.resize(buf_.size() * 2);  // a line longer than the buffer
        const int64_t r = src_->read(buf_offset_ + end_, buf_.data() + end_, buf_.size() - end_);
        if (r < 0) {
            error_ = true;
            return false;
        }
        if (r == 0) eof_ = true;
        end_ += static_cast<size_t>(r);
        return true;
    }

    ByteSource* src_;
    size_t chunk_;
    std::vector<char> buf_;
    size_t pos_ = 0, end_ = 0;
    uint64_t buf_offset_ = 0;
    uint64_t start64_ = 0;
    bool eof_ = false;
    bool error_ = false;
    uint32_t line_ = 1;
};

// ------------------------------------------------------------- positions

// A run of complete lines held in memory: [base, base + text.size()).
struct Window {
    std::string_view text;
    uint32_t base = 0;
    uint32_t first_line = 1;
    std::vector<uint32_t> starts;  // relative line starts; also text.size() when it ends with a terminator

    void set(std::string_view t, uint32_t b, uint32_t line) {
        text = t;
        base = b;
        first_line = line;
        starts.clear();
        starts.push_back(0);
        for (size_t i = 0; i < t.size(); ++i) {
            const char c = t[i];
            if (c == '\n' || (c == '\r' && !(i + 1 < t.size() && t[i + 1] == '\n')))
                starts.push_back(static_cast<uint32_t>(i + 1));
        }
    }
    void set_line(const LineRef& l) {
        text = std::string_view(l.text.data(), l.text.size() + l.terminator.size());
        base = l.start;
        first_line = l.line;
        starts.resize(l.terminator.empty() ? 1 : 2);
        starts[0] = 0;
        if (!l.terminator.empty()) starts[1] = static_cast<uint32_t>(text.size());
    }
    bool empty() const { return starts.empty(); }
    bool contains(uint32_t offset) const {
        return !empty() && offset >= base && offset - base <= text.size();
    }
    bool has_line(uint32_t line) const {
        return !empty() && line >= first_line && line - first_line < starts.size() &&
               !(line - first_line == starts.size() - 1 && starts.back() == text.size() && starts.size() > 1);
    }
    Position position(uint32_t offset) const {
        const uint32_t rel = offset - base;
        const auto it = std::upper_bound(starts.begin(), starts.end(), rel);
        const size_t k = static_cast<size_t>(it - starts.begin()) - 1;
        Position p;
        p.line = first_line + static_cast<uint32_t>(k);
        p.byte_col = rel - starts[k];
        const ColumnCount c = count_columns(text.substr(starts[k], rel - starts[k]));
        p.cp_col = c.cp;
        p.utf16_col = c.utf16;
        return p;
    }
    // The text of a line held here, without its terminator.
    std::string_view line_text(uint32_t line) const {
        const size_t k = line - first_line;
        const uint32_t b = starts[k];
        uint32_t e = k + 1 < starts.size() ? starts[k + 1] : static_cast<uint32_t>(text.size());
        if (k + 1 < starts.size()) {
            if (e - b >= 2 && text[e - 2] == '\r' && text[e - 1] == '\n') e -= 2;
            else e -= 1;
        }
        return text.substr(b, e - b);
    }
    // Its terminator (empty for an unterminated last line).
    std::string_view line_terminator(uint32_t line) const {
        const size_t k = line - first_line;
        const std::string_view t = line_text(line);
        const uint32_t e = k + 1 < starts.size() ? starts[k + 1] : static_cast<uint32_t>(text.size());
        const size_t end_of_text = static_cast<size_t>(t.data() - text.data()) + t.size();
        return text.substr(end_of_text, e - end_of_text);
    }
    uint32_t line_start(uint32_t line) const { return base + starts[line - first_line]; }
};

// A line read again: its number, start, text and terminator.
struct LineData {
    bool ok = false;  // false: the offset or line is past the end of the input
    uint32_t line = 0;
    uint32_t start = 0;
    std::string text;
    std::string terminator;
};

// Positions anywhere in the input: from the windows in hand, or by reading the
// line again from the nearest checkpoint (one every kCheckpointLines lines).
class Positions {
public:
    Positions(ByteSource& src, std::optional<uint64_t> size) : src_(&src), size_(size) {
        checkpoints_.push_back({0, 1});
    }

    Window current;  // the line of the block being checked
    Window program;  // the lines of a buffered program

    // Every line read, in order (lines read again are ignored).
    void note_line(const LineRef& l) {
        if (l.line <= last_line_) return;
        last_line_ = l.line;
        if (l.line % kCheckpointLines == 0) checkpoints_.push_back({l.start, l.line});
    }

    // SourceText::position.
    Position position(uint32_t offset) {
        if (size_ && offset > *size_) offset = static_cast<uint32_t>(*size_);
        for (const Window* w : {&current, &program})
            if (w->contains(offset)) return w->position(offset);
        const LineData& f = find_offset(offset);
        Position p;
        p.line = f.line;
        if (!f.ok) return p;
        p.byte_col = offset - f.start;
        const std::string_view line = f.text;
        const std::string_view term = f.terminator;
        ColumnCount c = count_columns(line.substr(0, std::min<size_t>(p.byte_col, line.size())));
        if (p.byte_col > line.size()) {
            const ColumnCount t = count_columns(term.substr(0, p.byte_col - line.size()));
            c.cp += t.cp;
            c.utf16 += t.utf16;
        }
        p.cp_col = c.cp;
        p.utf16_col = c.utf16;
        return p;
    }

    // The line `line` (1-based): from a window, or read again.
    LineData line(uint32_t line) {
        for (const Window* w : {&current, &program})
            if (w->has_line(line)) {
                LineData d;
                d.ok = true;
                d.line = line;
                d.start = w->line_start(line);
                d.text.assign(w->line_text(line));
                d.terminator.assign(w->line_terminator(line));
                return d;
            }
        return find_line(line);
    }

    std::string line_text(uint32_t n) {
        for (const Window* w : {&current, &program})
            if (w->has_line(n)) return std::string(w->line_text(n));
        const LineData& d = find_line(n);
        return d.ok ? d.text : std::string();
    }

private:
    struct Checkpoint {
        uint64_t offset;
        uint32_t line;
    };

    // Reads lines from the last checkpoint before the target until `stop`
    // accepts one.
    template <class StartOk, class Stop>
    const LineData& scan(StartOk&& start_ok, Stop&& stop) {
        auto it = std::find_if(checkpoints_.rbegin(), checkpoints_.rend(), start_ok);
        const Checkpoint cp = it == checkpoints_.rend() ? checkpoints_.front() : *it;
        LineStream ls(*src_, size_t(64) << 10);
        ls.seek(cp.offset, cp.line);
        LineRef l;
        cache_ = LineData{};
        uint32_t last = cp.line - 1;
        bool terminated = true;
        while (ls.next(l)) {
            last = l.line;
            terminated = !l.terminator.empty();
            if (stop(l)) {
                cache_.ok = true;
                cache_.line = l.line;
                cache_.start = l.start;
                cache_.text.assign(l.text);
                cache_.terminator.assign(l.terminator);
                return cache_;
            }
        }
        // Past the end: the empty line after a final terminator.
        cache_.line = terminated ? last + 1 : std::max<uint32_t>(last, 1);
        return cache_;
    }

    const LineData& find_offset(uint32_t offset) {
        if (cache_.ok && offset >= cache_.start &&
            (offset - cache_.start < cache_.text.size() + cache_.terminator.size() ||
             (cache_.terminator.empty() && offset - cache_.start == cache_.text.size())))
            return cache_;
        return scan([&](const Checkpoint& c) { return c.offset <= offset; },
                    [&](const LineRef& l) {
                        const uint64_t end = uint64_t(l.start) + l.text.size() + l.terminator.size();
                        return offset < end || (l.terminator.empty() && offset == end);
                    });
    }
    const LineData& find_line(uint32_t n) {
        if (cache_.ok && cache_.line == n) return cache_;
        return scan([&](const Checkpoint& c) { return c.line <= n; }, [&](const LineRef& l) { return l.line == n; });
    }

    ByteSource* src_;
    std::optional<uint64_t> size_;
    std::vector<Checkpoint> checkpoints_;
    uint32_t last_line_ = 0;
    LineData cache_;
};

// ------------------------------------------------------------ the analysis

// Statements that make the control flow more than a straight line.
bool has_flow_statement(const Block& b) {
    for (const auto& st : b.statements)
        switch (st.kind) {
            case StmtKind::Goto:
            case StmtKind::If:
            case StmtKind::While:
            case StmtKind::Do:
            case StmtKind::End: return true;
            default: break;
        }
    return false;
}

// --------------------------------------------------------------- context

class StreamContext final : public RuleContext {
public:
    StreamContext(const std::string& path, const Config& config, const ProgramNames* known, Positions& positions,
                  ByteSource& src, StreamStats& stats)
        : path_(path), config_(config), known_(known), positions_(positions), src_(src), stats_(stats) {}

    const Config& config() const override { return config_; }
    const Catalog& catalog() const override { return config_.catalog; }
    std::string_view path() const override { return path_; }

    // The whole text, read on first use (StreamStats::source_loads): only for
    // a range outside the lines in hand, which no rule asks for today.
    const SourceText& source() const {
        if (!full_) {
            std::string text;
            std::vector<char> buf(size_t(1) << 20);
            for (uint64_t off = 0;;) {
                const int64_t r = src_.read(off, buf.data(), buf.size());
                if (r <= 0) break;
                text.append(buf.data(), static_cast<size_t>(r));
                off += static_cast<uint64_t>(r);
            }
            full_ = std::make_unique<SourceText>(std::move(text));
            ++stats_.source_loads;
        }
        return *full_;
    }

    // The analyzer's RuleContext::resolve without the whole text.
    SourceRange resolve(ByteRange r) const override {
        SourceRange out;
        out.bytes = r;
        out.start = positions_.position(r.begin);
        out.end = positions_.position(r.end);
        return out;
    }

    // The text of a range of the block being checked (or of its line terminator).
    std::string_view text(ByteRange r) const override {
        for (const Window* w : {&positions_.current, &positions_.program}) {
            if (w->contains(r.begin) && w->contains(r.end)) return w->text.substr(r.begin - w->base, r.size());
            // Past the end of the window: past the end of the file too when the
            // window's last line has no terminator.
            if (w->contains(r.begin) && !w->starts.empty() && w->starts.back() != w->text.size())
                return w->text.substr(r.begin - w->base, r.size());
        }
        const std::string& all = source().text();
        return std::string_view(all).substr(std::min<size_t>(r.begin, all.size()), r.size());
    }

    bool has_label(std::string_view name) const override {
        if (labels_) return labels_->count(std::string(name)) > 0;
        // Streaming keeps no sequence names (a post-processor may number every
        // block): a program whose rules ask for one is read again with all its
        // blocks.
        label_miss_ = true;
        return false;
    }

    bool has_program(std::string_view name) const override {
        if (name.empty() ? unnamed_first_program_ : names_.count(name) > 0) return true;
        if (known_ && known_->find(name) != known_->end()) return true;
        if (name.empty() || lookahead_done_ || !lookahead_) return false;
        lookahead_done_ = true;  // the names of the rest of the file, read once
        lookahead_();
        return names_.count(name) > 0;
    }

    std::optional<double> eval(const Block& block, ExprId e, const ModalState& state) const override {
        return evaluate(block, e, state);
    }

    Diagnostic& report(const RuleMeta& rule, ByteRange range, std::string message) override {
        const SourceRange where = resolve(range);
        Diagnostic d = make_diagnostic(rule, config_, std::move(message), where, positions_.line_text(where.start.line));
        d.fingerprint = fingerprint_for(rule.id, where.start.line);
        diagnostics.push_back(std::move(d));
        return diagnostics.back();
    }

    // --- set by the checker

    void begin_program(const std::string& name, const Labels* labels, const std::vector<Block>* blocks) {
        program_ = name;
        labels_ = labels;
        program_blocks_ = blocks;
        label_miss_ = false;
    }
    bool label_missed() const { return label_miss_; }
    void add_program_name(const std::string& name) const { names_.insert(name); }
    void set_unnamed_first_program(bool v) { unnamed_first_program_ = v; }
    void set_lookahead(std::function<void()> f) { lookahead_ = std::move(f); }
    void set_block(const Block* b) { block_ = b; }

    // Undoing what a program reported (when it is read again).
    struct Mark {
        size_t diagnostics = 0;
        size_t occurrences = 0;
    };
    Mark mark() const { return {diagnostics.size(), occurrence_log_.size()}; }
    void rollback(const Mark& m) {
        diagnostics.resize(m.diagnostics);
        while (occurrence_log_.size() > m.occurrences) {
            --occurrences_[occurrence_log_.back()];
            occurrence_log_.pop_back();
        }
    }

    std::vector<Diagnostic> diagnostics;

private:
    // As the analyzer's Context: rule, program, the block's text with blanks
    // folded and comments left out, occurrence.
    std::string fingerprint_for(std::string_view rule, uint32_t line) {
        const LineData ld = positions_.line(line);
        const std::string norm = fingerprint_text(ld.text, ld.start, ld.ok ? comments_of(ld) : nullptr);
        std::string key = fmt::format("{}|{}|{}", rule, program_, norm);
        const int occurrence = ++occurrences_[key];
        occurrence_log_.push_back(std::move(key));
        return make_fingerprint(rule, program_, norm, occurrence);
    }

    // The comments of the block of a line.
    const std::vector<Comment>* comments_of(const LineData& ld) {
        if (block_ && block_->line == ld.line) return &block_->comments;
        if (program_blocks_ && !program_blocks_->empty()) {
            const uint32_t first = program_blocks_->front().line;
            if (ld.line >= first && ld.line - first < program_blocks_->size())
                return &(*program_blocks_)[ld.line - first].comments;
        }
        if (ld.text.empty() && ld.terminator.empty()) return nullptr;  // no block
        const LineRef l{ld.text, ld.terminator, ld.line, ld.start};
        parser_.parse(l, scratch_);
        return &scratch_.comments;
    }

    const std::string& path_;
    const Config& config_;
    const ProgramNames* known_;
    Positions& positions_;
    ByteSource& src_;
    StreamStats& stats_;
    mutable std::unique_ptr<SourceText> full_;

    std::string program_;
    const Labels* labels_ = nullptr;
    const std::vector<Block>* program_blocks_ = nullptr;
    mutable bool label_miss_ = false;
    mutable std::set<std::string, std::less<>> names_;
    bool unnamed_first_program_ = true;  // until the first program shows its name
    mutable bool lookahead_done_ = false;
    std::function<void()> lookahead_;
    const Block* block_ = nullptr;
    std::unordered_map<std::string, int> occurrences_;
    std::vector<std::string> occurrence_log_;
    FastLineParser parser_;
    Block scratch_;
};

// ---------------------------------------------------------- suppressions

// The directives of the file's comments (analyzer/suppress.h), collected block
// by block and applied at the end exactly as apply_suppressions applies them
// to a parsed file.
class Suppressions {
public:
    Suppressions(const Config& config, const AnalysisOptions& options) : config_(config), options_(options) {}

    // Every block, in file order, once (blocks read again are ignored).
    void add_block(const Block& b, uint32_t index, std::string_view line_text) {
        if (index < next_index_) return;
        next_index_ = index + 1;
        // Program boundaries, as split_programs draws them.
        if (!first_seen_) {
            if (b.program_name || (b.kind == LineKind::Block && !b.is_empty())) {
                first_seen_ = true;
                program_names_[0] = b.program_name ? b.program_name->name : std::string();
            }
        } else if (b.program_name) {
            program_names_.push_back(b.program_name->name);
        }
        const bool content = suppression_target(b);
        if (content) {
            for (size_t k : pending_) blocks_[k].target = index;
            pending_.clear();
        }
        bool any = false;
        for (const auto& c : b.comments) {
            const ByteRange rel{c.range.begin - b.line_start, c.range.end - b.line_start};
            if (parse_directive(line_text, rel).is_directive) any = true;
        }
        if (!any) return;
        DirectiveBlock d;
        d.line = b.line;
        d.line_start = b.line_start;
        d.text.assign(line_text);
        d.program = program_names_.size() - 1;
        d.target = content ? static_cast<int64_t>(index) : int64_t{-1};
        for (const auto& c : b.comments) d.comments.push_back(c.range);
        if (!content) pending_.push_back(blocks_.size());
        blocks_.push_back(std::move(d));
    }

    SuppressionResult finish(std::vector<Diagnostic> diagnostics);

private:
    struct DirectiveBlock {
        uint32_t line = 0;
        uint32_t line_start = 0;
        std::string text;  // the whole line
        size_t program = 0;
        int64_t target = -1;  // block index (= line - 1) of the next block with content
        std::vector<ByteRange> comments;
    };
    const Config& config_;
    const AnalysisOptions& options_;
    uint32_t next_index_ = 0;
    bool first_seen_ = false;
    std::vector<std::string> program_names_{std::string()};
    std::vector<DirectiveBlock> blocks_;
    std::vector<size_t> pending_;  // directive blocks waiting for the next block with content
};

SuppressionResult Suppressions::finish(std::vector<Diagnostic> diagnostics) {
    std::vector<DirectiveLine> lines;
    lines.reserve(blocks_.size());
    for (DirectiveBlock& db : blocks_) {
        DirectiveLine l;
        l.line = db.line;
        l.line_start = db.line_start;
        l.text = std::move(db.text);
        l.program = program_names_[db.program];
        l.target_line = db.target >= 0 ? static_cast<uint32_t>(db.target) + 1 : 0;  // blocks are lines
        l.comments = std::move(db.comments);
        lines.push_back(std::move(l));
    }
    blocks_.clear();
    return apply_directive_lines(lines, std::move(diagnostics), config_, options_);
}

// ---------------------------------------------------------------- checker

// Where a program starts: its first line, and its name when it has one.
struct ProgramStart {
    uint64_t offset = 0;
    uint32_t line = 1;
    bool first = true;                   // the file's first program
    std::optional<Label> name;           // the program name of its first block
    bool rts = false;                    // known to hold an RTS (a subprogram)
};

class Checker {
public:
    Checker(const std::string& path, ByteSource& src, std::optional<uint64_t> size, const Config& config,
            const AnalysisOptions& options, const StreamOptions& stream)
        : path_(path), src_(src), size_(size), config_(config),
          stats_(stream.stats ? *stream.stats : own_stats_), main_(src, stream.chunk_size), positions_(src, size),
          ctx_(path_, config, options.known_programs, positions_, src, stats_), suppressions_(config, options) {
        library_ = file_is_subprogram_library(path_);
        for (auto& r : make_rules()) {
            const RuleMeta& m = r->meta();
            if (!options.only_rules.empty()) {
                if (std::find(options.only_rules.begin(), options.only_rules.end(), m.id) == options.only_rules.end())
                    continue;
            } else if (!config.severity_of(m.id, m.severity, m.enabled_by_default)) {
                continue;
            }
            rules_.push_back(std::move(r));
        }
        for (auto& r : rules_)
            if (r->sees_plain_moves(config)) plain_rules_.push_back(r.get());
        plain_ok_ = plain_moves_possible(config.catalog);
        ctx_.set_lookahead([this] { lookahead(); });
        if (size_) stats_.bytes = *size_;
    }

    FileResult run() {
        FileResult r;
        r.path = path_;
        ProgramStart start;
        bool buffered = false;
        while (!failed_) {
            Outcome o = buffered ? run_buffered(start) : run_linear(start);
            if (failed_) break;
            if (o.kind == Outcome::Restart) {
                ++stats_.restarts;
                buffered = o.buffered;
                start = o.start;
                continue;
            }
            if (o.kind == Outcome::End) break;
            start = o.start;
            buffered = false;
        }
        if (failed_) {
            r.io_error = error_;
            return r;
        }
        if (!size_) stats_.bytes = main_.next_offset();
        std::vector<Diagnostic> diagnostics = std::move(ctx_.diagnostics);
        std::stable_sort(diagnostics.begin(), diagnostics.end(), diagnostic_less);
        SuppressionResult s = suppressions_.finish(std::move(diagnostics));
        r.diagnostics = std::move(s.diagnostics);
        r.suppressed = std::move(s.suppressed);
        return r;
    }

private:
    struct Outcome {
        enum Kind { Next, End, Restart } kind = End;
        ProgramStart start;
        bool buffered = false;
    };

    // ---------------------------------------------------------------- input

    // The next block from the main stream into `b` (with its line in `line`).
    bool read_block(Block& b, LineRef& line) {
        if (!main_.next(line)) {
            if (main_.error()) fail("read error");
            return false;
        }
        if (main_.last_start() + line.text.size() + line.terminator.size() > kMaxSize) {
            fail(kTooLarge);
            return false;
        }
        positions_.note_line(line);
        ++stats_.lines_parsed;
        if (parser_.parse(line, b)) ++stats_.fast_lines;
        else ++stats_.fallback_lines;
        const uint32_t index = line.line - 1;
        if (index >= fed_) {
            fed_ = index + 1;
            suppressions_.add_block(b, index, line.text);
            if (b.program_name) ctx_.add_program_name(b.program_name->name);
        }
        return true;
    }

    void fail(std::string message) {
        if (!failed_) error_ = std::move(message);
        failed_ = true;
    }

    // The file's first block with content or a program name decides the first
    // program's name (split_programs); returns whether `b` starts a new program.
    bool starts_program(const Block& b, uint32_t index, uint32_t start_index) {
        if (!first_known_) {
            if (b.program_name || (b.kind == LineKind::Block && !b.is_empty())) {
                first_known_ = true;
                first_index_ = index;
                first_name_ = b.program_name;
                ctx_.set_unnamed_first_program(!b.program_name);
            }
            return false;
        }
        return b.program_name && index > first_index_ && index != start_index;
    }

    // The names of the programs in the rest of the file (has_program asked for
    // one not seen yet): lines whose first token can be a program name.
    void lookahead() {
        LineStream ls(src_, size_t(1) << 20);
        ls.seek(main_.next_offset(), main_.next_line());
        FastLineParser parser;
        Block b;
        LineRef l;
        while (ls.next(l)) {
            size_t i = 0;
            const std::string_view t = l.text;
            while (i < t.size()) {
                const char c = t[i];
                if (c == ' ' || c == '\t' || c == '\f' || c == '\v' || c == '/' || c == '\xEF' || c == '\xBB' ||
                    c == '\xBF') {
                    ++i;
                } else if (c == '(') {
                    while (i < t.size() && t[i] != ')') ++i;
                    if (i < t.size()) ++i;
                } else {
                    break;
                }
            }
            if (i >= t.size() || (t[i] != 'O' && t[i] != 'o')) continue;
            parser.parse(l, b);
            if (b.program_name) ctx_.add_program_name(b.program_name->name);
        }
    }

    bool subprogram_for(const ProgramStart& s) const {
        // Later programs have content (their name); the first program of a main
        // file is the main program unless it holds an RTS.
        return library_ || s.rts || (!s.first && seen_main_);
    }

    void finish_program(bool has_content, bool subprogram) {
        if (has_content && !subprogram) seen_main_ = true;
        ++stats_.programs;
    }

    // -------------------------------------------------- streamed programs

    Outcome run_linear(const ProgramStart& start) {
        main_.seek(start.offset, start.line);
        LineRef line;
        Block& b = block_;
        if (!read_block(b, line)) return {};
        const uint32_t start_index = start.line - 1;
        starts_program(b, start_index, start_index);
        positions_.current.set_line(line);
        ctx_.set_block(&b);

        Program program;
        program.first_block = start_index;
        bool speculative_name = false;
        if (start.first) {
            if (first_known_ && first_name_) {
                program.name = first_name_->name;
                program.name_range = first_name_->range;
            } else {
                speculative_name = !first_known_;  // unnamed until a name shows up
            }
        } else if (start.name) {
            program.name = start.name->name;
            program.name_range = start.name->range;
        }
        const bool subprogram = subprogram_for(start);
        const StreamContext::Mark mark = ctx_.mark();
        ctx_.begin_program(program.name, nullptr, nullptr);
        ProgramView pv{program, nullptr, subprogram, nullptr};
        for (auto& r : rules_) r->begin_program(ctx_, pv);

        auto restart = [&](bool buffered, bool rts) {
            ctx_.rollback(mark);
            ctx_.set_block(nullptr);
            positions_.current = Window{};
            Outcome o;
            o.kind = Outcome::Restart;
            o.start = start;
            o.start.rts = start.rts || rts;
            o.buffered = buffered;
            return o;
        };

        // The state before the block and the state after it; they trade places
        // after each block (the copy reuses the map nodes of the older state).
        ModalState* A = &state_a_;
        ModalState* B = &state_b_;
        *A = initial_state(config_, subprogram);
        const ModalState unknown;
        std::optional<ModalState> final_state;
        bool reachable = true;
        bool near = false;  // A and B differ at most in the fields a plain move sets
        bool last_falls_through = false;  // the last block reachable and falling through
        bool has_content = false;
        uint32_t index = start_index;
        Outcome next;
        next.kind = Outcome::End;
        const Catalog& catalog = config_.catalog;

        while (true) {
            if (index != start_index) {
                if (!read_block(b, line)) {
                    if (failed_) return {};
                    break;
                }
                // The line in hand (the previous one may have moved in the buffer).
                positions_.current.set_line(line);
                ctx_.set_block(&b);
                if (starts_program(b, index, start_index)) {
                    next.kind = Outcome::Next;
                    next.start.offset = line.start;
                    next.start.line = line.line;
                    next.start.first = false;
                    next.start.name = b.program_name;
                    break;
                }
            }
            if (speculative_name && first_known_) {
                speculative_name = false;
                if (first_name_) return restart(false, false);  // the program has a name after all
            }
            // (A plain move from the parser has no statement and is not empty.)
            const bool plain_line = parser_.last_plain();
            if (!plain_line) {
                if (has_flow_statement(b)) return restart(true, false);
                if (!subprogram && b.statement(StmtKind::Rts)) return restart(false, true);
            }
            if (plain_line || (b.kind == LineKind::Block && !b.is_empty())) has_content = true;

            if (reachable && plain_ok_ && (plain_line || is_plain_move_block(b)) && plain_move_state(*A)) {
                // A plain move (analyzer.h). A and B differ at most in what a
                // plain move sets when `near` is true, so those fields make B
                // equal to A again.
                if (near) {
                    B->motion = A->motion;
                    B->feed = A->feed;
                    B->x = A->x;
                    B->y = A->y;
                    B->z = A->z;
                } else {
                    *B = *A;
                }
                apply_plain_move(b, *B);
                const BlockView view{b, *A, *B, nullptr, true};
                for (Rule* r : plain_rules_)
                    if (r->wants_plain_moves() || b.sequence) r->check_block(ctx_, view);
                if (ctx_.label_missed()) return restart(true, false);
                std::swap(A, B);
                near = true;
                last_falls_through = true;
            } else if (reachable) {
                std::optional<MacroCall> call = resolve_call(b, *A, catalog);
                *B = *A;
                apply_block(b, call ? &*call : nullptr, catalog, *B);
                near = false;
                const BlockView view{b, *A, *B, call ? &*call : nullptr, true};
                for (auto& r : rules_) r->check_block(ctx_, view);
                if (ctx_.label_missed()) return restart(true, false);
                if (b.block_delete) B->merge(*A);
                B->clear_one_shots();
                const bool ends = ends_program(b);
                if (ends) {
                    if (!final_state) final_state = *B;
                    else final_state->merge(*B);
                }
                const bool falls = !(ends && !b.block_delete);
                std::swap(A, B);
                reachable = falls;
                last_falls_through = falls && !ends;
            } else {
                std::optional<MacroCall> call = resolve_call(b, unknown, catalog);
                ModalState after = unknown;
                apply_block(b, call ? &*call : nullptr, catalog, after);
                const BlockView view{b, unknown, after, call ? &*call : nullptr, false};
                for (auto& r : rules_) r->check_block(ctx_, view);
                if (ctx_.label_missed()) return restart(true, false);
                last_falls_through = false;
            }
            ++index;
        }
        if (speculative_name && first_known_ && first_name_) return restart(false, false);
        // The last block is an exit when control falls off its end.
        if (last_falls_through) {
            if (!final_state) final_state = *A;
            else final_state->merge(*A);
        }
        program.end_block = index;
        pv.final_state = final_state ? &*final_state : nullptr;
        for (auto& r : rules_) r->end_program(ctx_, pv);
        ctx_.set_block(nullptr);
        positions_.current = Window{};
        finish_program(has_content, subprogram);
        return next;
    }

    // ------------------------------------------------- buffered programs

    // The program's blocks in memory, analysed as analyze() does: control
    // flow, the modal-state fixpoint, then every rule on every block.
    Outcome run_buffered(const ProgramStart& start) {
        ++stats_.buffered_programs;
        main_.seek(start.offset, start.line);
        std::vector<Block> blocks;
        std::string text;
        LineRef line;
        Block b;
        const uint32_t start_index = start.line - 1;
        Outcome next;
        next.kind = Outcome::End;
        for (uint32_t index = start_index;; ++index) {
            if (!read_block(b, line)) {
                if (failed_) return {};
                break;
            }
            if (starts_program(b, index, start_index)) {
                next.kind = Outcome::Next;
                next.start.offset = line.start;
                next.start.line = line.line;
                next.start.first = false;
                next.start.name = b.program_name;
                break;
            }
            text.append(line.text);
            text.append(line.terminator);
            blocks.push_back(b);
        }
        if (blocks.empty()) return next;
        stats_.max_buffered_blocks = std::max<uint64_t>(stats_.max_buffered_blocks, blocks.size());

        Program p;
        p.first_block = start_index;
        p.end_block = start_index + static_cast<uint32_t>(blocks.size());
        if (start.first) {
            if (first_known_ && first_name_) {
                p.name = first_name_->name;
                p.name_range = first_name_->range;
            }
        } else if (start.name) {
            p.name = start.name->name;
            p.name_range = start.name->range;
        }
        const uint32_t n = static_cast<uint32_t>(blocks.size());
        const Labels labels = labels_of(blocks.data(), n);
        bool subprogram = library_;
        bool has_content = false;
        for (const Block& bl : blocks) {
            if (bl.statement(StmtKind::Rts)) subprogram = true;
            if (bl.kind == LineKind::Block && !bl.is_empty()) has_content = true;
        }
        if (has_content && !subprogram && seen_main_) subprogram = true;

        positions_.program.set(text, static_cast<uint32_t>(start.offset), start.line);
        ctx_.begin_program(p.name, &labels, &blocks);
        ProgramInput input;
        input.blocks = blocks.data();
        input.count = n;
        input.program = &p;
        input.subprogram = subprogram;
        input.labels = &labels;
        analyze_program(input, config_, ctx_, rules_, [&](uint32_t i) { ctx_.set_block(&blocks[i]); }, nullptr);
        ctx_.set_block(nullptr);
        ctx_.begin_program(std::string(), nullptr, nullptr);
        positions_.program = Window{};
        finish_program(has_content, subprogram);
        return next;
    }

    const std::string& path_;
    ByteSource& src_;
    std::optional<uint64_t> size_;
    const Config& config_;
    StreamStats own_stats_;
    StreamStats& stats_;
    LineStream main_;
    Positions positions_;
    StreamContext ctx_;
    Suppressions suppressions_;
    FastLineParser parser_;
    std::vector<std::unique_ptr<Rule>> rules_;
    std::vector<Rule*> plain_rules_;  // the rules that look at plain moves
    bool plain_ok_ = true;            // plain_moves_possible with this catalog
    Block block_;
    ModalState state_a_, state_b_;

    bool library_ = false;
    bool seen_main_ = false;
    bool first_known_ = false;
    uint32_t first_index_ = 0;
    std::optional<Label> first_name_;
    uint32_t fed_ = 0;  // blocks handed to the suppressions and the program names
    bool failed_ = false;
    std::string error_;
};

FileResult check_source(const std::string& path, ByteSource& src, std::optional<uint64_t> size,
                        const Config& config, const AnalysisOptions& options, const StreamOptions& stream) {
    if (size && *size > kMaxSize) {
        FileResult r;
        r.path = path;
        r.io_error = kTooLarge;
        return r;
    }
    Checker checker(path, src, size, config, options, stream);
    return checker.run();
}

// collect_program_names over lines read in chunks (the same rule: a line whose
// first character that is not a blank or tab is an O).
bool collect_names(ByteSource& src, ProgramNames& out) {
    LineStream ls(src, size_t(1) << 20);
    LineRef l;
    while (ls.next(l)) {
        const std::string_view line = l.text;
        const size_t k = line.find_first_not_of(" \t");
        if (k == std::string_view::npos || (line[k] != 'O' && line[k] != 'o')) continue;
        std::string name = "O";
        for (size_t j = k + 1; j < line.size() && std::isalnum(static_cast<unsigned char>(line[j])); ++j)
            name += static_cast<char>(std::toupper(static_cast<unsigned char>(line[j])));
        if (name.size() > 1) out.insert(name);
    }
    return !ls.error();
}

}  // namespace

FileResult check_text_fast(const std::string& path, std::string_view text, const Config& config,
                           const AnalysisOptions& options, const StreamOptions& stream) {
    MemorySource src(text);
    return check_source(path, src, text.size(), config, options, stream);
}

FileResult check_fd_fast(int fd, const std::string& path, const Config& config, const AnalysisOptions& options,
                         const StreamOptions& stream) {
    struct stat st;
    if (::fstat(fd, &st) == 0 && S_ISREG(st.st_mode)) {
        FdSource src(fd);
        return check_source(path, src, static_cast<uint64_t>(st.st_size), config, options, stream);
    }
    PipeSource src(fd);
    if (!src.ok()) {
        FileResult r;
        r.path = path;
        r.io_error = std::string("cannot create a temporary file: ") + std::strerror(errno);
        return r;
    }
    return check_source(path, src, std::nullopt, config, options, stream);
}

FileResult check_file_fast(const std::string& path, const Config& config, const AnalysisOptions& options,
                           const StreamOptions& stream) {
    FileResult r;
    r.path = path;
    std::error_code ec;
    auto st = std::filesystem::status(path, ec);
    if (ec || !std::filesystem::exists(st)) {
        r.io_error = std::filesystem::is_symlink(std::filesystem::symlink_status(path, ec)) ? "dangling symbolic link"
                                                                                          : "no such file";
        return r;
    }
    if (std::filesystem::is_directory(st)) {
        r.io_error = "is a directory";
        return r;
    }
    const int fd = ::open(path.c_str(), O_RDONLY | O_CLOEXEC);
    if (fd < 0) {
        r.io_error = std::string("cannot open: ") + std::strerror(errno);
        return r;
    }
    r = check_fd_fast(fd, path, config, options, stream);
    ::close(fd);
    return r;
}

int spool_to_temporary_file(int fd, std::string& error) {
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
    std::vector<char> buf(size_t(1) << 20);
    while (true) {
        const ssize_t r = ::read(fd, buf.data(), buf.size());
        if (r < 0) {
            if (errno == EINTR) continue;
            error = "read error";
            ::close(out);
            return -1;
        }
        if (r == 0) break;
        for (ssize_t done = 0; done < r;) {
            const ssize_t w = ::write(out, buf.data() + done, static_cast<size_t>(r - done));
            if (w < 0) {
                if (errno == EINTR) continue;
                error = std::string("cannot write a temporary file: ") + std::strerror(errno);
                ::close(out);
                return -1;
            }
            done += w;
        }
    }
    ::lseek(out, 0, SEEK_SET);
    return out;
}

namespace {

std::string dump_position(const Position& p) {
    return fmt::format("{}:{}/{}/{}", p.line, p.byte_col, p.cp_col, p.utf16_col);
}
std::string dump_range(const SourceRange& r) {
    return fmt::format("[{},{}) {}-{}", r.bytes.begin, r.bytes.end, dump_position(r.start), dump_position(r.end));
}
void dump_diagnostic(std::string& o, const Diagnostic& d) {
    o += fmt::format("{} {} {} {} '{}'\n", d.rule, d.name, severity_name(d.severity), dump_range(d.range), d.message);
    o += fmt::format("  line '{}' fingerprint {}\n", d.line_text, d.fingerprint);
    for (const auto& n : d.notes)
        o += fmt::format("  note '{}' {}\n", n.message, n.range ? dump_range(*n.range) : std::string("-"));
    for (const auto& f : d.fixes) {
        o += fmt::format("  fix '{}'\n", f.title);
        for (const auto& e : f.edits) o += fmt::format("    edit {} '{}'\n", dump_range(e.range), e.replacement);
    }
}

}  // namespace

std::string dump_result(const FileResult& r) {
    std::string o = "path " + r.path + "\n";
    if (!r.io_error.empty()) o += "io_error " + r.io_error + "\n";
    for (const auto& d : r.diagnostics) dump_diagnostic(o, d);
    for (const auto& s : r.suppressed) {
        o += fmt::format("suppressed kind {} reason '{}' file {} directive {}\n", static_cast<int>(s.kind), s.reason,
                         s.file_scope, s.directive ? dump_range(*s.directive) : std::string("-"));
        dump_diagnostic(o, s.diagnostic);
    }
    return o;
}

bool collect_program_names_fd(int fd, ProgramNames& out) {
    FdSource src(fd);
    return collect_names(src, out);
}

bool collect_program_names_file(const std::string& path, ProgramNames& out) {
    const int fd = ::open(path.c_str(), O_RDONLY | O_CLOEXEC);
    if (fd < 0) return false;
    const bool ok = collect_program_names_fd(fd, out);
    ::close(fd);
    return ok;
}

}  // namespace osplint
