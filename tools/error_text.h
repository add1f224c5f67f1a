// What `tavis` prints for an error: the library names a setting by its key ("videos must be at
// least 0", "resume with a larger max_attempts"), the command names the flag its user typed.
#pragma once

#include <exception>
#include <stdexcept>
#include <string>

#include "batch/output/setting_error.h"

namespace tavis::tools {

// The flag of a setting key: a cell setting's own (observation_keys -> --keys), else the key with
// dashes (max_attempts -> --max-attempts).
std::string FlagOfSetting(const std::string& key);

// The error's message, with the settings it names (batch::output::NamesSettings) named by their
// flags; what() for any other error.
std::string ErrorText(const std::exception& error);

// The error being handled, thrown again as an Error naming its settings by flag (as it was when
// it names none).
template <typename Error>
[[noreturn]] void RethrowNamingFlags(const Error& error) {
  if (dynamic_cast<const batch::output::NamesSettings*>(&error) == nullptr) throw;
  throw Error(ErrorText(error));
}

// Runs `call` of a command whose settings all came from its flags: an error naming settings is
// thrown again naming their flags, as the same standard type. (A sweep's cells take their
// settings from its spec, whose errors keep the keys.)
template <typename Call>
void RunNamingFlags(Call&& call) {
  try {
    call();
  } catch (const std::invalid_argument& error) {
    RethrowNamingFlags(error);
  } catch (const std::runtime_error& error) {
    RethrowNamingFlags(error);
  }
}

}  // namespace tavis::tools
