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
        std::string s = file;
        if (line) s += ":" + std::to_string(line);
        s += ": ";
        if (!key.empty()) s += "'" + key + "': ";
        return s + message;
    }
    std::string file_;
    uint32_t line_;
    std::string key_;
};

}  // namespace osplint
