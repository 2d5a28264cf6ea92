// osplint as a library: check a program (a buffer or a file), get its findings.
//
// Self-contained: this header and osplint/diagnostic.h include nothing but
// the standard library; they need C++20 (the CMake targets ask for it; with
// pkg-config, compile with -std=c++20). Link `osplint::osplint` (CMake:
// find_package(osplint)), `pkg-config --libs osplint`, or -losplint. C and
// other languages: osplint/osplint_c.h.
//
//     #include <osplint/osplint.h>
//
//     // The configuration: the built-in defaults, or the nearest osplint.toml.
//     // find() returns nothing when there is none (that is no error); load()
//     // throws osplint::ConfigurationError when the file cannot be read or is
//     // invalid (the message names the file, line and key).
//     osplint::Configuration config;
//     if (auto toml = osplint::Configuration::find("posted")) config = osplint::Configuration::load(*toml);
//
//     osplint::FileResult r = osplint::check_text("PART.MIN", text, config);
//     for (const osplint::Diagnostic& d : r.diagnostics)
//         ... d.rule ("OSP104"), d.severity, d.message, d.range.start.line, d.fixes
//
// or, for a program of any size, with the findings handed over as they are made:
//
//     struct Printer : osplint::DiagnosticSink {
//         void diagnostic(osplint::Diagnostic&& d) override { ... }
//     };
//     Printer p;
//     osplint::check_file("POSTED.MIN", config, {}, p);
//
// Errors:
// - A configuration file that is missing, unreadable or invalid:
//   Configuration::load and Configuration::parse throw ConfigurationError.
//   Nothing else throws it; no check ever reads osplint.toml by itself.
// - A program file that cannot be read (missing, a directory, a read error):
//   FileResult::io_error, or the `io_error` of DiagnosticSink::end_file. Never
//   thrown; the findings made before a read error stop the file are kept.
// - Findings are data (FileResult::diagnostics), never exceptions.
// - std::bad_alloc may be thrown, as anywhere in C++.
//
// Thread safety: a Configuration may be shared by any number of threads; each
// check is independent (checks of different files may run at the same time).
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

// A configuration that cannot be used: a file that cannot be read, TOML that
// does not parse, an unknown key, a value of the wrong type or out of range.
// what(): "FILE:LINE: KEY: why".
class OSPLINT_API ConfigurationError : public std::runtime_error {
public:
    using std::runtime_error::runtime_error;
};

// Machine defaults, travel limits, macro registrations, shop macros and rule
// severities (osplint.toml). Cheap to copy (shared, immutable).
class OSPLINT_API Configuration {
public:
    // The built-in defaults: the shipped macro catalog, no travel limits, every
    // rule at its default severity.
    Configuration();
    // Reads `osplint.toml` (or any file of that schema). Throws
    // ConfigurationError when `path` does not exist, cannot be read or holds
    // an invalid configuration.
    static Configuration load(const std::string& path);
    // Parses configuration text; `origin` names it in error messages. Throws
    // ConfigurationError when the text is invalid.
    static Configuration parse(std::string_view toml, const std::string& origin);
    // The nearest osplint.toml in `dir` or one of its parents; nothing when
    // there is none (never throws for that).
    static std::optional<std::string> find(const std::string& dir);
    // The effective configuration as TOML.
    std::string dump() const;

    // The analysis's own form (for osplint's own entry points; Config is not
    // part of the public interface).
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

// Checks a program held in memory. `path` is not read: it names the program
// in the findings, and its extension tells a file of subprograms (.SSB, .SUB,
// .LIB, .MSB) from a main program. Findings are sorted by position and carry
// fingerprints. A text above the input size limit gives `io_error`.
OSPLINT_API FileResult check_text(const std::string& path, std::string_view text, const Configuration& config,
                      const CheckOptions& options = {});
// Checks a file, read as a stream (any size, bounded memory). A file that
// cannot be read gives a FileResult with `io_error` set.
OSPLINT_API FileResult check_file(const std::string& path, const Configuration& config, const CheckOptions& options = {});
// Checks a file and hands each finding to `sink` as it is made (memory does not
// grow with the number of findings). Exceptions thrown by the sink propagate.
OSPLINT_API void check_file(const std::string& path, const Configuration& config, const CheckOptions& options,
                DiagnosticSink& sink);

// The library's version ("0.1.0").
OSPLINT_API std::string_view version();

}  // namespace osplint
