#pragma once
// The command line's exit codes for the study and sweep drivers (fdem itself
// maps them in solver/app/main.cpp): 0 done, 2 bad input (InputError, before
// any step), 3 anything else that stopped the run.
#include <cstdio>
#include <exception>
#include <string>

#include "core/error.hpp"

namespace fdem {

/// Runs `body` (returning the exit code when it ends normally) and turns
/// what it throws into 2 or 3, with "<program>: <what>" on stderr.
template <class Body>
int run_with_exit_codes(const std::string& program, Body&& body) {
  try {
    return body();
  } catch (const InputError& e) {
    std::fprintf(stderr, "%s: %s\n", program.c_str(), e.what());
    return 2;
  } catch (const std::exception& e) {
    std::fprintf(stderr, "%s: %s\n", program.c_str(), e.what());
    return 3;
  }
}

}  // namespace fdem
