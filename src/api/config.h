// Configurations read against the built-in rules (the layer that knows them).
#pragma once

#include <filesystem>
#include <string>
#include <string_view>

#include "semantics/config.h"

namespace osplint {

// The built-in rules as a configuration names them.
const RuleIdentities& builtin_rule_identities();

// Reads and validates a configuration file. Throws ConfigError (file, line, key).
Config load_config(const std::filesystem::path& file);
// Parses configuration text (for tests and the language server).
Config parse_config(std::string_view text, const std::string& origin);
// The effective configuration as TOML (`osplint config`).
std::string dump_config(const Config& config);

}  // namespace osplint
