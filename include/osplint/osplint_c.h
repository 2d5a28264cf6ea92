/* osplint from C and from any language that can call C (Python ctypes, ...).
 *
 * Self-contained (the C standard library only). Link -losplint
 * (`pkg-config --libs osplint`, or the CMake target osplint::osplint).
 *
 * Conventions:
 * - Every string is UTF-8 and NUL-terminated, unless a length is given with it.
 * - Objects are opaque handles made by osplint_*_new/load/parse/check and
 *   released by the matching osplint_*_free; every free function accepts NULL.
 * - Functions that can fail return an osplint_status. On failure they set
 *   *error (when `error` is not NULL) to a message the caller releases with
 *   osplint_string_free, and leave the out handle NULL. On success *error is
 *   set to NULL.
 * - Strings returned by accessors belong to the handle they come from and
 *   stay valid until it is freed.
 * - No function throws or aborts on bad input; a NULL where a handle or a
 *   string is required gives OSPLINT_STATUS_INVALID_ARGUMENT.
 * - A configuration may be shared by threads; a result belongs to one.
 *
 *     osplint_config* config = NULL;
 *     char* error = NULL;
 *     if (osplint_config_new(&config, &error) != OSPLINT_STATUS_OK) { ... }
 *     osplint_result* result = NULL;
 *     if (osplint_check_file("PART.MIN", config, NULL, &result, &error) != OSPLINT_STATUS_OK) {
 *         fprintf(stderr, "%s\n", error);
 *         osplint_string_free(error);
 *     }
 *     for (size_t i = 0; i < osplint_result_count(result); ++i) {
 *         const osplint_diagnostic* d = osplint_result_diagnostic(result, i);
 *         printf("%u:%u: %s[%s]: %s\n", d->line, d->column, osplint_severity_name(d->severity), d->rule, d->message);
 *     }
 *     osplint_result_free(result);
 *     osplint_config_free(config);
 */
#ifndef OSPLINT_OSPLINT_C_H
#define OSPLINT_OSPLINT_C_H

#include <stddef.h>

#ifndef OSPLINT_API
#if defined(__GNUC__) || defined(__clang__)
#define OSPLINT_API __attribute__((visibility("default")))
#else
#define OSPLINT_API
#endif
#endif

#ifdef __cplusplus
extern "C" {
#endif

typedef enum osplint_status {
    OSPLINT_STATUS_OK = 0,
    /* A NULL handle or string where one is required, or an unknown rule ID. */
    OSPLINT_STATUS_INVALID_ARGUMENT = 1,
    /* A configuration that is missing, unreadable or invalid (file, line and
     * key in the message). */
    OSPLINT_STATUS_CONFIG_ERROR = 2,
    /* A program file that cannot be read: missing, a directory, a read error,
     * too large. */
    OSPLINT_STATUS_IO_ERROR = 3,
    /* Out of memory, or any other failure inside osplint. */
    OSPLINT_STATUS_INTERNAL_ERROR = 4
} osplint_status;

typedef enum osplint_severity {
    OSPLINT_SEVERITY_INFO = 0,
    OSPLINT_SEVERITY_WARNING = 1,
    OSPLINT_SEVERITY_ERROR = 2
} osplint_severity;

/* One finding. Lines are 1-based; columns are 1-based and count Unicode code
 * points; `end_*` is the position just after the range. `byte_begin` and
 * `byte_end` are offsets into the checked text ([begin, end)). `fix_title` is
 * the title of the first fix (NULL when the finding has none). Fields may be
 * added at the end in later versions; the struct is only ever read through the
 * pointer osplint_result_diagnostic returns. */
typedef struct osplint_diagnostic {
    const char* rule;      /* "OSP104" */
    const char* name;      /* "m52-on-call-line" */
    osplint_severity severity;
    const char* message;
    unsigned line;
    unsigned column;
    unsigned end_line;
    unsigned end_column;
    size_t byte_begin;
    size_t byte_end;
    const char* line_text; /* the text of the line the range starts on */
    const char* fix_title;
    size_t note_count;     /* notes: osplint_diagnostic_note */
    int fix_safe;          /* 1 when the first fix is safe (`osplint check --fix` applies it), else 0 */
} osplint_diagnostic;

typedef struct osplint_config osplint_config;
typedef struct osplint_options osplint_options;
typedef struct osplint_result osplint_result;

/* The library's version ("0.1.0"). */
OSPLINT_API const char* osplint_version(void);
/* "info", "warning", "error"; "" for a value out of range. */
OSPLINT_API const char* osplint_severity_name(osplint_severity severity);
/* Releases a string returned by osplint (messages, paths, dumps). */
OSPLINT_API void osplint_string_free(char* s);

/* Configurations (osplint.toml). */

/* The built-in defaults. */
OSPLINT_API osplint_status osplint_config_new(osplint_config** out, char** error);
/* Reads a configuration file: OSPLINT_STATUS_CONFIG_ERROR when it is missing,
 * unreadable or invalid. */
OSPLINT_API osplint_status osplint_config_load(const char* path, osplint_config** out, char** error);
/* Parses configuration text of `length` bytes; `origin` names it in messages
 * (NULL: "<text>"). */
OSPLINT_API osplint_status osplint_config_parse(const char* toml, size_t length, const char* origin,
                                                osplint_config** out, char** error);
/* The nearest osplint.toml in `dir` or a parent: *path is set to it (release
 * with osplint_string_free), or to NULL when there is none (still
 * OSPLINT_STATUS_OK). */
OSPLINT_API osplint_status osplint_config_find(const char* dir, char** path, char** error);
/* The effective configuration as TOML (release with osplint_string_free). */
OSPLINT_API osplint_status osplint_config_dump(const osplint_config* config, char** toml, char** error);
OSPLINT_API void osplint_config_free(osplint_config* config);

/* Options of a check; NULL wherever options are taken means the defaults. */

OSPLINT_API osplint_status osplint_options_new(osplint_options** out, char** error);
/* A program name defined outside the checked text (another file of the job,
 * the control's library): a CALL of it is not reported as unknown. */
OSPLINT_API osplint_status osplint_options_add_known_program(osplint_options* options, const char* name,
                                                             char** error);
/* Checks only the rules selected (IDs such as "OSP104"); none selected: every
 * rule the configuration enables. An unknown ID gives
 * OSPLINT_STATUS_INVALID_ARGUMENT. */
OSPLINT_API osplint_status osplint_options_select_rule(osplint_options* options, const char* rule, char** error);
OSPLINT_API void osplint_options_free(osplint_options* options);

/* Checks. */

/* Checks `length` bytes of program text. `path` is not read: it names the
 * program, and its extension tells a file of subprograms (.SSB, .SUB, .LIB,
 * .MSB) from a main program. */
OSPLINT_API osplint_status osplint_check_text(const char* path, const char* text, size_t length,
                                              const osplint_config* config, const osplint_options* options,
                                              osplint_result** out, char** error);
/* Checks a file on disk. A file that cannot be read gives
 * OSPLINT_STATUS_IO_ERROR and no result. */
OSPLINT_API osplint_status osplint_check_file(const char* path, const osplint_config* config,
                                              const osplint_options* options, osplint_result** out,
                                              char** error);

/* The findings of a check, sorted by position. */
OSPLINT_API const char* osplint_result_path(const osplint_result* result);
OSPLINT_API size_t osplint_result_count(const osplint_result* result);
/* The `index`th finding; NULL when `index` is out of range. */
OSPLINT_API const osplint_diagnostic* osplint_result_diagnostic(const osplint_result* result, size_t index);
/* The message of a finding's `index`th note; NULL when out of range. */
OSPLINT_API const char* osplint_diagnostic_note(const osplint_result* result, size_t diagnostic, size_t index);
/* How many findings of each severity ([info, warning, error] order). */
OSPLINT_API size_t osplint_result_count_severity(const osplint_result* result, osplint_severity severity);
OSPLINT_API void osplint_result_free(osplint_result* result);

#ifdef __cplusplus
}
#endif

#endif /* OSPLINT_OSPLINT_C_H */
