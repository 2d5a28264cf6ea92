#include "osplint/diagnostic.h"

#include <tuple>

namespace osplint {

std::string_view severity_name(Severity s) {
    switch (s) {
        case Severity::Info: return "info";
        case Severity::Warning: return "warning";
        case Severity::Error: return "error";
    }
    return "error";
}

std::optional<Severity> parse_severity(std::string_view s) {
    if (s == "info") return Severity::Info;
    if (s == "warning") return Severity::Warning;
    if (s == "error") return Severity::Error;
    return std::nullopt;
}

bool diagnostic_less(const Diagnostic& a, const Diagnostic& b) {
    return std::tie(a.range.bytes.begin, a.range.bytes.end, a.rule, a.message) <
           std::tie(b.range.bytes.begin, b.range.bytes.end, b.rule, b.message);
}

}  // namespace osplint
