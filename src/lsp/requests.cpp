// Reading a request's params, and the requests answered from a document's model.
#include "lsp/requests.h"

#include <stdexcept>

namespace osplint::lsp {

namespace {

// The requests answered from a document's model, and what they answer for a
// document that is not open (or closed while the request waited).
struct DocumentRequest {
    std::string_view method;
    bool null_when_empty;  // null, else an empty array
};
constexpr DocumentRequest kDocumentRequests[] = {
    {"textDocument/hover", true},          {"textDocument/completion", false},
    {"textDocument/codeAction", false},    {"textDocument/documentSymbol", false},
    {"textDocument/definition", true},     {"textDocument/references", false},
    {"textDocument/documentHighlight", false}, {"textDocument/prepareRename", true},
    {"textDocument/rename", true},         {"textDocument/foldingRange", false},
    {"textDocument/semanticTokens/full", true}, {"textDocument/semanticTokens/range", true},
    {"textDocument/inlayHint", false},     {"textDocument/signatureHelp", true},
};

const DocumentRequest* document_request(std::string_view method) {
    for (const auto& r : kDocumentRequests)
        if (r.method == method) return &r;
    return nullptr;
}

}  // namespace

const json& field(const json& obj, const char* key) {
    if (!obj.is_object()) throw std::invalid_argument("params must be an object");
    auto it = obj.find(key);
    if (it == obj.end()) throw std::invalid_argument(std::string("missing '") + key + "'");
    return *it;
}

std::string uri_of(const json& params) {
    const json& td = field(params, "textDocument");
    const json& uri = field(td, "uri");
    if (!uri.is_string()) throw std::invalid_argument("textDocument.uri must be a string");
    return uri.get<std::string>();
}

json empty_result(std::string_view method) {
    const DocumentRequest* r = document_request(method);
    return r && r->null_when_empty ? json(nullptr) : json::array();
}

bool is_document_request(std::string_view method) { return document_request(method) != nullptr; }

}  // namespace osplint::lsp
