// The HTML report (`osplint check --format html`): one page per run, to be
// read in a browser without a network or scripts (the styles are in the page,
// the side views are inline SVG).
//
// At the top, the summary: files checked, findings by severity, the count of
// each rule with a link to its first finding and to its page. Then each file:
// its findings in line order, each with the lines around it (the columns of
// its range marked), its message, rule, severity, notes and fixes; and the
// cycle-axis side view of each of its programs beside the list of the cycle
// calls (output/sideview.h).
//
// The report stays bounded whatever the size of the files: the findings of a
// file beyond kMaxFindings are counted, not shown; the lines around the shown
// ones are read again from the file, line by line, when the file has ended,
// and only those are kept; the page is written to a spool (a temporary file
// past a few megabytes) until the summary, which comes first, is known.
#pragma once

#include <cstddef>
#include <iosfwd>
#include <memory>
#include <string>
#include <string_view>

#include "output/writer.h"

namespace osplint {

inline constexpr size_t kHtmlMaxFindings = 200;  // findings shown per file
inline constexpr unsigned kHtmlContext = 2;      // lines shown before and after a finding's lines

std::unique_ptr<ReportWriter> make_html_writer(std::ostream& out, const WriterOptions& options);

// Text for an HTML page: & < > " ' escaped, invalid UTF-8 and control
// characters (but tab and line feed) replaced by U+FFFD.
std::string html_escape(std::string_view s);

}  // namespace osplint
