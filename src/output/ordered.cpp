#include "output/ordered.h"

#include <cstring>

namespace osplint {
namespace {

enum class Event : char { Begin = 'B', Diagnostic = 'D', Suppressed = 'S', End = 'E' };

void put_u64(std::string& out, uint64_t v) { out.append(reinterpret_cast<const char*>(&v), sizeof v); }
void put_u32(std::string& out, uint32_t v) { out.append(reinterpret_cast<const char*>(&v), sizeof v); }
void put_str(std::string& out, std::string_view s) {
    put_u64(out, s.size());
    out.append(s);
}
void put_range(std::string& out, const SourceRange& r) {
    for (uint32_t v : {r.bytes.begin, r.bytes.end, r.start.line, r.start.byte_col, r.start.cp_col, r.start.utf16_col,
                       r.end.line, r.end.byte_col, r.end.cp_col, r.end.utf16_col})
        put_u32(out, v);
}
void put_opt_range(std::string& out, const std::optional<SourceRange>& r) {
    out += r ? '1' : '0';
    if (r) put_range(out, *r);
}

bool get_u64(std::string_view& in, uint64_t& v) {
    if (in.size() < sizeof v) return false;
    std::memcpy(&v, in.data(), sizeof v);
    in.remove_prefix(sizeof v);
    return true;
}
bool get_u32(std::string_view& in, uint32_t& v) {
    if (in.size() < sizeof v) return false;
    std::memcpy(&v, in.data(), sizeof v);
    in.remove_prefix(sizeof v);
    return true;
}
bool get_str(std::string_view& in, std::string& s) {
    uint64_t n;
    if (!get_u64(in, n) || in.size() < n) return false;
    s.assign(in.substr(0, n));
    in.remove_prefix(n);
    return true;
}
bool get_range(std::string_view& in, SourceRange& r) {
    uint32_t* fields[] = {&r.bytes.begin, &r.bytes.end, &r.start.line, &r.start.byte_col, &r.start.cp_col,
                          &r.start.utf16_col, &r.end.line, &r.end.byte_col, &r.end.cp_col, &r.end.utf16_col};
    for (uint32_t* f : fields)
        if (!get_u32(in, *f)) return false;
    return true;
}
bool get_opt_range(std::string_view& in, std::optional<SourceRange>& r) {
    if (in.empty()) return false;
    const char flag = in.front();
    in.remove_prefix(1);
    if (flag == '0') {
        r.reset();
        return true;
    }
    r.emplace();
    return get_range(in, *r);
}

}  // namespace

void encode_diagnostic(std::string& out, const Diagnostic& d) {
    put_str(out, d.rule);
    put_str(out, d.name);
    put_u32(out, static_cast<uint32_t>(d.severity));
    put_str(out, d.message);
    put_range(out, d.range);
    put_u64(out, d.notes.size());
    for (const auto& n : d.notes) {
        put_str(out, n.message);
        put_opt_range(out, n.range);
    }
    put_u64(out, d.fixes.size());
    for (const auto& f : d.fixes) {
        put_str(out, f.title);
        put_u64(out, f.safe ? 1 : 0);
        put_u64(out, f.edits.size());
        for (const auto& e : f.edits) {
            put_range(out, e.range);
            put_str(out, e.replacement);
        }
    }
    put_str(out, d.line_text);
    put_str(out, d.fingerprint);
    put_u64(out, d.folded);
    put_opt_range(out, d.folded_last);
}

bool decode_diagnostic(std::string_view& in, Diagnostic& d) {
    uint32_t severity = 0;
    uint64_t n = 0;
    if (!get_str(in, d.rule) || !get_str(in, d.name) || !get_u32(in, severity) || !get_str(in, d.message) ||
        !get_range(in, d.range) || !get_u64(in, n))
        return false;
    d.severity = static_cast<Severity>(severity);
    d.notes.resize(n);
    for (auto& note : d.notes)
        if (!get_str(in, note.message) || !get_opt_range(in, note.range)) return false;
    if (!get_u64(in, n)) return false;
    d.fixes.resize(n);
    for (auto& f : d.fixes) {
        uint64_t safe = 0;
        if (!get_str(in, f.title) || !get_u64(in, safe) || !get_u64(in, n)) return false;
        f.safe = safe != 0;
        f.edits.resize(n);
        for (auto& e : f.edits)
            if (!get_range(in, e.range) || !get_str(in, e.replacement)) return false;
    }
    return get_str(in, d.line_text) && get_str(in, d.fingerprint) && get_u64(in, d.folded) &&
           get_opt_range(in, d.folded_last);
}

class OrderedOutput::Channel final : public DiagnosticSink {
public:
    Channel(OrderedOutput& owner, size_t index) : owner_(owner), index_(index) {}

    bool wants_fingerprints() const override { return owner_.sink_.wants_fingerprints(); }
    void begin_file(const std::string& path) override {
        forward([&](DiagnosticSink& sink) { sink.begin_file(path); },
                [&](std::string& e) {
                    e += static_cast<char>(Event::Begin);
                    put_str(e, path);
                });
    }
    void diagnostic(Diagnostic&& d) override {
        forward([&](DiagnosticSink& sink) { sink.diagnostic(std::move(d)); },
                [&](std::string& e) {
                    e += static_cast<char>(Event::Diagnostic);
                    encode_diagnostic(e, d);
                });
    }
    void suppressed(SuppressedDiagnostic&& s) override {
        forward([&](DiagnosticSink& sink) { sink.suppressed(std::move(s)); },
                [&](std::string& e) {
                    e += static_cast<char>(Event::Suppressed);
                    encode_diagnostic(e, s.diagnostic);
                    put_u32(e, static_cast<uint32_t>(s.kind));
                    put_str(e, s.reason);
                    e += s.file_scope ? '1' : '0';
                    put_opt_range(e, s.directive);
                });
    }
    void end_file(const std::string& path, const std::string& io_error) override {
        std::unique_lock lock(m_);
        const bool direct = direct_;
        if (!direct) {
            std::string e(1, static_cast<char>(Event::End));
            put_str(e, path);
            put_str(e, io_error);
            spool(e);
        }
        ended_ = true;
        lock.unlock();
        std::lock_guard out(owner_.m_);
        if (direct) owner_.sink_.end_file(path, io_error);
        if (owner_.current_ == index_) owner_.advance_locked();
    }

    // With the owner's lock held: hands what waited to the sink. Returns
    // whether the file has ended; if not, its next calls go straight through.
    bool flush_locked() {
        std::lock_guard lock(m_);
        spool_.drain([&](std::string_view piece) {
            pending_.append(piece);
            replay(owner_.sink_);
        });
        if (!spool_.error().empty()) owner_.errors_.push_back(spool_.error());
        if (!ended_) direct_ = true;
        return ended_;
    }
    void make_direct() { direct_ = true; }

private:
    // Straight to the sink when it is this file's turn, else into the spool.
    template <class Direct, class Encode>
    void forward(Direct&& direct, Encode&& encode) {
        std::unique_lock lock(m_);
        if (direct_) {
            lock.unlock();
            std::lock_guard out(owner_.m_);
            direct(owner_.sink_);
            return;
        }
        std::string e;
        encode(e);
        spool(e);
    }
    void spool(const std::string& event) {
        std::string framed;
        put_u64(framed, event.size());
        framed += event;
        spool_.append(framed);
    }
    // Replays the whole events in `pending_`.
    void replay(DiagnosticSink& sink) {
        std::string_view in(pending_);
        while (true) {
            uint64_t size = 0;
            std::string_view probe = in;
            if (!get_u64(probe, size) || probe.size() < size) break;
            std::string_view e = probe.substr(0, size);
            in = probe.substr(size);
            const Event kind = static_cast<Event>(e.front());
            e.remove_prefix(1);
            std::string a, b;
            switch (kind) {
                case Event::Begin:
                    get_str(e, a);
                    sink.begin_file(a);
                    break;
                case Event::Diagnostic: {
                    Diagnostic d;
                    if (decode_diagnostic(e, d)) sink.diagnostic(std::move(d));
                    break;
                }
                case Event::Suppressed: {
                    SuppressedDiagnostic s;
                    uint32_t k = 0;
                    if (decode_diagnostic(e, s.diagnostic) && get_u32(e, k) && get_str(e, s.reason) && !e.empty()) {
                        s.kind = static_cast<SuppressedDiagnostic::Kind>(k);
                        s.file_scope = e.front() == '1';
                        e.remove_prefix(1);
                        get_opt_range(e, s.directive);
                        sink.suppressed(std::move(s));
                    }
                    break;
                }
                case Event::End:
                    get_str(e, a);
                    get_str(e, b);
                    sink.end_file(a, b);
                    break;
            }
        }
        pending_.erase(0, pending_.size() - in.size());
    }

    OrderedOutput& owner_;
    size_t index_;
    std::mutex m_;
    bool direct_ = false;
    bool ended_ = false;
    Spool spool_;
    std::string pending_;  // drained bytes not yet replayed (an event cut between pieces)
};

OrderedOutput::OrderedOutput(DiagnosticSink& sink, size_t files) : sink_(sink) {
    for (size_t i = 0; i < files; ++i) channels_.push_back(std::make_unique<Channel>(*this, i));
    if (!channels_.empty()) channels_.front()->make_direct();
}

OrderedOutput::~OrderedOutput() = default;

DiagnosticSink& OrderedOutput::channel(size_t i) { return *channels_.at(i); }

std::vector<std::string> OrderedOutput::errors() const {
    std::lock_guard lock(m_);
    return errors_;
}

void OrderedOutput::advance_locked() {
    ++current_;
    while (current_ < channels_.size() && channels_[current_]->flush_locked()) ++current_;
}

}  // namespace osplint
