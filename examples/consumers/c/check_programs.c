/* Checks the part programs named on the command line with the osplint C
 * library, each with the nearest osplint.toml of its directory, and prints
 * the findings as PATH:LINE:COLUMN: SEVERITY: MESSAGE [RULE].
 * Exit code: 0 no findings, 1 findings, 2 a file or configuration error.
 *
 *   cc $(pkg-config --cflags osplint) check_programs.c $(pkg-config --libs osplint) -o check_programs
 */
#include <osplint/osplint_c.h>

#include <stdio.h>
#include <stdlib.h>
#include <string.h>

/* The directory part of `path` ("." when it has none), in `dir`. */
static void directory_of(const char* path, char* dir, size_t size) {
    const char* slash = strrchr(path, '/');
    size_t n = slash ? (size_t)(slash - path) : 0;
    if (!slash) {
        snprintf(dir, size, ".");
    } else if (n == 0) {
        snprintf(dir, size, "/");
    } else {
        snprintf(dir, size, "%.*s", (int)n, path);
    }
}

/* Reports `error` (and releases it); returns 2. */
static int report(char* error) {
    fprintf(stderr, "%s\n", error ? error : "error");
    osplint_string_free(error);
    return 2;
}

int main(int argc, char** argv) {
    if (argc < 2) {
        fprintf(stderr, "usage: check_programs FILE...\n");
        return 2;
    }
    int status = 0;
    for (int i = 1; i < argc; ++i) {
        char dir[4096];
        char* toml = NULL;
        char* error = NULL;
        osplint_config* config = NULL;
        osplint_result* result = NULL;
        directory_of(argv[i], dir, sizeof dir);
        if (osplint_config_find(dir, &toml, &error) != OSPLINT_STATUS_OK) {
            status = report(error);
            continue;
        }
        osplint_status s = toml ? osplint_config_load(toml, &config, &error) : osplint_config_new(&config, &error);
        osplint_string_free(toml);
        if (s != OSPLINT_STATUS_OK) {
            status = report(error);
            continue;
        }
        if (osplint_check_file(argv[i], config, NULL, &result, &error) != OSPLINT_STATUS_OK) {
            status = report(error);
            osplint_config_free(config);
            continue;
        }
        for (size_t k = 0; k < osplint_result_count(result); ++k) {
            const osplint_diagnostic* d = osplint_result_diagnostic(result, k);
            printf("%s:%u:%u: %s: %s [%s]\n", argv[i], d->line, d->column, osplint_severity_name(d->severity),
                   d->message, d->rule);
            if (status == 0) status = 1;
        }
        osplint_result_free(result);
        osplint_config_free(config);
    }
    return status;
}
