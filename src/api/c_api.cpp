// The C interface (include/osplint/osplint_c.h) over the public C++ API. No
// exception leaves a function of this file.
#include <cstdlib>
#include <cstring>
#include <new>
#include <string>
#include <vector>

#include "osplint/osplint.h"
#include "osplint/osplint_c.h"
#include "rules/registry.h"

struct osplint_config {
    osplint::Configuration config;
};

struct osplint_options {
    osplint::CheckOptions options;
};

struct osplint_result {
    osplint::FileResult file;
    std::vector<osplint_diagnostic> views;  // one per file.diagnostics, pointing into it
};

namespace {

char* copy_string(const std::string& s) {
    char* p = static_cast<char*>(std::malloc(s.size() + 1));
    if (!p) return nullptr;
    std::memcpy(p, s.data(), s.size());
    p[s.size()] = '\0';
    return p;
}

osplint_status fail(osplint_status status, const std::string& message, char** error) {
    if (error) *error = copy_string(message);
    return status;
}

osplint_status succeed(char** error) {
    if (error) *error = nullptr;
    return OSPLINT_STATUS_OK;
}

// Runs `body` (which returns a status), turning any exception into one.
template <class F>
osplint_status guarded(char** error, F&& body) {
    if (error) *error = nullptr;
    try {
        return body();
    } catch (const osplint::ConfigurationError& e) {
        return fail(OSPLINT_STATUS_CONFIG_ERROR, e.what(), error);
    } catch (const std::bad_alloc&) {
        return fail(OSPLINT_STATUS_INTERNAL_ERROR, "out of memory", error);
    } catch (const std::exception& e) {
        return fail(OSPLINT_STATUS_INTERNAL_ERROR, e.what(), error);
    } catch (...) {
        return fail(OSPLINT_STATUS_INTERNAL_ERROR, "unknown error", error);
    }
}

osplint_status missing(const char* what, char** error) {
    return fail(OSPLINT_STATUS_INVALID_ARGUMENT, std::string(what) + " is NULL", error);
}

const osplint::CheckOptions& options_of(const osplint_options* options) {
    static const osplint::CheckOptions defaults;
    return options ? options->options : defaults;
}

// Wraps a finished check; an unreadable file is an error, not a result.
osplint_status deliver(osplint::FileResult&& file, osplint_result** out, char** error) {
    if (!file.io_error.empty())
        return fail(OSPLINT_STATUS_IO_ERROR, file.path + ": " + file.io_error, error);
    auto* r = new osplint_result{std::move(file), {}};
    r->views.reserve(r->file.diagnostics.size());
    for (const osplint::Diagnostic& d : r->file.diagnostics) {
        osplint_diagnostic v{};
        v.rule = d.rule.c_str();
        v.name = d.name.c_str();
        v.severity = static_cast<osplint_severity>(d.severity);
        v.message = d.message.c_str();
        v.line = d.range.start.line;
        v.column = d.range.start.cp_col + 1;
        v.end_line = d.range.end.line;
        v.end_column = d.range.end.cp_col + 1;
        v.byte_begin = d.range.bytes.begin;
        v.byte_end = d.range.bytes.end;
        v.line_text = d.line_text.c_str();
        v.fix_title = d.fixes.empty() ? nullptr : d.fixes.front().title.c_str();
        v.note_count = d.notes.size();
        v.fix_safe = !d.fixes.empty() && d.fixes.front().safe ? 1 : 0;
        r->views.push_back(v);
    }
    *out = r;
    return succeed(error);
}

}  // namespace

extern "C" {

const char* osplint_version(void) { return OSPLINT_VERSION; }

const char* osplint_severity_name(osplint_severity severity) {
    switch (severity) {
        case OSPLINT_SEVERITY_INFO: return "info";
        case OSPLINT_SEVERITY_WARNING: return "warning";
        case OSPLINT_SEVERITY_ERROR: return "error";
    }
    return "";
}

void osplint_string_free(char* s) { std::free(s); }

osplint_status osplint_config_new(osplint_config** out, char** error) {
    if (!out) return missing("out", error);
    *out = nullptr;
    return guarded(error, [&] {
        *out = new osplint_config{osplint::Configuration()};
        return OSPLINT_STATUS_OK;
    });
}

osplint_status osplint_config_load(const char* path, osplint_config** out, char** error) {
    if (!out) return missing("out", error);
    *out = nullptr;
    if (!path) return missing("path", error);
    return guarded(error, [&] {
        *out = new osplint_config{osplint::Configuration::load(path)};
        return OSPLINT_STATUS_OK;
    });
}

osplint_status osplint_config_parse(const char* toml, size_t length, const char* origin, osplint_config** out,
                                    char** error) {
    if (!out) return missing("out", error);
    *out = nullptr;
    if (!toml && length > 0) return missing("toml", error);
    return guarded(error, [&] {
        std::string_view text(toml ? toml : "", toml ? length : 0);
        *out = new osplint_config{osplint::Configuration::parse(text, origin ? origin : "<text>")};
        return OSPLINT_STATUS_OK;
    });
}

osplint_status osplint_config_find(const char* dir, char** path, char** error) {
    if (!path) return missing("path", error);
    *path = nullptr;
    if (!dir) return missing("dir", error);
    return guarded(error, [&] {
        if (auto found = osplint::Configuration::find(dir)) {
            *path = copy_string(*found);
            if (!*path) throw std::bad_alloc();
        }
        return OSPLINT_STATUS_OK;
    });
}

osplint_status osplint_config_dump(const osplint_config* config, char** toml, char** error) {
    if (!toml) return missing("toml", error);
    *toml = nullptr;
    if (!config) return missing("config", error);
    return guarded(error, [&] {
        *toml = copy_string(config->config.dump());
        if (!*toml) throw std::bad_alloc();
        return OSPLINT_STATUS_OK;
    });
}

void osplint_config_free(osplint_config* config) { delete config; }

osplint_status osplint_options_new(osplint_options** out, char** error) {
    if (!out) return missing("out", error);
    *out = nullptr;
    return guarded(error, [&] {
        *out = new osplint_options{};
        return OSPLINT_STATUS_OK;
    });
}

osplint_status osplint_options_add_known_program(osplint_options* options, const char* name, char** error) {
    if (!options) return missing("options", error);
    if (!name) return missing("name", error);
    return guarded(error, [&] {
        options->options.known_programs.emplace_back(name);
        return OSPLINT_STATUS_OK;
    });
}

osplint_status osplint_options_select_rule(osplint_options* options, const char* rule, char** error) {
    if (!options) return missing("options", error);
    if (!rule) return missing("rule", error);
    return guarded(error, [&] {
        const osplint::RuleMeta* meta = osplint::find_rule(rule);
        if (!meta) {
            for (const auto& m : osplint::all_rules())
                if (m.name == rule) meta = &m;
        }
        if (!meta) return fail(OSPLINT_STATUS_INVALID_ARGUMENT, std::string("unknown rule: ") + rule, error);
        options->options.only_rules.emplace_back(meta->id);
        return OSPLINT_STATUS_OK;
    });
}

void osplint_options_free(osplint_options* options) { delete options; }

osplint_status osplint_check_text(const char* path, const char* text, size_t length, const osplint_config* config,
                                  const osplint_options* options, osplint_result** out, char** error) {
    if (!out) return missing("out", error);
    *out = nullptr;
    if (!path) return missing("path", error);
    if (!text && length > 0) return missing("text", error);
    if (!config) return missing("config", error);
    return guarded(error, [&] {
        std::string_view program(text ? text : "", text ? length : 0);
        return deliver(osplint::check_text(path, program, config->config, options_of(options)), out, error);
    });
}

osplint_status osplint_check_file(const char* path, const osplint_config* config, const osplint_options* options,
                                  osplint_result** out, char** error) {
    if (!out) return missing("out", error);
    *out = nullptr;
    if (!path) return missing("path", error);
    if (!config) return missing("config", error);
    return guarded(error, [&] {
        return deliver(osplint::check_file(path, config->config, options_of(options)), out, error);
    });
}

const char* osplint_result_path(const osplint_result* result) { return result ? result->file.path.c_str() : nullptr; }

size_t osplint_result_count(const osplint_result* result) { return result ? result->views.size() : 0; }

const osplint_diagnostic* osplint_result_diagnostic(const osplint_result* result, size_t index) {
    if (!result || index >= result->views.size()) return nullptr;
    return &result->views[index];
}

const char* osplint_diagnostic_note(const osplint_result* result, size_t diagnostic, size_t index) {
    if (!result || diagnostic >= result->file.diagnostics.size()) return nullptr;
    const auto& notes = result->file.diagnostics[diagnostic].notes;
    return index < notes.size() ? notes[index].message.c_str() : nullptr;
}

size_t osplint_result_count_severity(const osplint_result* result, osplint_severity severity) {
    if (!result) return 0;
    size_t n = 0;
    for (const auto& v : result->views) n += v.severity == severity;
    return n;
}

void osplint_result_free(osplint_result* result) { delete result; }

}  // extern "C"
