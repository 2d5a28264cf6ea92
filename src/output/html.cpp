#include "output/html.h"

#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>

#include <algorithm>
#include <map>
#include <tuple>
#include <ostream>
#include <vector>

#include <fmt/format.h>

#include "osplint/osplint.h"
#include "output/sideview.h"
#include "rules/registry.h"
#include "support/io.h"

namespace osplint {

namespace {

// The length of the UTF-8 sequence at `s[i]`, or 0 when it is not a valid one.
size_t utf8_length(std::string_view s, size_t i) {
    const auto c = static_cast<unsigned char>(s[i]);
    size_t n = c < 0x80 ? 1 : (c >> 5) == 6 ? 2 : (c >> 4) == 14 ? 3 : (c >> 3) == 30 ? 4 : 0;
    if (n == 0 || (n == 2 && c < 0xC2) || i + n > s.size()) return 0;
    for (size_t k = 1; k < n; ++k)
        if ((static_cast<unsigned char>(s[i + k]) & 0xC0) != 0x80) return 0;
    const auto c1 = static_cast<unsigned char>(s[i + 1 < s.size() ? i + 1 : i]);
    if (n == 3 && ((c == 0xE0 && c1 < 0xA0) || (c == 0xED && c1 >= 0xA0))) return 0;  // overlong, surrogates
    if (n == 4 && ((c == 0xF0 && c1 < 0x90) || (c == 0xF4 && c1 >= 0x90) || c > 0xF4)) return 0;
    return n;
}

// At most `max` bytes of `s`, not cutting a UTF-8 sequence.
size_t cut_at(std::string_view s, size_t max) {
    if (s.size() <= max) return s.size();
    size_t i = max;
    while (i > 0 && (static_cast<unsigned char>(s[i]) & 0xC0) == 0x80) --i;
    return i;
}

const char* kSeverityClass[] = {"info", "warning", "error"};
const char* severity_class(Severity s) { return kSeverityClass[static_cast<int>(s)]; }

std::string plural(uint64_t n, std::string_view word) {
    return fmt::format("{} {}{}", n, word, n == 1 ? "" : "s");
}

std::string rule_url(std::string_view id) {
    return std::string(kProjectUri) + "/blob/main/docs/rules/" + std::string(id) + ".md";
}

constexpr size_t kMaxLineShown = 400;  // bytes of a source line shown

// The page's styles: the report is read offline, from a file attached to a
// posted program, so everything it needs is here.
constexpr std::string_view kStyle = R"css(
:root { --error:#c62828; --error-bg:#fdecea; --warning:#a15c00; --warning-bg:#fff4e0; --info:#1565c0;
  --info-bg:#e8f1fc; --ink:#1d232b; --muted:#5c6670; --line:#d9dee4; --panel:#f6f8fa; --mark:#ffe08a; }
* { box-sizing: border-box; }
body { margin: 0; font: 14px/1.5 "DejaVu Sans", "Segoe UI", Arial, Helvetica, sans-serif; color: var(--ink);
  background: #eef1f4; }
main { max-width: 1240px; margin: 0 auto; padding: 20px 24px 40px; }
a { color: #0b5cad; text-decoration: none; } a:hover { text-decoration: underline; }
code, pre, .code, .path { font-family: "DejaVu Sans Mono", Consolas, Menlo, monospace; }
h1 { font-size: 24px; margin: 0; } h2 { font-size: 18px; margin: 0 0 10px; } h3 { font-size: 15px; margin: 18px 0 8px; }
.top { background: #1f2a36; color: #fff; padding: 18px 24px; }
.top .inner { max-width: 1240px; margin: 0 auto; display: flex; align-items: baseline; gap: 18px; flex-wrap: wrap; }
.top .meta { color: #c5d0db; }
.box { background: #fff; border: 1px solid var(--line); border-radius: 8px; padding: 18px 20px; margin: 18px 0; }
.cards { display: flex; gap: 12px; flex-wrap: wrap; margin-bottom: 16px; }
.card { flex: 1 1 140px; border-radius: 8px; padding: 10px 14px; border: 1px solid var(--line); background: var(--panel); }
.card .n { display: block; font-size: 28px; font-weight: bold; line-height: 1.2; }
.card.error { background: var(--error-bg); border-color: #f3b8b2; color: var(--error); }
.card.warning { background: var(--warning-bg); border-color: #f2cf94; color: var(--warning); }
.card.info { background: var(--info-bg); border-color: #b5cff0; color: var(--info); }
.card.zero { background: var(--panel); border-color: var(--line); color: var(--muted); }
.tables { display: grid; grid-template-columns: 1fr 1fr; gap: 20px; }
@media (max-width: 900px) { .tables { grid-template-columns: 1fr; } }
table { border-collapse: collapse; width: 100%; }
th, td { text-align: left; padding: 5px 8px; border-bottom: 1px solid var(--line); vertical-align: top; }
th { background: var(--panel); font-weight: 600; color: var(--muted); font-size: 12px; text-transform: uppercase;
  letter-spacing: .03em; }
td.num, th.num { text-align: right; font-variant-numeric: tabular-nums; }
.sev { display: inline-block; min-width: 64px; text-align: center; border-radius: 10px; padding: 0 8px; font-size: 12px;
  font-weight: bold; color: #fff; }
.sev.error { background: var(--error); } .sev.warning { background: #c77700; } .sev.info { background: var(--info); }
.counts span { margin-right: 10px; font-weight: 600; }
.counts .error { color: var(--error); } .counts .warning { color: var(--warning); } .counts .info { color: var(--info); }
.counts .zero { color: var(--muted); font-weight: normal; }
.file > h2 { word-break: break-all; }
.note, .muted { color: var(--muted); }
.io-error { background: var(--error-bg); color: var(--error); border-radius: 6px; padding: 8px 12px; }
.clean { color: #2e7d32; font-weight: 600; }
.finding { border: 1px solid var(--line); border-left: 5px solid var(--muted); border-radius: 6px; margin: 12px 0;
  background: #fff; overflow: hidden; }
.finding.error { border-left-color: var(--error); } .finding.warning { border-left-color: #c77700; }
.finding.info { border-left-color: var(--info); }
.finding > header { display: flex; gap: 10px; align-items: center; flex-wrap: wrap; padding: 8px 12px;
  background: var(--panel); border-bottom: 1px solid var(--line); }
.finding .rule { font-weight: bold; } .finding .loc { margin-left: auto; color: var(--muted); }
.finding .msg { margin: 8px 12px; font-weight: 600; }
table.src { width: auto; min-width: 60%; margin: 4px 12px 8px; border: 1px solid var(--line); }
table.src td { border: 0; padding: 0 10px; font-size: 13px; white-space: pre; }
table.src td.ln { text-align: right; color: var(--muted); background: var(--panel); border-right: 1px solid var(--line);
  user-select: none; }
table.src tr.hit td.code { background: #fffbea; } table.src tr.hit td.ln { color: var(--ink); font-weight: bold; }
mark { background: var(--mark); color: inherit; border-bottom: 2px solid #d18b00; padding: 0 1px; }
.finding.error mark { background: #ffd3cf; border-bottom-color: var(--error); }
.finding ul { margin: 4px 12px 10px; padding-left: 20px; }
.finding li.fix code { background: #e9f5ea; border: 1px solid #b8dcbb; border-radius: 4px; padding: 0 4px; }
.more { background: var(--panel); border: 1px dashed var(--line); border-radius: 6px; padding: 8px 12px; }
.sideview { display: grid; grid-template-columns: minmax(260px, 1fr) 2fr; gap: 16px; align-items: start; }
@media (max-width: 900px) { .sideview { grid-template-columns: 1fr; } }
.sideview .calls { max-height: 900px; overflow: auto; border: 1px solid var(--line); border-radius: 6px; }
.sideview .calls td { font-size: 12px; padding: 3px 8px; }
.sideview .calls td.code, .sideview .calls td:nth-child(2) { white-space: nowrap; }
.sideview .calls .why { white-space: normal; font-family: "DejaVu Sans", Arial, sans-serif; margin-top: 2px; }
.sideview .calls tr.travel td { background: var(--error-bg); color: var(--error); }
.sideview .figure { border: 1px solid var(--line); border-radius: 6px; padding: 6px; background: #fff; overflow: auto; }
.sideview svg { display: block; max-width: 100%; height: auto; }
footer { color: var(--muted); font-size: 12px; text-align: center; margin-top: 24px; }
@media print { body { background: #fff; } .box { border: 0; } .sideview .calls { max-height: none; } }
)css";

// One finding kept for the page, with its place in the arrival order (its anchor).
struct Kept {
    Diagnostic d;
    size_t index = 0;
};

struct RuleRow {
    std::string name;
    Severity severity = Severity::Error;
    uint64_t count = 0;
    std::string first;  // anchor of its first finding shown
};

struct FileRow {
    std::string path;
    std::string anchor;
    uint64_t error = 0, warning = 0, info = 0, suppressed = 0, calls = 0;
    bool unreadable = false;
};

// Lines [first, last] of the report's files, read again after their walk.
struct Excerpt {
    uint32_t first = 0, last = 0;
};

class HtmlWriter final : public ReportWriter {
public:
    HtmlWriter(std::ostream& out, const WriterOptions& o) : out_(out), views_(o.side_views), stdin_path_(o.stdin_path) {}

    void begin_file(const std::string& path) override {
        file_ = FileRow{path, fmt::format("file-{}", files_.size() + 1)};
        kept_.clear();
        arrived_ = 0;
        omitted_ = 0;
    }
    void diagnostic(Diagnostic&& d) override {
        const uint64_t n = 1 + d.folded;
        (d.severity == Severity::Error ? file_.error : d.severity == Severity::Warning ? file_.warning : file_.info) += n;
        RuleRow& r = rules_[d.rule];
        if (r.count == 0) {
            r.name = d.name;
            r.severity = d.severity;
        }
        r.count += n;
        const size_t index = ++arrived_;
        if (kept_.size() >= kHtmlMaxFindings) {
            omitted_ += n;
            return;
        }
        if (r.first.empty()) r.first = anchor(index);
        kept_.push_back({std::move(d), index});
    }
    void suppressed(SuppressedDiagnostic&&) override { ++file_.suppressed; }
    void end_file(const std::string& path, const std::string& io_error) override {
        file_.path = path;
        if (file_.anchor.empty()) file_.anchor = fmt::format("file-{}", files_.size() + 1);
        file_.unreadable = !io_error.empty();
        std::vector<SideView> views = views_ ? views_->take(path) : std::vector<SideView>();
        for (const auto& v : views) file_.calls += v.calls.size() + v.omitted;
        write_file(io_error, views);
        files_.push_back(std::move(file_));
        file_ = {};
        kept_.clear();
    }
    void finish(const Counts& counts) override {
        out_ << "<!DOCTYPE html>\n<html lang=\"en\">\n<head>\n<meta charset=\"utf-8\">\n"
                "<meta name=\"viewport\" content=\"width=device-width, initial-scale=1\">\n"
                "<meta name=\"generator\" content=\"osplint "
             << html_escape(version()) << "\">\n<title>" << html_escape(title()) << "</title>\n<style>" << kStyle
             << "</style>\n</head>\n<body>\n";
        out_ << "<header class=\"top\"><div class=\"inner\"><h1>osplint report</h1><span class=\"meta\">"
             << html_escape(title_detail(counts)) << "</span></div></header>\n<main>\n";
        write_summary(counts);
        body_.drain([&](std::string_view piece) { out_ << piece; });
        if (!body_.error().empty())
            out_ << "<p class=\"io-error\">Part of the report was lost: " << html_escape(body_.error()) << "</p>\n";
        out_ << "<footer>Made by osplint " << html_escape(version())
             << ", a static analyzer for Okuma OSP part programs. Run <code>osplint explain ID</code> for the "
                "page of a rule.</footer>\n</main>\n</body>\n</html>\n";
    }

private:
    std::string anchor(size_t index) const { return fmt::format("{}-{}", file_.anchor, index); }

    std::string title() const {
        if (files_.size() == 1) return "osplint report: " + files_.front().path;
        return "osplint report";
    }
    std::string title_detail(const Counts& c) const {
        return fmt::format("osplint {} · {} checked · {}, {}, {}", version(), plural(c.files, "file"),
                           plural(c.error, "error"), plural(c.warning, "warning"), plural(c.info, "info"));
    }

    // ------------------------------------------------------------- summary

    void write_summary(const Counts& c) {
        std::string s = "<section class=\"box summary\" id=\"summary\">\n<h2>Summary</h2>\n<div class=\"cards\">\n";
        auto card = [&](const char* cls, uint64_t n, std::string_view one, std::string_view many) {
            s += fmt::format("<div class=\"card {}{}\"><span class=\"n\">{}</span>{}</div>\n", cls,
                             n == 0 && std::string_view(cls) != "files" ? " zero" : "", n, n == 1 ? one : many);
        };
        card("error", c.error, "error", "errors");
        card("warning", c.warning, "warning", "warnings");
        card("info", c.info, "info", "infos");
        card("files", c.files, "file checked", "files checked");
        if (c.suppressed) card("files", c.suppressed, "suppressed finding", "suppressed findings");
        if (c.unreadable) card("error", c.unreadable, "unreadable file", "unreadable files");
        s += "</div>\n";
        if (c.folded)
            s += fmt::format("<p class=\"note\">{} of these findings are shown folded into others of their kind "
                             "(the count is given with each).</p>\n",
                             c.folded);
        s += "<div class=\"tables\">\n<div>\n<h3>Findings by rule</h3>\n";
        if (rules_.empty()) {
            s += "<p class=\"clean\">No findings.</p>\n";
        } else {
            std::vector<std::pair<std::string, const RuleRow*>> rows;
            for (const auto& [id, r] : rules_) rows.emplace_back(id, &r);
            std::stable_sort(rows.begin(), rows.end(), [](const auto& a, const auto& b) {
                if (a.second->severity != b.second->severity) return a.second->severity > b.second->severity;
                return a.second->count > b.second->count;
            });
            s += "<table class=\"rules\">\n<thead><tr><th>Rule</th><th>Name</th><th>Severity</th>"
                 "<th class=\"num\">Findings</th></tr></thead>\n<tbody>\n";
            for (const auto& [id, r] : rows) {
                const RuleMeta* meta = find_rule(id);
                std::string name = html_escape(r->name);
                if (!r->first.empty()) name = fmt::format("<a href=\"#{}\">{}</a>", r->first, name);
                std::string link = meta ? fmt::format("<a href=\"{}\" title=\"{}\">{}</a>", html_escape(rule_url(id)),
                                                      html_escape(meta->summary), html_escape(id))
                                        : html_escape(id);
                s += fmt::format("<tr><td class=\"code\">{}</td><td>{}</td><td><span class=\"sev {}\">{}</span></td>"
                                 "<td class=\"num\">{}</td></tr>\n",
                                 link, name, severity_class(r->severity), severity_name(r->severity), r->count);
            }
            s += "</tbody>\n</table>\n";
        }
        s += "</div>\n<div>\n<h3>Files</h3>\n<table class=\"files\">\n<thead><tr><th>File</th>"
             "<th class=\"num\">Errors</th><th class=\"num\">Warnings</th><th class=\"num\">Infos</th>"
             "<th class=\"num\">Cycle calls</th></tr></thead>\n<tbody>\n";
        for (const auto& f : files_) {
            auto cell = [](uint64_t n, const char* cls) {
                return fmt::format("<td class=\"num counts\"><span class=\"{}\">{}</span></td>", n ? cls : "zero", n);
            };
            s += fmt::format("<tr><td class=\"path\"><a href=\"#{}\">{}</a>{}</td>{}{}{}<td class=\"num\">{}</td></tr>\n",
                             f.anchor, html_escape(f.path), f.unreadable ? " <span class=\"sev error\">unread</span>" : "",
                             cell(f.error, "error"), cell(f.warning, "warning"), cell(f.info, "info"), f.calls);
        }
        s += "</tbody>\n</table>\n</div>\n</div>\n</section>\n";
        out_ << s;
    }

    // ---------------------------------------------------------------- files

    // The lines around the kept findings, read again from the file (none for
    // standard input or a file that is not a regular file any more).
    std::map<uint32_t, std::string> read_lines(const std::vector<Excerpt>& wanted) const {
        std::map<uint32_t, std::string> lines;
        if (wanted.empty() || file_.path == stdin_path_) return lines;
        const int fd = ::open(file_.path.c_str(), O_RDONLY | O_CLOEXEC);
        if (fd < 0) return lines;
        struct stat st {};
        if (::fstat(fd, &st) == 0 && S_ISREG(st.st_mode)) {
            FdSource src(fd, static_cast<uint64_t>(st.st_size));
            LineStream stream(src, size_t(1) << 16);
            LineRef line;
            size_t w = 0;  // wanted is sorted by first line
            const uint32_t last = std::max_element(wanted.begin(), wanted.end(), [](const Excerpt& a, const Excerpt& b) {
                                      return a.last < b.last;
                                  })->last;
            while (stream.next(line) && line.line <= last) {
                while (w < wanted.size() && wanted[w].last < line.line) ++w;
                bool want = false;
                for (size_t k = w; k < wanted.size() && wanted[k].first <= line.line; ++k)
                    if (line.line <= wanted[k].last) want = true;
                if (want) lines.emplace(line.line, std::string(line.text.substr(0, cut_at(line.text, kMaxLineShown + 4))));
            }
        }
        ::close(fd);
        return lines;
    }

    // The last line a range covers (not the next line when it ends at its start).
    static uint32_t last_line(const SourceRange& r) {
        if (r.end.line > r.start.line && r.end.byte_col == 0) return r.end.line - 1;
        return std::max(r.end.line, r.start.line);
    }

    static Excerpt excerpt_of(const Diagnostic& d) {
        const uint32_t start = d.range.start.line;
        const uint32_t end = std::min(last_line(d.range), start + 4);
        return {start > kHtmlContext ? start - kHtmlContext : 1, end + kHtmlContext};
    }

    // A source line, shortened when long, with the bytes [from, to) marked
    // when `mark` is set. An empty range marks the character at `from` (a
    // blank at the end of the line).
    static std::string code_cell(std::string_view text, bool mark = false, size_t from = 0, size_t to = 0) {
        const size_t shown = cut_at(text, kMaxLineShown);
        const std::string_view t = text.substr(0, shown);
        std::string s;
        if (!mark) {
            s = html_escape(t);
        } else {
            from = std::min(from, t.size());
            to = std::min(std::max(to, from), t.size());
            if (to == from && from < t.size()) to = from + std::max<size_t>(1, utf8_length(t, from));
            s = html_escape(t.substr(0, from));
            s += "<mark>" + (to > from ? html_escape(t.substr(from, to - from)) : std::string(" ")) + "</mark>";
            s += html_escape(t.substr(to));
        }
        if (shown < text.size()) s += "<span class=\"muted\"> …</span>";
        return s;
    }

    static std::string source_table(const Diagnostic& d, const std::map<uint32_t, std::string>& lines) {
        const Excerpt ex = excerpt_of(d);
        const uint32_t start = d.range.start.line;
        const uint32_t end = last_line(d.range);
        // The lines read again must be those the finding was made on.
        auto it = lines.find(start);
        const bool have = it != lines.end() &&
                          std::string_view(it->second).substr(0, std::min(it->second.size(), d.line_text.size())) ==
                              std::string_view(d.line_text).substr(0, std::min(it->second.size(), d.line_text.size()));
        std::string s = "<table class=\"src\">\n";
        auto row = [&](uint32_t n, std::string_view text) {
            const bool hit = n >= start && n <= end;
            size_t from = 0, to = 0;
            if (hit) {
                from = n == start ? d.range.start.byte_col : 0;
                to = n == end && d.range.end.line == end ? d.range.end.byte_col : text.size();
                if (n == start && n == end && to < from) to = from;
            }
            s += fmt::format("<tr{}><td class=\"ln\">{}</td><td class=\"code\">{}</td></tr>\n",
                             hit ? " class=\"hit\"" : "", n, code_cell(text, hit, from, to));
        };
        if (!have) {
            row(start, d.line_text);
        } else {
            for (uint32_t n = ex.first; n <= ex.last; ++n) {
                auto l = lines.find(n);
                if (l == lines.end()) {
                    if (n > start) break;  // the end of the file
                    continue;
                }
                row(n, l->second);
            }
        }
        return s + "</table>\n";
    }

    static std::string place(const SourceRange& r) {
        return fmt::format("line {}, column {}", r.start.line, r.start.cp_col + 1);
    }

    std::string finding(const Kept& k, const std::map<uint32_t, std::string>& lines) const {
        const Diagnostic& d = k.d;
        const RuleMeta* meta = find_rule(d.rule);
        std::string s = fmt::format("<article class=\"finding {}\" id=\"{}\">\n<header><span class=\"sev {}\">{}</span>",
                                    severity_class(d.severity), anchor(k.index), severity_class(d.severity),
                                    severity_name(d.severity));
        s += meta ? fmt::format("<a class=\"rule code\" href=\"{}\">{}</a>", html_escape(rule_url(d.rule)),
                                html_escape(d.rule))
                  : fmt::format("<span class=\"rule code\">{}</span>", html_escape(d.rule));
        s += fmt::format("<span class=\"name\">{}</span><span class=\"loc\">{}</span></header>\n", html_escape(d.name),
                         place(d.range));
        s += "<p class=\"msg\">" + html_escape(d.message) + "</p>\n";
        s += source_table(d, lines);
        if (!d.notes.empty() || !d.fixes.empty() || d.folded) {
            s += "<ul>\n";
            for (const auto& n : d.notes) {
                s += "<li class=\"note\">note: " + html_escape(n.message);
                if (n.range && n.range->start.line != d.range.start.line)
                    s += fmt::format(" <span class=\"muted\">({})</span>", place(*n.range));
                s += "</li>\n";
            }
            for (const auto& f : d.fixes) {
                s += std::string("<li class=\"fix\"><strong>") + (f.safe ? "Fix" : "Fix (unsafe)") + ":</strong> " +
                     html_escape(f.title);
                for (const auto& e : f.edits) {
                    const bool insert = e.range.bytes.empty();
                    if (insert && e.replacement.empty()) continue;
                    s += fmt::format(" <span class=\"muted\">({} {})</span> ",
                                     insert ? "insert at" : e.replacement.empty() ? "delete at" : "replace at",
                                     place(e.range));
                    if (!e.replacement.empty()) s += "<code>" + html_escape(e.replacement) + "</code>";
                }
                s += "</li>\n";
            }
            if (d.folded) {
                s += fmt::format("<li class=\"note\">and {} more like this in this file", d.folded);
                if (d.folded_last) s += fmt::format(" (the last at line {})", d.folded_last->start.line);
                s += "</li>\n";
            }
            s += "</ul>\n";
        }
        return s + "</article>\n";
    }

    static std::string side_view(const SideView& v) {
        std::string s = fmt::format("<section class=\"cycles\">\n<h3>Cycle-axis side view{}{}</h3>\n",
                                    v.program.empty() ? "" : ": ", html_escape(v.program));
        s += "<div class=\"sideview\">\n<div class=\"calls\"><table>\n<thead><tr><th class=\"num\">Line</th>"
             "<th>Call or hole</th><th>Envelope</th></tr></thead>\n<tbody>\n";
        for (const auto& c : v.calls) {
            s += fmt::format("<tr{}><td class=\"num\">{}</td><td>{}</td><td class=\"code\">{}{}</td></tr>\n",
                             c.travel.empty() ? "" : " class=\"travel\"", c.line, html_escape(c.title),
                             html_escape(c.envelope),
                             c.travel.empty() ? "" : "<div class=\"why\">" + html_escape(c.travel) + "</div>");
        }
        s += "</tbody>\n</table>\n";
        if (v.omitted)
            s += fmt::format("<p class=\"more\">and {} more, not listed and not drawn</p>\n", v.omitted);
        s += "</div>\n<div class=\"figure\">\n" + v.svg + "</div>\n</div>\n</section>\n";
        return s;
    }

    void write_file(const std::string& io_error, const std::vector<SideView>& views) {
        std::sort(kept_.begin(), kept_.end(), [](const Kept& a, const Kept& b) {
            if (diagnostic_less(a.d, b.d)) return true;
            if (diagnostic_less(b.d, a.d)) return false;
            return a.index < b.index;
        });
        std::vector<Excerpt> wanted;
        for (const auto& k : kept_) wanted.push_back(excerpt_of(k.d));
        std::sort(wanted.begin(), wanted.end(), [](const Excerpt& a, const Excerpt& b) { return a.first < b.first; });
        const auto lines = read_lines(wanted);

        const FileRow& f = file_;
        std::string s = fmt::format("<section class=\"box file\" id=\"{}\">\n<h2 class=\"path\">{}</h2>\n", f.anchor,
                                    html_escape(f.path));
        s += "<p class=\"counts\">";
        for (auto [n, cls, word] : {std::tuple{f.error, "error", "error"}, std::tuple{f.warning, "warning", "warning"},
                                    std::tuple{f.info, "info", "info"}})
            s += fmt::format("<span class=\"{}\">{}</span>", n ? cls : "zero", plural(n, word));
        if (f.suppressed) s += fmt::format("<span class=\"zero\">{} suppressed</span>", f.suppressed);
        s += "<a href=\"#summary\" class=\"muted\">back to the summary</a></p>\n";
        if (!io_error.empty()) s += "<p class=\"io-error\">" + html_escape(io_error) + "</p>\n";
        if (kept_.empty() && io_error.empty()) s += "<p class=\"clean\">No findings.</p>\n";
        body_.append(s);
        for (const auto& k : kept_) body_.append(finding(k, lines));
        if (omitted_)
            body_.append(fmt::format("<p class=\"more\">and {} more finding{} not shown here (the report shows {} "
                                     "findings of a file; the text, JSON and SARIF reports list every one)</p>\n",
                                     omitted_, omitted_ == 1 ? "" : "s", kHtmlMaxFindings));
        for (const auto& v : views) body_.append(side_view(v));
        body_.append("</section>\n");
    }

    std::ostream& out_;
    SideViews* views_;
    std::string stdin_path_;
    Spool body_;
    std::map<std::string, RuleRow> rules_;
    std::vector<FileRow> files_;
    FileRow file_;
    std::vector<Kept> kept_;
    size_t arrived_ = 0;
    uint64_t omitted_ = 0;
};

}  // namespace

std::string html_escape(std::string_view s) {
    std::string out;
    out.reserve(s.size() + s.size() / 8);
    for (size_t i = 0; i < s.size();) {
        const char c = s[i];
        switch (c) {
            case '&': out += "&amp;"; ++i; continue;
            case '<': out += "&lt;"; ++i; continue;
            case '>': out += "&gt;"; ++i; continue;
            case '"': out += "&quot;"; ++i; continue;
            case '\'': out += "&#39;"; ++i; continue;
            default: break;
        }
        const auto u = static_cast<unsigned char>(c);
        if ((u < 0x20 && c != '\t' && c != '\n') || u == 0x7f) {
            out += "\xEF\xBF\xBD";
            ++i;
            continue;
        }
        const size_t n = utf8_length(s, i);
        if (n == 0) {
            out += "\xEF\xBF\xBD";
            ++i;
            continue;
        }
        out.append(s.substr(i, n));
        i += n;
    }
    return out;
}

std::unique_ptr<ReportWriter> make_html_writer(std::ostream& out, const WriterOptions& options) {
    return std::make_unique<HtmlWriter>(out, options);
}

}  // namespace osplint
