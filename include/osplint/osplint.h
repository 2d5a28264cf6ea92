// osplint as a library: check a program (a buffer or a file), get its findings.
//
// Self-contained: this header and osplint/diagnostic.h include nothing but
// the standard library. A CAM post-processor needs only this:
//
//     osplint::Configuration config;                   // built-in defaults, or:
//     auto dir = osplint::Configuration::find("posted");  // nearest osplint.toml
//     if (dir) config = osplint::Configuration::load(*dir);  // throws osplint::ConfigurationError
//     osplint::FileResult r = osplint::check_text("PART.MIN", text, config);
//     for (const auto& d : r.diagnostics) ... d.rule, d.severity, d.message, d.range.start.line
//
// or, for a program of any size with findings written as they are made:
//
//     struct Printer : osplint::DiagnosticSink { void diagnostic(osplint::Diagnostic&& d) override {...} };
//     Printer p;
//     osplint::check_file("POSTED.MIN", config, {}, p);
//
// Errors: a configuration that cannot be read or is invalid throws
// ConfigurationError (file, line, key in the message); a file that cannot be
// read is reported in FileResult::io_error (or DiagnosticSink::end_file),
// never thrown. Findings are never thrown.
#pragma once

#include <memory>
#include <optional>
#include <stdexcept>
#include <string>
#include <string_view>
#include <vector>

#include "osplint/diagnostic.h"

namespace osplint {

struct Config;  // the analysis's own form of a configuration

// A configuration that cannot be used.
class ConfigurationError : public std::runtime_error {
public:
    using std::runtime_error::runtime_error;
};

// Machine defaults, travel limits, macro registrations, shop macros and rule
// severities (osplint.toml). Cheap to copy (shared, immutable).
class Configuration {
public:
    // The built-in defaults: the shipped macro catalog, no travel limits, every
    // rule at its default severity.
    Configuration();
    // Reads `osplint.toml` (or any file of that schema).
    static Configuration load(const std::string& path);
    // Parses configuration text; `origin` names it in error messages.
    static Configuration parse(std::string_view toml, const std::string& origin);
    // The nearest osplint.toml in `dir` or one of its parents.
    static std::optional<std::string> find(const std::string& dir);
    // The effective configuration as TOML.
    std::string dump() const;

    const Config& get() const { return *impl_; }
    explicit Configuration(std::shared_ptr<const Config> impl) : impl_(std::move(impl)) {}

private:
    std::shared_ptr<const Config> impl_;
};

struct CheckOptions {
    // Program names defined outside the checked text (other files of the same
    // job, the control's library): CALL targets that are not unknown.
    std::vector<std::string> known_programs;
    // Only these rules (IDs); empty: every rule the configuration enables.
    std::vector<std::string> only_rules;
};

// Checks a program held in memory.
FileResult check_text(const std::string& path, std::string_view text, const Configuration& config,
                      const CheckOptions& options = {});
// Checks a file, read as a stream (any size, bounded memory).
FileResult check_file(const std::string& path, const Configuration& config, const CheckOptions& options = {});
// Checks a file and hands each finding to `sink` as it is made (memory does not
// grow with the number of findings).
void check_file(const std::string& path, const Configuration& config, const CheckOptions& options,
                DiagnosticSink& sink);

// The library's version ("0.1.0").
std::string_view version();

}  // namespace osplint
