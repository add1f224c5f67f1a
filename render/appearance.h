// How a surface looks: a diffuse colour, an optional procedural label, or a flat emissive colour.
#pragma once

#include <cstdint>

#include <Eigen/Core>

namespace tavis::render {

// Procedural labels, evaluated in the shape's local frame (z up). "Side" means every face whose
// normal is not mostly vertical; "caps" the top and bottom faces.
enum class LabelPattern : uint8_t {
  kNone,
  kBand,        // a horizontal band around the middle 60 % of the height, on the sides
  kStripes,     // eight vertical stripes around a round shape, four across each box side
  kChecker,     // a 3-D checker whose cell is half the smallest half-extent
  kCaps,        // top and bottom faces in the label colour (a lid)
  kFrontPanel,  // a centred rectangular panel on each side face (on round shapes: facing local +x)
};

struct Appearance {
  // Linear diffuse reflectance in [0, 1] (as USD's diffuseColor); images are sRGB-encoded.
  Eigen::Vector3f rgb = Eigen::Vector3f::Constant(0.5f);
  LabelPattern label = LabelPattern::kNone;
  Eigen::Vector3f label_rgb = Eigen::Vector3f::Ones();
  // Emissive surfaces ignore the lights and shadows: the pixel is rgb (linear), sRGB-encoded.
  bool emissive = false;
};

}  // namespace tavis::render
