// The side views of an HTML report: the cycle-axis envelopes of every macro
// call and fixed-cycle hole of a file, taken from the check's own walk.
//
// `osplint check --format html` gives each file's walk a SideViewTap: a
// BlockObserver of the engine (it sees every block the rules see, in the same
// walk: nothing is analysed twice) and a DiagnosticSink in front of the file's
// channel. When the walk ends, before the file's end_file goes on, the tap
// draws one picture per program (output/svg.h, inline form) and leaves it in
// the SideViews of the run; the HTML writer takes a file's pictures out when
// that file's end_file reaches it, which with parallel files may be later.
#pragma once

#include <cstddef>
#include <cstdint>
#include <map>
#include <mutex>
#include <string>
#include <vector>

#include "engine/engine.h"
#include "osplint/diagnostic.h"
#include "semantics/config.h"
#include "semantics/motion.h"

namespace osplint {

// One program's cycles as the report shows them: the picture and the calls.
struct SideView {
    struct Call {
        uint32_t line = 0;
        std::string title;     // "OZAGR (CALL)", "G81 hole"
        std::string envelope;  // "Z -37 .. 50", "Z ? .. 50"
        std::string travel;    // what passes a travel limit, "" when nothing does
    };
    std::string program;       // its name ("O1000"); empty when the file starts without one
    std::string svg;           // inline <svg> element
    std::vector<Call> calls;   // in program order (at most kMaxCalls per file)
    uint64_t omitted = 0;      // calls beyond the cap, neither listed nor drawn
};

// The side views of the files of a run, from the worker that walked a file to
// the writer. Files are keyed by the path they are reported under.
class SideViews {
public:
    void put(const std::string& path, std::vector<SideView> views);
    // The views of `path`, removed from here; empty when there are none.
    std::vector<SideView> take(const std::string& path);

private:
    std::mutex m_;
    std::map<std::string, std::vector<SideView>> files_;
};

// Collects the envelopes of one file's walk and hands the pictures on at its
// end. At most kMaxCalls envelopes of a file are kept (the others counted), so
// that what waits for the writer stays bounded whatever the size of the file.
class SideViewTap final : public BlockObserver, public DiagnosticSink {
public:
    static constexpr size_t kMaxCalls = 400;
    SideViewTap(DiagnosticSink& next, const Config& config, SideViews& views)
        : next_(next), config_(config), views_(views) {}

    // BlockObserver
    void program(const Program& program, bool subprogram) override;
    bool block(const BlockView& view, const LineRef& line) override;

    // DiagnosticSink
    bool wants_fingerprints() const override { return next_.wants_fingerprints(); }
    void begin_file(const std::string& path) override;
    void diagnostic(Diagnostic&& d) override { next_.diagnostic(std::move(d)); }
    void suppressed(SuppressedDiagnostic&& s) override { next_.suppressed(std::move(s)); }
    void end_file(const std::string& path, const std::string& io_error) override;

private:
    struct Collected {
        std::string name;
        std::vector<Envelope> envelopes;
        uint64_t omitted = 0;
    };
    DiagnosticSink& next_;
    const Config& config_;
    SideViews& views_;
    std::vector<Collected> programs_;
    size_t kept_ = 0;
};

// The side view of `envelopes`: the picture (ids prefixed with `id_prefix`)
// and the list of calls.
SideView make_side_view(std::string program, const std::vector<Envelope>& envelopes, const Config& config,
                        const std::string& title, const std::string& id_prefix);

}  // namespace osplint
