// Report formats for CI, next to the text and JSON renderers of report.h and
// the SARIF renderer of sarif.h.
#pragma once

#include <string>
#include <string_view>
#include <vector>

#include "osplint/osplint.h"

namespace osplint {

// `path:line:col: error|warning|note: message [OSP104]`, one line per finding
// (info is `note`), in path order. Columns are 1-based code points, as in the
// text report. Suppressed findings are left out.
std::string render_gcc(const std::vector<FileResult>& results);

// GitHub Actions workflow commands, one per finding:
//   ::error file=PATH,line=L,col=C,endLine=EL,endColumn=EC,title=OSP104::message
// error -> ::error, warning -> ::warning, info -> ::notice; errors first, then
// warnings, then notices (GitHub shows only the first few of each per step),
// each group in path order. Notes follow the message on their own lines.
std::string render_github(const std::vector<FileResult>& results);

// The escaping of GitHub workflow commands: the message ("data") escapes
// % CR LF; property values also escape ':' and ','.
std::string github_escape_data(std::string_view s);
std::string github_escape_property(std::string_view s);

// The JSON report (render_json's version 1 contract, unchanged) plus, per file,
// `"suppressed": [...]`: the silenced findings, each with the fields of a
// diagnostic and `"suppression": {"kind": "inSource"|"baseline", "reason",
// "scope": "block"|"file"|"baseline", "directive": range}`; and
// `summary.suppressed`, their count.
std::string render_json_report(const std::vector<FileResult>& results);

}  // namespace osplint
