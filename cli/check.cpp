// `osplint check`: the batch path for CAM pre-flight and CI.
#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <cstdio>
#include <cstring>
#include <atomic>
#include <chrono>
#include <condition_variable>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <functional>
#include <iostream>
#include <iterator>
#include <map>
#include <memory>
#include <mutex>
#include <optional>
#include <thread>

#include <fmt/format.h>

#include "output/baseline.h"
#include "output/diff.h"
#include "support/errors.h"
#include "api/check.h"
#include "api/config.h"
#include "api/fix.h"
#include "engine/summaries.h"
#include "engine/workspace.h"
#include "output/ordered.h"
#include "output/pipeline.h"
#include "output/sideview.h"
#include "output/writer.h"
#include "cli/commands.h"
#include "osplint/osplint.h"
#include "rules/registry.h"
#include "support/glob.h"
#include "support/threads.h"

namespace fs = std::filesystem;

namespace osplint::cli {

void add_check_options(CLI::App& cmd, CheckOptions& o) {
    cmd.add_option("paths", o.paths, "Files, directories (.MIN .SSB .SUB .SDF .LIB .NC .MSB) or - for stdin")->required();
    cmd.add_option("--format", o.format,
                   "Output format: text, json, sarif, gcc, github or html (one page: summary, findings with their "
                   "lines, cycle-axis side views)")
        ->check(CLI::IsMember({"text", "json", "sarif", "gcc", "github", "html"}));
    cmd.add_option("--config", o.config, "Configuration file (default: nearest osplint.toml of each file)");
    cmd.add_option("--fail-on", o.fail_on, "Lowest severity that makes the exit code 1")
        ->check(CLI::IsMember({"error", "warning", "info", "never"}));
    // One value per occurrence (comma-separated, repeatable): a list option
    // that took every word after it would take the paths that follow too.
    cmd.add_option("--select", o.select,
                   "Only these rules (IDs, names or prefixes such as OSP2; comma-separated, repeatable)")
        ->delimiter(',')
        ->allow_extra_args(false);
    cmd.add_option("--ignore", o.ignore, "Not these rules (IDs, names or prefixes; comma-separated, repeatable)")
        ->delimiter(',')
        ->allow_extra_args(false);
    cmd.add_option("--exclude", o.exclude,
                   "Skip files and folders matching this glob pattern when walking directories (repeatable; "
                   "adds to osplint.toml's exclude)")
        ->allow_extra_args(false);
    cmd.add_flag("--force-exclude", o.force_exclude,
                 "Apply the exclusions to the files and directories named on the command line too");
    cmd.add_option("--stdin-filename", o.stdin_filename, "Path to report for the program read from stdin");
    cmd.add_option("--color", o.color, "Color in text output")->check(CLI::IsMember({"auto", "always", "never"}));
    cmd.add_option("-j,--jobs", o.jobs, "Files checked in parallel (default: one per core)");
    cmd.add_option("--baseline", o.baseline, "Report only findings not recorded in this baseline file");
    cmd.add_option("--write-baseline", o.write_baseline,
                   "Record the current findings in this baseline file (they are then accepted)");
    cmd.add_option("--max-findings", o.max_findings,
                   "Show at most N findings per file; the others are counted (default: no limit)");
    cmd.add_flag("--engine-stats", o.engine_stats,
                 "Print what the analysis did for each file (lines, loops, sweeps, ...) on stderr");
    cmd.add_flag("--statistics", o.statistics,
                 "Print how many findings each rule made (text) instead of the findings; no folding, no limit");
    cmd.add_option("--output-file,-o", o.output_file, "Write the report to this file instead of standard output");
    cmd.add_flag("-q,--quiet", o.quiet, "Print the findings only: no summary line, no notes on standard error");
    cmd.add_flag("--fix", o.fix,
                 "Apply the safe fixes to the files (atomically; a file with syntax errors is left as it is), then "
                 "report what is left; for stdin, print the fixed program");
    cmd.add_flag("--unsafe-fixes", o.unsafe_fixes, "With --fix or --diff: apply the unsafe fixes too");
    cmd.add_flag("--diff", o.diff,
                 "Print the fixes --fix would apply as a unified diff (for patch -p1 or git apply) and change "
                 "nothing; exit code 1 when there is something to fix");
    cmd.add_option("--fold", o.fold,
                   "Show at most N findings of one kind (rule and message) per file, and the others as a count "
                   "(default 10; 0 shows every one)");
}

namespace {

// --select / --ignore on top of the configuration's [rules]. A rule that
// prefixes do not reach (OSP001) stays as it is: a file that does not parse
// is never passed over silently.
void apply_selection(Config& c, const CheckOptions& o) {
    for (const auto& m : all_rules()) {
        if (!m.selected_by_prefix) continue;
        bool selected = o.select.empty();
        for (const auto& p : o.select)
            if (rule_matches(m.id, p)) selected = true;
        for (const auto& p : o.ignore)
            if (rule_matches(m.id, p)) selected = false;
        if (!selected) {
            c.rule_severity[std::string(m.id)] = std::nullopt;
        } else if (!o.select.empty() && !c.severity_of(m.id, m.severity, m.enabled_by_default)) {
            // Explicitly selected rules run even when off by default.
            bool explicit_id = false;
            for (const auto& p : o.select)
                if (p == m.id) explicit_id = true;
            if (explicit_id) c.rule_severity[std::string(m.id)] = m.severity;
        }
    }
}

// Rule names in --select / --ignore become their IDs; a prefix stays as written.
CheckOptions resolve_selection(const CheckOptions& o) {
    CheckOptions r = o;
    for (auto* list : {&r.select, &r.ignore})
        for (auto& p : *list)
            if (const RuleMeta* m = builtin_rules().resolve(p)) p = std::string(m->id);
    return r;
}

void validate_selection(const CheckOptions& o) {
    for (const auto* list : {&o.select, &o.ignore})
        for (const auto& p : *list) {
            bool any = false;
            for (const auto& m : all_rules())
                if (rule_matches(m.id, p)) any = true;
            if (!any)
                throw std::runtime_error("no rule matches '" + p + "'" + builtin_rules().suggestion(p) +
                                         " (see `osplint rules`)");
        }
}

std::string describe(const EngineStats& s) {
    return fmt::format("{} bytes, {} lines, {} programs; outline parsed {} lines; walk parsed {} blocks ({} by "
                       "tree-sitter), {} transfers ({} plain moves a run at a time, {} checked from their values "
                       "without a block, {} calls taken from the call before but for their values, {} positioning blocks of "
                       "a MODIN that kept the call before, {} repeats of the block before moved in the plane, {} of them "
                       "told from their text); {} loops ({} held in memory), {} sweeps without the rules, "
                       "{} walked with the rules after one sweep",
                       s.bytes, s.lines, s.programs, s.outline_lines_parsed, s.blocks_parsed, s.fallback_lines,
                       s.transfers, s.run_blocks, s.value_blocks, s.calls_again, s.modin_calls_kept, s.repeats, s.text_repeats,
                       s.loops,
                       s.held_loops, s.loop_sweeps, s.speculative_walks);
}

// Checks every file on a pool of worker threads, each file's findings handed
// on through its channel of `out` as the walk makes them: the report is in
// path order and identical whatever the number of workers, and memory does not
// grow with the findings. With `side_views` (the HTML report), each walk also
// records the cycle-axis envelopes of its blocks for the writer (the same walk:
// the tap is the engine's block observer). Returns an error when the workers
// could not all be started (the files are then checked by those that were).
// `check_one(i, options, sink)` checks file i.
using CheckOne = std::function<void(size_t, const AnalysisOptions&, DiagnosticSink&)>;
std::string check_files(const std::vector<std::string>& files, const std::vector<std::shared_ptr<Config>>& configs,
                        const std::string& stdin_name, const CheckOne& check_one, const AnalysisOptions& options,
                        unsigned jobs, OrderedOutput& out, bool progress, bool report_stats, SideViews* side_views) {
    std::atomic<size_t> next{0};
    std::atomic<size_t> done{0};
    std::mutex mu;
    std::condition_variable cv;
    auto worker = [&] {
        for (size_t i; (i = next.fetch_add(1)) < files.size();) {
            DiagnosticSink& channel = out.channel(i);
            std::optional<SideViewTap> tap;
            if (side_views && configs[i]) tap.emplace(channel, *configs[i], *side_views);
            DiagnosticSink& sink = tap ? static_cast<DiagnosticSink&>(*tap) : channel;
            const std::string path = files[i] == "-" ? stdin_name : files[i];
            try {
                AnalysisOptions mine = options;
                EngineStats stats;
                if (report_stats) mine.stats = &stats;
                if (tap) mine.observer = &*tap;
                check_one(i, mine, sink);
                if (report_stats) {
                    std::lock_guard<std::mutex> lock(mu);
                    std::cerr << "osplint: " << path << ": " << describe(stats) << "\n";
                }
            } catch (const std::bad_alloc&) {
                sink.end_file(path, "out of memory while checking this file");
            } catch (const std::exception& e) {
                sink.end_file(path, std::string("internal error while checking this file (please report it): ") +
                                        e.what());
            }
            done.fetch_add(1);
            cv.notify_one();
        }
    };
    unsigned n = jobs ? jobs : std::max(1u, std::thread::hardware_concurrency());
    n = static_cast<unsigned>(std::min<size_t>(n, std::max<size_t>(files.size(), 1)));
    if (n <= 1 && !progress) {
        worker();
        return {};
    }
    // This thread shows the progress, or is one of the workers.
    auto show_progress = [&] {
        std::unique_lock<std::mutex> lock(mu);
        while (done.load() < files.size()) {
            cv.wait_for(lock, std::chrono::milliseconds(100));
            std::cerr << "\rosplint: checked " << done.load() << "/" << files.size() << " files" << std::flush;
        }
        std::cerr << "\r\x1b[K" << std::flush;
    };
    if (progress) return run_on_threads(n, worker, show_progress);
    return run_on_threads(n - 1, worker, worker);
}

// What --fix or --diff did to one file.
struct FixOutcome {
    uint64_t fixes = 0;      // fixes applied (or, with --diff, that would be)
    std::string note;        // why the file was left as it is (a state of the program)
    std::string error;       // what went wrong (exit code 2)
    std::unique_ptr<Spool> diff;  // --diff: the file's diff
    DiffStats stats;
};

// Plans the fixes of a program read from `fd` (its stamp `before`: a file
// that changes while it is read fails the plan); with `diff`, renders them as
// a diff, else hands the fixed text to `write`.
void fix_program(int fd, const FileStamp& before, const std::string& path, const Config& config,
                 const AnalysisOptions& options, bool unsafe, bool diff,
                 const std::function<bool(FdSource&, const std::vector<Edit>&, std::string&)>& write,
                 FixOutcome& out) {
    FdSource src(fd, before);
    FixPlan plan = plan_fixes(path, src, config, options, unsafe);
    if (!plan.refused.empty()) {
        (plan.failed ? out.error : out.note) = plan.refused;
        return;
    }
    if (plan.edits.empty()) return;
    std::string error;
    if (diff) {
        out.diff = std::make_unique<Spool>(size_t(1) << 16);
        if (!write_unified_diff(src, plan.edits, path, [&](std::string_view piece) { return out.diff->append(piece); },
                                error, &out.stats)) {
            out.error = "the diff could not be made: " + (out.diff->error().empty() ? error : out.diff->error());
            out.diff.reset();
            return;
        }
    } else if (!write(src, plan.edits, error)) {
        out.error = "not fixed: " + error;
        return;
    }
    out.fixes = plan.fixes;
}

// --fix / --diff for a file on disk: the fixes are planned on the file as it
// is, and written over it atomically (through a symbolic link, to its
// target), unless it changed meanwhile. What cannot be opened is left to the
// check to report.
void fix_file(const std::string& path, const Config& config, const AnalysisOptions& options, bool unsafe, bool diff,
              FixOutcome& out) {
    std::error_code ec;
    const fs::path target = fs::canonical(path, ec);
    if (ec) return;
    const int fd = ::open(target.c_str(), O_RDONLY | O_CLOEXEC);
    if (fd < 0) return;
    struct stat st;
    const std::optional<FileStamp> before = file_stamp(fd);
    if (::fstat(fd, &st) != 0 || !S_ISREG(st.st_mode) || !before || before->size > kMaxInputSize) {
        ::close(fd);
        return;
    }
    auto write = [&](FdSource& src, const std::vector<Edit>& edits, std::string& error) {
        return write_fixes(target.string(), *before, src, edits, error);
    };
    fix_program(fd, *before, path, config, options, unsafe, diff, write, out);
    ::close(fd);
}

// --fix / --diff for standard input (already in the temporary file `fd`):
// with --fix the fixed program is printed on standard output and `fd`
// becomes a temporary file of it, which the check then reads.
void fix_stdin(int& fd, const std::string& path, const Config& config, const AnalysisOptions& options, bool unsafe,
               bool diff, FixOutcome& out) {
    const std::optional<FileStamp> before = fd < 0 ? std::nullopt : file_stamp(fd);
    if (!before) return;
    int fixed_fd = -1;
    auto write = [&](FdSource& src, const std::vector<Edit>& edits, std::string& error) {
        std::FILE* f = std::tmpfile();
        if (!f) {
            error = std::string("cannot create a temporary file: ") + std::strerror(errno);
            return false;
        }
        const bool ok = apply_edits(src, edits, [&](std::string_view piece) {
            return std::fwrite(piece.data(), 1, piece.size(), f) == piece.size();
        }, error) && std::fflush(f) == 0;
        if (ok) fixed_fd = ::dup(fileno(f));
        std::fclose(f);
        return ok && fixed_fd >= 0;
    };
    fix_program(fd, *before, path, config, options, unsafe, diff, write, out);
    if (diff) return;
    if (fixed_fd >= 0) {
        ::close(fd);
        fd = fixed_fd;
    }
    // The program, fixed or as it was, on standard output.
    std::vector<char> buf(size_t(1) << 20);
    for (uint64_t off = 0;;) {
        const int64_t r = pread_full(fd, off, buf.data(), buf.size());
        if (r <= 0) break;
        std::cout.write(buf.data(), r);
        off += static_cast<uint64_t>(r);
    }
    std::cout.flush();
    if (!std::cout) out.error = "the fixed program could not be written to standard output";
}

// --statistics: how many findings each rule made, in place of the findings.
class RuleStatistics final : public DiagnosticSink {
public:
    void diagnostic(Diagnostic&& d) override {
        auto& [name, count] = rules_[d.rule];
        name = d.name;
        count += 1 + d.folded;
    }
    // Most findings first, then by rule ID.
    void write(std::ostream& out) const {
        std::vector<std::pair<std::string, std::pair<std::string, uint64_t>>> rows(rules_.begin(), rules_.end());
        std::stable_sort(rows.begin(), rows.end(),
                         [](const auto& a, const auto& b) { return a.second.second > b.second.second; });
        for (const auto& [rule, entry] : rows) out << fmt::format("{:>7}  {}  {}\n", entry.second, rule, entry.first);
    }

private:
    std::map<std::string, std::pair<std::string, uint64_t>> rules_;
};

// Notes the files that could not be read, for the message at the end.
class Unreadable final : public DiagnosticSink {
public:
    explicit Unreadable(DiagnosticSink& next) : next_(next) {}
    bool wants_fingerprints() const override { return next_.wants_fingerprints(); }
    void begin_file(const std::string& path) override { next_.begin_file(path); }
    void diagnostic(Diagnostic&& d) override { next_.diagnostic(std::move(d)); }
    void suppressed(SuppressedDiagnostic&& s) override { next_.suppressed(std::move(s)); }
    void end_file(const std::string& path, const std::string& io_error) override {
        if (!io_error.empty()) errors.push_back(path + ": " + io_error);
        next_.end_file(path, io_error);
    }
    std::vector<std::string> errors;

private:
    DiagnosticSink& next_;
};

// The --exclude patterns, once the options that go together are checked.
std::vector<PathPattern> check_usage(const CheckOptions& o) {
    validate_selection(o);
    if (o.statistics && o.format != "text") throw std::runtime_error("--statistics prints text: it takes no --format");
    if (o.diff && (o.format != "text" || o.statistics || !o.baseline.empty() || !o.write_baseline.empty()))
        throw std::runtime_error("--diff prints a diff: it takes no --format, --statistics, --baseline or --write-baseline");
    std::vector<PathPattern> exclude;  // relative to the working directory
    for (const auto& p : o.exclude) {
        std::string_view why;
        if (!glob_valid(p, &why)) throw std::runtime_error("--exclude '" + p + "': " + std::string(why));
        std::string pattern = p;
        while (pattern.size() > 2 && pattern.compare(0, 2, "./") == 0) pattern.erase(0, 2);
        exclude.push_back({pattern, fs::path("."), "--exclude"});
    }
    return exclude;
}

// Each checked file's configuration: one file for everything (--config),
// else the nearest osplint.toml of the file's directory (for stdin: of
// --stdin-filename's), with the [[per-path]] tables that match the file,
// then --select / --ignore. A broken osplint.toml is reported once, the
// files it applies to are not checked (no configuration), and the others are.
class Configurations {
public:
    Configurations(const CheckOptions& o, std::vector<PathPattern> exclude) : o_(o), exclude_(std::move(exclude)) {
        if (!o.config.empty()) fixed_ = std::make_shared<Config>(load_config(o.config));
    }

    fs::path dir_of(const std::string& file) const {
        fs::path dir = file == "-" ? (o_.stdin_filename.empty() ? fs::path(".") : fs::path(o_.stdin_filename).parent_path())
                                   : fs::path(file).parent_path();
        if (dir.empty()) dir = ".";
        return dir;
    }

    // What a directory walk skips: --exclude, and the `exclude` of the
    // configuration that applies there.
    bool excluded(const fs::path& p) {
        for (const auto& e : exclude_)
            if (path_matches(e, p)) return true;
        fs::path dir = p.parent_path();
        if (dir.empty()) dir = ".";
        const auto c = of_dir(dir);
        return c && c->excluded(p);
    }

    // Null when the file's osplint.toml has an error.
    std::shared_ptr<Config> for_file(const std::string& file) {
        const fs::path dir = dir_of(file);
        auto base = of_dir(dir);
        if (!base) return nullptr;
        const fs::path named = file == "-" ? (o_.stdin_filename.empty() ? fs::path() : fs::path(o_.stdin_filename))
                                           : fs::path(file);
        const std::vector<size_t> tables = named.empty() ? std::vector<size_t>{} : base->per_path_matching(named);
        std::string key = (fixed_ ? std::string("\n") : dir.string()) + "\n";
        for (size_t t : tables) key += std::to_string(t) + ",";
        if (auto it = by_file_kind_.find(key); it != by_file_kind_.end()) return it->second;
        auto c = std::make_shared<Config>(*base);
        c->apply_per_path(tables);
        apply_selection(*c, o_);
        by_file_kind_[key] = c;
        return c;
    }

    // One message per broken configuration file.
    std::vector<std::string> errors() const {
        std::vector<std::string> out;
        for (const auto& [file, error] : broken_) out.push_back("configuration error: " + error);
        return out;
    }
    // Why a file without a configuration is not checked.
    std::string not_checked(const std::string& file) const {
        const auto it = broken_by_dir_.find(dir_of(file).string());
        return "not checked: its configuration " + (it == broken_by_dir_.end() ? std::string() : it->second) +
               " has an error";
    }

private:
    // As read, before [[per-path]] and the selection.
    std::shared_ptr<Config> of_dir(const fs::path& dir) {
        if (fixed_) return fixed_;
        const std::string key = dir.string();
        if (auto it = by_dir_.find(key); it != by_dir_.end()) return it->second;
        auto c = std::make_shared<Config>();
        if (auto f = find_config(dir)) {
            try {
                *c = load_config(*f);
            } catch (const ConfigError& e) {
                broken_.emplace(f->string(), e.what());
                broken_by_dir_[key] = f->string();
                c = nullptr;
            }
        }
        by_dir_[key] = c;
        return c;
    }

    const CheckOptions& o_;
    std::vector<PathPattern> exclude_;
    std::shared_ptr<Config> fixed_;
    std::map<std::string, std::string> broken_;  // configuration file -> its error
    std::map<std::string, std::string> broken_by_dir_;
    std::map<std::string, std::shared_ptr<Config>> by_dir_;
    std::map<std::string, std::shared_ptr<Config>> by_file_kind_;
};

// What the check knows beside each file's own text: the program names the
// checked files and the subprogram files (.SSB/.SUB/.LIB/.MSB) beside them
// define (for unknown-subprogram checks), and standard input.
struct KnownPrograms {
    ProgramNames names;
    SubprogramDirectories directories;
    int stdin_fd = -1;  // stdin copied to an unlinked temporary file: read twice, never held
    std::string stdin_error;
};

void gather_programs(const std::vector<std::string>& files, const Configurations& configs, unsigned jobs,
                     KnownPrograms& out) {
    bool have_stdin = false;
    std::map<std::string, bool> scanned_dirs;
    // A file checked alone needs no pass of its own: the names it defines
    // matter to the other checked files, and the check finds its own names.
    const bool alone = files.size() == 1;
    std::vector<std::string> to_scan;
    for (const auto& f : files) {
        fs::path dir = configs.dir_of(f);
        if (!scanned_dirs[dir.string()]) {
            scanned_dirs[dir.string()] = true;
            out.directories.add_names(dir, out.names);
        }
        if (f == "-") {
            if (!have_stdin) {
                out.stdin_fd = spool_to_temporary_file(STDIN_FILENO, out.stdin_error);  // reported when checked
                have_stdin = true;
            }
            if (out.stdin_fd >= 0 && !alone) {
                FdSource src(out.stdin_fd, std::nullopt);
                add_program_names(src, out.names);
            }
            continue;
        }
        std::error_code ec;
        if (!alone && fs::is_regular_file(f, ec) && fs::file_size(f, ec) < (1ull << 32)) to_scan.push_back(f);
    }
    // The checked files' own names, read by as many threads as the check uses.
    const unsigned cores = std::max(1u, std::thread::hardware_concurrency());
    const size_t n = std::min<size_t>(jobs ? jobs : cores, to_scan.size());
    std::atomic<size_t> next{0};
    std::mutex mu;
    auto scan = [&] {
        ProgramNames found;
        for (size_t i; (i = next.fetch_add(1)) < to_scan.size();) add_program_names(fs::path(to_scan[i]), found);
        std::lock_guard<std::mutex> lock(mu);
        out.names.merge(found);
    };
    if (n >= 1) {
        const std::string error = run_on_threads(static_cast<unsigned>(n - 1), scan, scan);
        if (!error.empty()) std::cerr << "osplint: note: " << error << "; fewer files were read at once\n";
    }
}

// Standard error with a buffer, for the GitHub format's text log: std::cerr
// writes every piece at once and flushes standard output first (they are
// tied), three system calls per finding. Flushed at the end of each file, so
// what else goes to standard error keeps its place after that file's log.
class BufferedStderr final : public std::streambuf {
public:
    BufferedStderr() { setp(buf_, buf_ + sizeof buf_); }
    ~BufferedStderr() override { sync(); }
    int sync() override {
        const size_t n = static_cast<size_t>(pptr() - pbase());
        if (n && std::fwrite(pbase(), 1, n, stderr) != n) return -1;
        setp(buf_, buf_ + sizeof buf_);
        return std::fflush(stderr) == 0 ? 0 : -1;
    }

protected:
    int_type overflow(int_type c) override {
        if (sync() != 0) return traits_type::eof();
        if (!traits_type::eq_int_type(c, traits_type::eof())) {
            *pptr() = traits_type::to_char_type(c);
            pbump(1);
        }
        return traits_type::not_eof(c);
    }

private:
    char buf_[1 << 16];
};

// Forwards to a writer and flushes its stream when a file ends.
class FlushAtFileEnd final : public DiagnosticSink {
public:
    FlushAtFileEnd(DiagnosticSink& to, std::ostream& out) : to_(to), out_(out) {}
    bool wants_fingerprints() const override { return to_.wants_fingerprints(); }
    void begin_file(const std::string& path) override { to_.begin_file(path); }
    void diagnostic(Diagnostic&& d) override { to_.diagnostic(std::move(d)); }
    void suppressed(SuppressedDiagnostic&& s) override { to_.suppressed(std::move(s)); }
    void end_file(const std::string& path, const std::string& io_error) override {
        to_.end_file(path, io_error);
        out_.flush();
    }

private:
    DiagnosticSink& to_;
    std::ostream& out_;
};

// The chain the findings go through (output/pipeline.h), from the head the
// checks write to: the baseline (recorded or applied), the files that could
// not be read, counting, folding, the limit, then the writer(s), the rule
// statistics or nothing (--diff).
class ReportChain {
public:
    ReportChain(const CheckOptions& o, Format format, std::ostream& report, const WriterOptions& wo)
        : writer(make_writer(format, report, wo)),
          log(format == Format::Github && !o.diff && !o.statistics ? make_writer(Format::Text, log_stream, wo) : nullptr),
          log_flush(log ? std::make_unique<FlushAtFileEnd>(*log, log_stream) : nullptr),
          tee(log ? std::make_unique<TeeSink>(*writer, *log_flush) : nullptr),
          limit(o.diff ? static_cast<DiagnosticSink&>(discard)
                : o.statistics ? static_cast<DiagnosticSink&>(statistics)
                : tee ? static_cast<DiagnosticSink&>(*tee)
                      : *writer,
                o.statistics ? 0 : o.max_findings, counts),
          has_baseline(!o.write_baseline.empty() || !o.baseline.empty()),
          fold(limit, has_baseline ? fold_after(o) : 0, counts),
          count(fold, counts),
          unreadable(count) {
        if (!o.write_baseline.empty()) {
            recorder.emplace(unreadable, recorded, o.write_baseline);
            head_ = &*recorder;
        } else if (!o.baseline.empty()) {
            filter.emplace(unreadable, load_baseline(o.baseline), o.baseline);
            head_ = &*filter;
        }
    }
    DiagnosticSink& head() { return *head_; }
    // Ends the report: the rule statistics, or the writers' summary (with
    // --quiet, the text formats leave it out; JSON and SARIF end their
    // document).
    void finish(const CheckOptions& o, Format format, std::ostream& report) {
        if (o.statistics) statistics.write(report);
        const bool summary_only = format == Format::Text || format == Format::Github;
        if (!(o.quiet && summary_only) && !o.diff) writer->finish(counts);
        if (log && !o.quiet) log->finish(counts);
        log_stream.flush();
        report.flush();
    }
    // Folding is the engine's, which then need not build the findings it
    // only counts; after the baseline when there is one (it must see every
    // finding).
    uint64_t engine_fold(const CheckOptions& o) const { return has_baseline ? 0 : fold_after(o); }

    std::unique_ptr<ReportWriter> writer;
    BufferedStderr log_buffer;
    std::ostream log_stream{&log_buffer};
    std::unique_ptr<ReportWriter> log;  // GitHub: the annotations are for the pull request, the log gets the text
    std::unique_ptr<FlushAtFileEnd> log_flush;
    std::unique_ptr<TeeSink> tee;
    RuleStatistics statistics;
    DiscardFindings discard;  // --diff: the diff is the report
    Counts counts;
    LimitSink limit;
    const bool has_baseline;
    FoldingSink fold;
    CountingSink count;
    Unreadable unreadable;
    Baseline recorded;
    std::optional<BaselineFilter> filter;
    std::optional<BaselineRecorder> recorder;

private:
    // --statistics counts every finding.
    static uint64_t fold_after(const CheckOptions& o) { return o.statistics ? 0 : o.fold; }
    DiagnosticSink* head_ = &unreadable;
};

// --fix / --diff: each file's diff on the report, what went wrong in
// `errors`, and the count on standard error. Returns the fixes (applied or
// that would be).
uint64_t report_fixes(const CheckOptions& o, const std::vector<std::string>& files, const std::string& stdin_name,
                      std::vector<FixOutcome>& outcomes, std::ostream& report, std::vector<std::string>& errors) {
    uint64_t fixes = 0, fixed_files = 0;
    DiffStats diff_total;
    for (size_t i = 0; i < outcomes.size(); ++i) {
        auto& f = outcomes[i];
        const std::string& path = files[i] == "-" ? stdin_name : files[i];
        if (f.fixes) ++fixed_files;
        fixes += f.fixes;
        if (f.diff) {
            diff_total.hunks += f.stats.hunks;
            diff_total.added += f.stats.added;
            diff_total.removed += f.stats.removed;
            if (!f.diff->drain([&](std::string_view piece) { report.write(piece.data(), static_cast<std::streamsize>(piece.size())); }))
                errors.push_back(path + ": the diff could not be read back: " + f.diff->error());
        }
        if (!f.error.empty()) errors.push_back(path + ": " + f.error);
        if (!f.note.empty() && !o.quiet) std::cerr << "osplint: " << path << ": not fixed: " << f.note << "\n";
    }
    if ((o.fix || o.diff) && !o.quiet) {
        auto plural = [](uint64_t n, const char* one, const char* many) { return fmt::format("{} {}", n, n == 1 ? one : many); };
        if (o.diff)
            std::cerr << "osplint: " << plural(fixes, "fix", "fixes") << " in " << plural(fixed_files, "file", "files")
                      << (fixes ? " would be applied (" + plural(diff_total.hunks, "hunk", "hunks") + ")" : " to apply") << "\n";
        else
            std::cerr << "osplint: applied " << plural(fixes, "fix", "fixes") << " in " << plural(fixed_files, "file", "files")
                      << "\n";
    }
    return fixes;
}

// --write-baseline: written only when every file could be read (a file that
// could not be read would lose its entries).
void write_recorded_baseline(const CheckOptions& o, Baseline& recorded, bool io_failed, std::vector<std::string>& errors) {
    if (io_failed) {
        errors.push_back("the baseline " + o.write_baseline + " was not written: some files could not be read");
        return;
    }
    std::sort(recorded.entries.begin(), recorded.entries.end(), [](const BaselineEntry& x, const BaselineEntry& y) {
        return std::tie(x.path, x.rule, x.fingerprint) < std::tie(y.path, y.rule, y.fingerprint);
    });
    write_baseline(recorded, o.write_baseline);
    if (!o.quiet)
        std::cerr << "osplint: recorded " << recorded.entries.size() << " finding"
                  << (recorded.entries.size() == 1 ? "" : "s") << " in " << o.write_baseline << "\n";
}

// The files the paths name, less those excluded (--exclude, the
// configurations' `exclude`; with --force-exclude, standard input too when
// --stdin-filename is excluded).
std::vector<std::string> files_to_check(const CheckOptions& o, Configurations& configurations,
                                        std::vector<std::string>& errors) {
    auto excluded = [&](const fs::path& p) { return configurations.excluded(p); };
    std::vector<std::string> files = expand_paths(o.paths, errors, excluded, o.force_exclude);
    if (o.force_exclude && !o.stdin_filename.empty() && excluded(fs::path(o.stdin_filename)))
        files.erase(std::remove(files.begin(), files.end(), std::string("-")), files.end());
    return files;
}

// Whether the report written to `fd` is in colour (--color, NO_COLOR; never
// in a file named by --output).
bool use_color(const CheckOptions& o, int fd) {
    if (!o.output_file.empty() || std::getenv("NO_COLOR")) return false;
    if (o.color == "always") return true;
    return o.color == "auto" && isatty(fd);
}

}  // namespace

int run_check(const CheckOptions& given) {
    const CheckOptions o = resolve_selection(given);
    Configurations configurations(o, check_usage(o));
    const bool fixing = o.fix || o.diff;
    const bool fix_writes = o.fix && !o.diff;  // --fix --diff shows the diff and writes nothing
    std::ofstream output_file;
    if (!o.output_file.empty()) {
        output_file.open(o.output_file, std::ios::binary | std::ios::trunc);
        if (!output_file) throw std::runtime_error("cannot write the report to " + o.output_file);
    }
    // `--fix -` prints the fixed program on standard output: the report then goes to standard error.
    const bool program_on_stdout =
        fix_writes && o.output_file.empty() && std::find(o.paths.begin(), o.paths.end(), "-") != o.paths.end();
    std::ostream& report = !o.output_file.empty() ? static_cast<std::ostream&>(output_file)
                           : program_on_stdout    ? std::cerr
                                                  : std::cout;
    std::vector<std::string> errors;
    const std::string stdin_name = o.stdin_filename.empty() ? std::string("<stdin>") : o.stdin_filename;

    const std::vector<std::string> files = files_to_check(o, configurations, errors);
    std::vector<std::shared_ptr<Config>> configs;
    configs.reserve(files.size());
    for (const auto& f : files) configs.push_back(configurations.for_file(f));
    for (auto& e : configurations.errors()) errors.push_back(std::move(e));
    std::vector<std::string> not_checked(files.size());  // why a file is not checked
    for (size_t i = 0; i < files.size(); ++i)
        if (!configs[i]) not_checked[i] = configurations.not_checked(files[i]);

    KnownPrograms known;
    gather_programs(files, configurations, o.jobs, known);
    AnalysisOptions options;
    options.known_programs = &known.names;
    // What the user subprograms beside the checked files leave behind.
    SubprogramSummaries summaries(builtin_rules(), known.directories);
    options.summaries = &summaries;

    const Format format = *parse_format(o.format);
    WriterOptions wo;
    wo.color = use_color(o, format == Format::Github || program_on_stdout ? STDERR_FILENO : STDOUT_FILENO);
    wo.sarif_root = fs::current_path();
    SideViews side_views;  // HTML: the cycle-axis pictures of each file, from its walk
    if (format == Format::Html) {
        wo.side_views = &side_views;
        if (std::find(files.begin(), files.end(), "-") != files.end()) wo.stdin_path = stdin_name;
    }
    ReportChain chain(o, format, report, wo);
    options.fold = chain.engine_fold(o);
    OrderedOutput ordered(chain.head(), files.size());
    const bool progress = !o.quiet && files.size() > 20 && isatty(STDERR_FILENO) &&
                          (!o.output_file.empty() || !isatty(STDOUT_FILENO));
    // --fix / --diff: each file's fixes are planned (and, with --fix,
    // written) by the worker that then checks it; stdin first, here.
    int& stdin_fd = known.stdin_fd;  // fix_stdin may replace it with the fixed copy
    std::vector<FixOutcome> outcomes(fixing ? files.size() : 0);
    if (fixing)
        for (size_t i = 0; i < files.size(); ++i)
            if (files[i] == "-" && not_checked[i].empty() && stdin_fd >= 0)
                fix_stdin(stdin_fd, stdin_name, *configs[i], options, o.unsafe_fixes, o.diff, outcomes[i]);
    const CheckOne check_one = [&](size_t i, const AnalysisOptions& mine, DiagnosticSink& sink) {
        const std::string path = files[i] == "-" ? stdin_name : files[i];
        if (!not_checked[i].empty() || (files[i] == "-" && stdin_fd < 0)) {
            sink.begin_file(path);
            sink.end_file(path, not_checked[i].empty() ? known.stdin_error : not_checked[i]);
            return;
        }
        if (fixing && files[i] != "-") {
            AnalysisOptions plain = mine;  // the fix rounds are not the report's walk
            plain.observer = nullptr;
            plain.stats = nullptr;
            fix_file(files[i], *configs[i], plain, o.unsafe_fixes, o.diff, outcomes[i]);
        }
        if (o.diff) {  // nothing to report but what could not be read
            sink.begin_file(path);
            sink.end_file(path, "");
            return;
        }
        if (files[i] == "-") check_fd(stdin_fd, stdin_name, *configs[i], mine, sink);
        else check_path(files[i], *configs[i], mine, sink);
    };
    const std::string pool_error =
        check_files(files, configs, stdin_name, check_one, options, o.jobs, ordered, progress, o.engine_stats,
                    format == Format::Html ? &side_views : nullptr);
    if (stdin_fd >= 0) ::close(stdin_fd);
    const uint64_t fixes = report_fixes(o, files, stdin_name, outcomes, report, errors);
    chain.finish(o, format, report);
    if (!o.output_file.empty() && !output_file) errors.push_back("the report could not be written to " + o.output_file);
    if (!pool_error.empty() && !o.quiet) std::cerr << "osplint: note: " << pool_error << "; fewer files were checked at once\n";
    for (const auto& e : ordered.errors()) errors.push_back("output lost: " + e);
    for (const auto& e : chain.unreadable.errors) errors.push_back(e);
    const bool io_failed = !errors.empty();
    if (chain.recorder) write_recorded_baseline(o, chain.recorded, io_failed, errors);
    for (const auto& e : errors) std::cerr << "osplint: " << e << "\n";

    if (io_failed) return 2;
    if (o.diff) return fixes ? 1 : 0;
    if (o.fail_on == "never") return 0;
    return chain.counts.at_least(*parse_severity(o.fail_on)) > 0 ? 1 : 0;
}

}  // namespace osplint::cli
