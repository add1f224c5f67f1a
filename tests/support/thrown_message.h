// What an error says: the message of the exception a call throws, for tests that check that an
// error names the bad value (file, key, value).
#pragma once

#include <string>

namespace tavis::testing {

// The what() of the `Error` that `call` throws; `none` when it throws nothing. Another exception
// type passes through, failing the test that expected this one.
template <typename Error, typename Call>
std::string ThrownMessage(Call&& call, const std::string& none = "") {
  try {
    call();
  } catch (const Error& error) {
    return error.what();
  }
  return none;
}

}  // namespace tavis::testing
