#include "scenarios/suite.h"

#include <stdexcept>

namespace tavis::scenarios {

const char* ToString(Suite suite) { return suite == Suite::kTavisHead ? "tavis-head" : "tavis-hands"; }

const char* Title(Suite suite) { return suite == Suite::kTavisHead ? "TAVIS-Head" : "TAVIS-Hands"; }

std::string KnownSuites() {
  std::string known;
  for (const Suite suite : kAllSuites) known += (known.empty() ? "" : ", ") + std::string(ToString(suite));
  return known;
}

Suite ParseSuite(const std::string& text) {
  for (const Suite suite : kAllSuites) {
    if (text == ToString(suite)) return suite;
  }
  throw std::invalid_argument("unknown suite '" + text + "' (known: " + KnownSuites() + ")");
}

}  // namespace tavis::scenarios
