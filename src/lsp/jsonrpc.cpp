#include "lsp/jsonrpc.h"

namespace osplint::lsp {

namespace {

bool valid_id(const json& id) { return id.is_number_integer() || id.is_number_unsigned() || id.is_string(); }

Incoming invalid(std::string problem, int code = error::kInvalidRequest, json id = nullptr) {
    Incoming in;
    in.kind = Incoming::Invalid;
    in.problem = std::move(problem);
    in.error_code = code;
    in.id = std::move(id);
    return in;
}

}  // namespace

Incoming classify(std::string_view body) {
    json msg = json::parse(body.begin(), body.end(), nullptr, /*allow_exceptions=*/false);
    if (msg.is_discarded()) return invalid("the message is not valid JSON", error::kParseError);
    if (!msg.is_object()) return invalid("a message must be a JSON object (batches are not supported)");
    auto jsonrpc = msg.find("jsonrpc");
    if (jsonrpc == msg.end() || !jsonrpc->is_string() || *jsonrpc != "2.0")
        return invalid("\"jsonrpc\": \"2.0\" is missing", error::kInvalidRequest,
                       msg.contains("id") && valid_id(msg["id"]) ? msg["id"] : json(nullptr));
    auto method = msg.find("method");
    auto id = msg.find("id");
    const bool has_id = id != msg.end();
    if (has_id && !valid_id(*id) && !(id->is_null() && method == msg.end()))
        return invalid("the id must be a number or a string");

    Incoming in;
    if (method == msg.end()) {
        if (!has_id) return invalid("a message needs a method or an id");
        in.kind = Incoming::Response;
        in.id = *id;
        return in;
    }
    if (!method->is_string())
        return invalid("the method must be a string", error::kInvalidRequest, has_id ? *id : json(nullptr));
    in.method = method->get<std::string>();
    auto params = msg.find("params");
    if (params != msg.end()) {
        if (!params->is_object() && !params->is_array() && !params->is_null())
            return invalid("params must be an object or an array", error::kInvalidRequest,
                           has_id ? *id : json(nullptr));
        in.params = std::move(*params);
    }
    if (has_id) {
        in.kind = Incoming::Request;
        in.id = *id;
    } else {
        in.kind = Incoming::Notification;
    }
    return in;
}

json make_response(const json& id, json result) {
    return json{{"jsonrpc", "2.0"}, {"id", id}, {"result", std::move(result)}};
}

json make_error(const json& id, int code, std::string_view message) {
    return json{{"jsonrpc", "2.0"}, {"id", id}, {"error", {{"code", code}, {"message", std::string(message)}}}};
}

json make_notification(std::string_view method, json params) {
    return json{{"jsonrpc", "2.0"}, {"method", std::string(method)}, {"params", std::move(params)}};
}

json make_request(const json& id, std::string_view method, json params) {
    return json{{"jsonrpc", "2.0"}, {"id", id}, {"method", std::string(method)}, {"params", std::move(params)}};
}

bool MessageWriter::send(const json& message) {
    return send_text(message.dump(-1, ' ', false, json::error_handler_t::replace));
}

bool MessageWriter::send_text(std::string_view body) {
    std::lock_guard lock(m_);
    return sink_.write(frame(body));
}

}  // namespace osplint::lsp
