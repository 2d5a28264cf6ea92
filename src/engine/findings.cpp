// The findings of the walk (walk.h): made when a rule reports, checked
// against the file's suppression directives, folded, given fingerprints and
// handed on in position order; and what the rules may ask of the text.
#include <algorithm>
#include <optional>
#include <utility>

#include "engine/walk.h"

namespace osplint {

std::string_view Walk::text(ByteRange r) const {
    for (const Window* w : {&positions_.current(), static_cast<const Window*>(&positions_.held)}) {
        if (w->contains(r.begin) && w->contains(r.end)) return w->text.substr(r.begin - w->base, r.size());
        // Past the end of the window: past the end of the file too when the
        // window's last line has no terminator.
        if (w->contains(r.begin) && !w->starts.empty() && w->starts.back() != w->text.size())
            return w->text.substr(r.begin - w->base, r.size());
    }
    // Elsewhere in the file (no rule asks for that today): read it.
    const uint64_t size = outline_.size;
    const uint64_t begin = std::min<uint64_t>(r.begin, size);
    const uint64_t len = std::min<uint64_t>(r.size(), size - begin);
    scratch_text_.assign(len, '\0');
    const int64_t got = len ? src_.read(begin, scratch_text_.data(), len) : 0;
    scratch_text_.resize(got > 0 ? static_cast<size_t>(got) : 0);
    return scratch_text_;
}

bool Walk::has_label(std::string_view name) const {
    if (auto it = defs_.find(std::string(name)); it != defs_.end() && !it->second.empty()) return true;
    if (flow_.is_referenced(name)) return false;
    // A name the outline did not see referenced: the walk kept none of its
    // definitions. Unknown, so no finding rests on it.
    ++stats_.label_misses;
    return true;
}

bool Walk::has_program(std::string_view name) const {
    if (name.empty()) {
        for (const auto& p : outline_.programs)
            if (p.name.empty()) return true;
        return false;
    }
    if (names_.find(name) != names_.end()) return true;
    return options_.known_programs && options_.known_programs->find(name) != options_.known_programs->end();
}

Diagnostic& Walk::report(const RuleMeta& rule, ByteRange range, std::string message) {
    ++reports_;
    Diagnostic d;
    d.rule = std::string(rule.id);
    d.name = std::string(rule.name);
    d.severity = config_.severity_of(rule.id, rule.severity, rule.enabled_by_default).value_or(rule.severity);
    d.message = std::move(message);
    d.range = positions_.range(range);
    d.line_text = positions_.line_text(d.range.start.line, 1000);
    d.kind = pending_verdict_ ? pending_kind_ : message_kind(rule.id, d.message);
    findings_.push_back(std::move(d));
    verdicts_.push_back(pending_verdict_);
    pending_verdict_.reset();
    return findings_.back();
}

namespace {

// Whether `key` equals the bytes at `other` (a short key: compared here, not
// by a call to memcmp).
bool same_bytes(std::string_view key, const char* other) {
    for (size_t i = 0; i < key.size(); ++i)
        if (key[i] != other[i]) return false;
    return true;
}

}  // namespace

bool Walk::folded(const RuleMeta& rule, std::string_view key, ByteRange range) {
    ++reports_;
    pending_verdict_.reset();
    if (!folder_.enabled()) return false;
    // A finding a directive silences is reported (and then suppressed), never folded.
    if (!filter_->empty()) {
        Diagnostic probe;
        probe.rule = std::string(rule.id);
        probe.range.start = positions_.position(range.begin);
        if (filter_->covers(probe)) return false;
    }
    if (key.size() == last_key_.size && rule.id.data() == last_key_.rule.data() && rule.id.size() == last_key_.rule.size() &&
        same_bytes(key, last_key_.key.data())) {
        pending_kind_ = last_key_.kind;
    } else {
        pending_kind_ = keyed_kind(rule.id, key);
        if (key.size() <= last_key_.key.size()) {
            std::copy(key.begin(), key.end(), last_key_.key.begin());
            last_key_.rule = rule.id;
            last_key_.size = key.size();
            last_key_.kind = pending_kind_;
        }
    }
    const Folder::Verdict v = folder_.next(pending_kind_, range);
    if (v == Folder::Verdict::Count) return true;
    pending_verdict_ = v;
    return false;
}

std::string Walk::fingerprint_for(std::string_view rule, uint32_t line) {
    if (line != fingerprint_line_ || line == 0 || program_.name != fingerprint_program_) {
        const LineData ld = positions_.line(line);
        fingerprint_text_ = fingerprint_text(ld.text, ld.start, ld.ok ? comments_of(ld) : nullptr);
        fingerprint_line_ = line;
        fingerprint_program_ = program_.name;
        fingerprint_keys_.clear();
    }
    auto it = fingerprint_keys_.find(rule);
    if (it == fingerprint_keys_.end())
        it = fingerprint_keys_.emplace(std::string(rule), fingerprint_key(rule, program_.name, fingerprint_text_)).first;
    return make_fingerprint(it->second, occurrences_.next(it->second));
}

// The comments of the block of a line.
const std::vector<Comment>* Walk::comments_of(const LineData& ld) {
    if (block_ && block_->line == ld.line) return &block_->comments;
    if (held_)
        for (const HeldLine& h : *held_)
            if (h.line == ld.line) return &h.block.comments;
    if (ld.text.empty() && ld.terminator.empty()) return nullptr;  // no block
    comment_parser_.parse(LineRef{ld.text, ld.terminator, ld.line, ld.start}, comment_block_);
    return &comment_block_.comments;
}

void Walk::flush() {
    // Decide in position order (the order the findings are handed on), and
    // give fingerprints in the order the rules reported (the occurrence count
    // of a fingerprint follows it): only to the findings that are shown.
    const size_t n = findings_.size();
    std::vector<size_t> order(n);
    for (size_t i = 0; i < n; ++i) order[i] = i;
    std::stable_sort(order.begin(), order.end(),
                     [&](size_t a, size_t b) { return diagnostic_less(findings_[a], findings_[b]); });
    std::vector<std::optional<SuppressedDiagnostic>> silenced(n);
    std::vector<Folder::Verdict> verdict(n, Folder::Verdict::Show);
    for (size_t i : order) {
        SuppressedDiagnostic s;
        if (filter_->silence(findings_[i], s)) silenced[i] = std::move(s);
        else verdict[i] = verdicts_[i] ? *verdicts_[i] : folder_.next(findings_[i].kind, findings_[i].range.bytes);
    }
    if (fingerprints_)
        for (size_t i = 0; i < n; ++i) {
            Diagnostic& d = silenced[i] ? silenced[i]->diagnostic : findings_[i];
            if (silenced[i] || verdict[i] != Folder::Verdict::Count)
                d.fingerprint = fingerprint_for(d.rule, d.range.start.line);
        }
    for (size_t i : order) {
        if (silenced[i]) deliver(std::move(*silenced[i]));
        else if (verdict[i] == Folder::Verdict::Show) deliver(std::move(findings_[i]));
        else if (verdict[i] == Folder::Verdict::Hold) folder_.hold(findings_[i].kind, std::move(findings_[i]));
    }
    findings_.clear();
    verdicts_.clear();
}

void Walk::extend_reach(const Diagnostic& d) { delivered_reach_ = std::max(delivered_reach_, reach_of(d)); }

void Walk::deliver(Diagnostic&& d) {
    if (!speculating_) {
        ++delivered_diagnostics_;
        extend_reach(d);
        sink_.diagnostic(std::move(d));
    } else if (speculative_.size() < kMaxSpeculativeFindings) {
        speculative_.emplace_back(std::move(d), std::nullopt);
    } else {
        speculation_overflow_ = true;
    }
}

void Walk::deliver(SuppressedDiagnostic&& s) {
    if (!speculating_) {
        ++delivered_suppressed_;
        extend_reach(s.diagnostic);
        if (s.directive) delivered_reach_ = std::max(delivered_reach_, s.directive->bytes.end);
        sink_.suppressed(std::move(s));
    } else if (speculative_.size() < kMaxSpeculativeFindings) {
        speculative_.emplace_back(std::nullopt, std::move(s));
    } else {
        speculation_overflow_ = true;
    }
}

}  // namespace osplint
