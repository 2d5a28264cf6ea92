#include "api/config.h"

#include "rules/registry.h"

namespace osplint {

const RuleIdentities& builtin_rule_identities() {
    static const RuleIdentities ids = builtin_rules().identities();
    return ids;
}

Config load_config(const std::filesystem::path& file) { return read_config_file(file, builtin_rule_identities()); }

Config parse_config(std::string_view text, const std::string& origin) {
    return read_config_text(text, origin, builtin_rule_identities());
}

std::string dump_config(const Config& config) { return render_config(config, builtin_rule_identities()); }

}  // namespace osplint
