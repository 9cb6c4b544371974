#pragma once
// Errors are exceptions carrying what a user needs to fix them; they are caught
// once, at the command-line boundary (solver/app), which maps them to exit codes.
#include <stdexcept>
#include <string>

namespace fdem {

/// Bad input: names the file, the key (with line when known) and the value.
/// The command line exits with code 2 on it, before any time step is taken.
class InputError : public std::runtime_error {
 public:
  InputError(std::string file, std::string key, std::string value, std::string reason, int line = 0);
  const std::string& file() const { return file_; }
  const std::string& key() const { return key_; }
  const std::string& value() const { return value_; }
  int line() const { return line_; }

 private:
  std::string file_, key_, value_;
  int line_;
};

/// A run that cannot go on (unstable step, failed solve, blow-up): exit code 3.
class SolverError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

}  // namespace fdem
