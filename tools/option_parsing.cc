#include "tools/option_parsing.h"

#include <cstdio>
#include <stdexcept>


namespace tavis::tools {

std::pair<int, int> ParseImageSize(const std::string& text) {
  int width = 0;
  int height = 0;
  char trailing = 0;
  if (std::sscanf(text.c_str(), "%dx%d%c", &width, &height, &trailing) != 2 || width < 1 || height < 1) {
    throw std::invalid_argument("--image-size '" + text + "' must be WIDTHxHEIGHT with positive integers, e.g. 224x224");
  }
  return {width, height};
}

}  // namespace tavis::tools
