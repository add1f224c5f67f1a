// The benchmark's two suites (reference 3): TAVIS-Head (the information is in view only once the
// head moves) and TAVIS-Hands (the wrist cameras must find it).
#pragma once

#include <string>

namespace tavis::scenarios {

enum class Suite { kTavisHead, kTavisHands };
constexpr Suite kAllSuites[] = {Suite::kTavisHead, Suite::kTavisHands};

const char* ToString(Suite suite);  // "tavis-head", "tavis-hands"
const char* Title(Suite suite);     // "TAVIS-Head", "TAVIS-Hands", as the paper's tables name them
// Accepts "tavis-head" and "tavis-hands"; throws std::invalid_argument naming the value and the
// known suites.
Suite ParseSuite(const std::string& text);
// "tavis-head, tavis-hands", for --help texts and errors.
std::string KnownSuites();

}  // namespace tavis::scenarios
