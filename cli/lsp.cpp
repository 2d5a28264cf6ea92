// `osplint lsp`: the language server over stdin/stdout (LSP 3.17).
#include <unistd.h>

#include <csignal>
#include <cstdlib>
#include <iostream>
#include <string_view>

#include "lsp/server.h"

namespace osplint::cli {

int run_lsp() {
    // A client that goes away must not kill the server with SIGPIPE mid-write:
    // the write fails and the message loop ends at the end of the input.
    std::signal(SIGPIPE, SIG_IGN);
    lsp::FdInput in(STDIN_FILENO);
    lsp::FdOutput out(STDOUT_FILENO);
    lsp::ServerOptions options;
    // One write per message: the workers log at the same time.
    options.log = [](const std::string& message) { std::cerr << ("osplint lsp: " + message + "\n") << std::flush; };
    // OSPLINT_LSP_TIMING=1: log when each analysis starts and how long it took.
    if (const char* t = std::getenv("OSPLINT_LSP_TIMING"); t && *t && std::string_view(t) != "0")
        options.log_timing = true;
    lsp::Server server(in, out, options);
    return server.run();
}

}  // namespace osplint::cli
