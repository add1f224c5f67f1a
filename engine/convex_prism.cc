#include "engine/convex_prism.h"

#include <cmath>

namespace tavis::engine {

ConvexPrism MakeCylinderPrism(double radius, double height, int sides) {
  ConvexPrism prism;
  const double half = 0.5 * height;
  for (int ring = 0; ring < 2; ++ring) {
    for (int i = 0; i < sides; ++i) {
      const double angle = 2.0 * M_PI * i / sides;
      prism.points.insert(prism.points.end(), {radius * std::cos(angle), radius * std::sin(angle), ring == 0 ? -half : half});
    }
  }
  const double side_offset = radius * std::cos(M_PI / sides);  // distance of a side face from the axis
  for (int i = 0; i < sides; ++i) {
    const double angle = 2.0 * M_PI * (i + 0.5) / sides;
    prism.planes.insert(prism.planes.end(), {std::cos(angle), std::sin(angle), 0.0, side_offset});
    const unsigned int a = i;
    const unsigned int b = (i + 1) % sides;
    prism.polygons.insert(prism.polygons.end(), {4u, a, b, b + sides, a + sides});
  }
  prism.planes.insert(prism.planes.end(), {0.0, 0.0, 1.0, half});
  prism.polygons.push_back(static_cast<unsigned int>(sides));
  for (int i = 0; i < sides; ++i) prism.polygons.push_back(static_cast<unsigned int>(sides + i));
  prism.planes.insert(prism.planes.end(), {0.0, 0.0, -1.0, half});
  prism.polygons.push_back(static_cast<unsigned int>(sides));
  for (int i = sides - 1; i >= 0; --i) prism.polygons.push_back(static_cast<unsigned int>(i));
  prism.face_count = static_cast<unsigned int>(sides + 2);
  prism.point_count = static_cast<unsigned int>(2 * sides);
  return prism;
}

}  // namespace tavis::engine
