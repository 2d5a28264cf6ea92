// Checks the part programs named on the command line with the osplint C++
// library, each with the nearest osplint.toml of its directory, and prints
// the findings as PATH:LINE:COLUMN: SEVERITY: MESSAGE [RULE].
// Exit code: 0 no findings, 1 findings, 2 a file or configuration error.
#include <osplint/osplint.h>

#include <filesystem>
#include <iostream>

int main(int argc, char** argv) {
    if (argc < 2) {
        std::cerr << "usage: check_programs FILE...\n";
        return 2;
    }
    int status = 0;
    for (int i = 1; i < argc; ++i) {
        const std::string path = argv[i];
        std::filesystem::path dir = std::filesystem::path(path).parent_path();
        try {
            osplint::Configuration config;  // the built-in defaults when there is no osplint.toml
            if (auto toml = osplint::Configuration::find(dir.empty() ? "." : dir.string()))
                config = osplint::Configuration::load(*toml);
            const osplint::FileResult result = osplint::check_file(path, config);
            if (!result.io_error.empty()) {
                std::cerr << path << ": " << result.io_error << "\n";
                status = 2;
                continue;
            }
            for (const osplint::Diagnostic& d : result.diagnostics) {
                std::cout << path << ":" << d.range.start.line << ":" << d.range.start.cp_col + 1 << ": "
                          << osplint::severity_name(d.severity) << ": " << d.message << " [" << d.rule << "]\n";
                if (status == 0) status = 1;
            }
        } catch (const osplint::ConfigurationError& e) {
            std::cerr << e.what() << "\n";
            status = 2;
        }
    }
    return status;
}
