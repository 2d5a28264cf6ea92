// Errors that stop a run before any file is checked (exit code 2): a bad
// configuration file or catalog entry. They name the file, line and key.
#pragma once

#include <cstdint>
#include <stdexcept>
#include <string>

namespace osplint {

class ConfigError : public std::runtime_error {
public:
    ConfigError(std::string file, uint32_t line, std::string key, const std::string& message)
        : std::runtime_error(format(file, line, key, message)),
          file_(std::move(file)), line_(line), key_(std::move(key)) {}
    const std::string& file() const { return file_; }
    uint32_t line() const { return line_; }
    const std::string& key() const { return key_; }

private:
    static std::string format(const std::string& file, uint32_t line, const std::string& key,
                              const std::string& message) {
        // A key or a value can be as long as the file: shown abbreviated.
        auto cut = [](const std::string& t, size_t max) {
            return t.size() <= max ? t : t.substr(0, max) + "... (" + std::to_string(t.size()) + " bytes)";
        };
        std::string s = cut(file, 1000);
        if (line) s += ":" + std::to_string(line);
        s += ": ";
        if (!key.empty()) s += "'" + cut(key, 80) + "': ";
        return s + cut(message, 1000);
    }
    std::string file_;
    uint32_t line_;
    std::string key_;
};

}  // namespace osplint
