#include "core/error.hpp"

#include <fmt/format.h>

namespace fdem {

namespace {
std::string input_message(const std::string& file, const std::string& key, const std::string& value,
                          const std::string& reason, int line) {
  const std::string where = line > 0 ? fmt::format("{}:{}", file, line) : file;
  return fmt::format("{}: key '{}' = '{}': {}", where, key, value, reason);
}
}  // namespace

InputError::InputError(std::string file, std::string key, std::string value, std::string reason, int line)
    : std::runtime_error(input_message(file, key, value, reason, line)),
      file_(std::move(file)),
      key_(std::move(key)),
      value_(std::move(value)),
      line_(line) {}

}  // namespace fdem
