// Positions anywhere in an input the engine reads as a stream.
//
// A rule reports a byte range; a finding needs its line and columns (bytes,
// code points, UTF-16 units) and the text of its line. The engine holds only
// the lines in hand: the current line, and the lines of a loop it keeps in
// memory. Anything older is found again from a checkpoint (a line number and
// its offset, one every 1024 lines) by reading forward from it.
#pragma once

#include <cstdint>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "osplint/diagnostic.h"
#include "support/io.h"

namespace osplint {

// A run of complete lines held in memory: [base, base + text.size()).
struct Window {
    std::string_view text;
    uint32_t base = 0;
    uint32_t first_line = 1;
    std::vector<uint32_t> starts;  // relative line starts; also text.size() when it ends with a terminator

    void set(std::string_view t, uint32_t b, uint32_t line);
    void set_line(const LineRef& l);
    void clear() { *this = Window{}; }
    bool empty() const { return starts.empty(); }
    bool contains(uint32_t offset) const { return !empty() && offset >= base && offset - base <= text.size(); }
    bool has_line(uint32_t line) const;
    Position position(uint32_t offset) const;
    std::string_view line_text(uint32_t line) const;        // without its terminator
    std::string_view line_terminator(uint32_t line) const;  // empty for an unterminated last line
    uint32_t line_start(uint32_t line) const { return base + starts[line - first_line]; }

private:
    mutable int ascii_ = -1;             // whether text is all ASCII; -1: not looked at yet
    mutable Position memo_{0, 0, 0, 0};  // the last position counted (line 0: none)
};

// A line read again: its number, start, text and terminator.
struct LineData {
    bool ok = false;  // false: the offset or line is past the end of the input
    uint32_t line = 0;
    uint32_t start = 0;
    std::string text;
    std::string terminator;
};

class Positions {
public:
    explicit Positions(ByteSource& src) : src_(&src) { checkpoints_.push_back({0, 1}); }

    // The line of the block being checked (its window is made when asked for).
    void set_current(const LineRef& l) {
        line_in_hand_ = l;
        has_line_in_hand_ = true;
    }
    void clear_current() {
        has_line_in_hand_ = false;
        current_.clear();
    }
    const Window& current() {
        if (has_line_in_hand_) {
            current_.set_line(line_in_hand_);
            has_line_in_hand_ = false;
        }
        return current_;
    }
    Window held;  // the lines of a loop held in memory

    // The size of the input, once known (offsets past it are clamped).
    void set_size(uint64_t size) { size_ = size; }
    // Every line read, in order (lines read again are ignored).
    void note_line(const LineRef& l) {
        if (l.line <= last_line_) return;
        last_line_ = l.line;
        if (l.line % kCheckpointLines == 0) checkpoints_.push_back({l.start, l.line});
    }
    // The position of an offset (SourceText::position).
    Position position(uint32_t offset);
    SourceRange range(ByteRange r) { return SourceRange{r, position(r.begin), position(r.end)}; }
    // The line `line` (1-based): from a window, or read again.
    LineData line(uint32_t line);
    // Its text, abbreviated to `max` bytes (support/text.h: abbreviate).
    std::string line_text(uint32_t line, size_t max);

    static constexpr uint32_t kCheckpointLines = 1024;

    // The line checkpoints up to a line, to start a later walk there.
    struct Marks {
        std::vector<std::pair<uint64_t, uint32_t>> offsets_and_lines;
        uint32_t last_line = 0;
    };
    Marks marks_before(uint32_t line) const {
        Marks m;
        for (const auto& c : checkpoints_)
            if (c.line < line) m.offsets_and_lines.emplace_back(c.offset, c.line);
        m.last_line = line - 1;
        return m;
    }
    void restore(const Marks& m) {
        checkpoints_.clear();
        for (const auto& [o, l] : m.offsets_and_lines) checkpoints_.push_back({o, l});
        if (checkpoints_.empty()) checkpoints_.push_back({0, 1});
        last_line_ = m.last_line;
    }

private:
    struct Checkpoint {
        uint64_t offset;
        uint32_t line;
    };
    template <class StartOk, class Stop>
    const LineData& scan(StartOk&& start_ok, Stop&& stop);
    bool read_line_at(uint64_t start, uint32_t line);
    const LineData& find_offset(uint32_t offset);
    const LineData& find_line(uint32_t n);

    ByteSource* src_;
    Window current_;
    LineRef line_in_hand_;
    bool has_line_in_hand_ = false;
    std::optional<uint64_t> size_;
    std::vector<Checkpoint> checkpoints_;
    uint32_t last_line_ = 0;
    LineData cache_;
    std::string count_buf_;  // find_offset's block of bytes (read_line_at's too)
};

}  // namespace osplint
