// Language server: reading a request's params, and the requests answered from
// a document's model (what each answers for a document that is not open).
// Shared by the message loop (server.cpp) and the workers (worker.cpp).
#pragma once

#include <string>
#include <string_view>

#include "lsp/jsonrpc.h"

namespace osplint::lsp {

// The member `key` of `obj`; throws std::invalid_argument when `obj` is not
// an object or has no such member (answered as InvalidParams).
const json& field(const json& obj, const char* key);
// params.textDocument.uri.
std::string uri_of(const json& params);

// Whether `method` is a request about one document, answered by a worker.
bool is_document_request(std::string_view method);
// The answer to such a request when the document is not open: null or [].
json empty_result(std::string_view method);

}  // namespace osplint::lsp
