// Language server, layer 2: JSON-RPC 2.0 messages.
//
// A body is classified as a request (id + method), a notification (method, no
// id), a response (id, no method: the client answering one of our requests)
// or invalid. Writing goes through one mutex, so the message loop and the
// analysis worker can both send.
#pragma once

#include <mutex>
#include <nlohmann/json.hpp>
#include <string>
#include <string_view>

#include "lsp/transport.h"

namespace osplint::lsp {

using json = nlohmann::json;

namespace error {
inline constexpr int kParseError = -32700;
inline constexpr int kInvalidRequest = -32600;
inline constexpr int kMethodNotFound = -32601;
inline constexpr int kInvalidParams = -32602;
inline constexpr int kInternalError = -32603;
inline constexpr int kServerNotInitialized = -32002;
inline constexpr int kRequestCancelled = -32800;
inline constexpr int kContentModified = -32801;
}  // namespace error

struct Incoming {
    enum Kind { Request, Notification, Response, Invalid } kind = Invalid;
    json id;  // Request/Response: number or string; Invalid: the id if one could be read, else null
    std::string method;
    json params;          // object, array or null
    std::string problem;  // Invalid: why; the answer is -32700 (bad JSON) or -32600
    int error_code = error::kInvalidRequest;
};

// Parses and classifies one message body. Never throws.
Incoming classify(std::string_view body);

json make_response(const json& id, json result);
json make_error(const json& id, int code, std::string_view message);
json make_notification(std::string_view method, json params);
json make_request(const json& id, std::string_view method, json params);

// Serialises (invalid UTF-8 in strings becomes U+FFFD) and frames messages.
class MessageWriter {
public:
    explicit MessageWriter(OutputStream& sink) : sink_(sink) {}
    bool send(const json& message);
    bool send_text(std::string_view body);  // a message already serialised

private:
    std::mutex m_;
    OutputStream& sink_;
};

}  // namespace osplint::lsp
