// Checking and printing a linear colour for the renderer's input errors (scene layouts, textures).
#pragma once

#include <sstream>
#include <string>

#include <Eigen/Core>

namespace tavis::render::internal {

// Every component finite and in [0, 1].
inline bool IsUnitColour(const Eigen::Vector3f& rgb) {
  return rgb.allFinite() && (rgb.array() >= 0.0f).all() && (rgb.array() <= 1.0f).all();
}

// "(r, g, b)" for messages.
inline std::string DescribeColour(const Eigen::Vector3f& v) {
  std::ostringstream text;
  text << "(" << v.x() << ", " << v.y() << ", " << v.z() << ")";
  return text.str();
}

}  // namespace tavis::render::internal
