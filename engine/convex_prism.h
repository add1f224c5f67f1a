// A cylinder as a convex prism, in the arrays ODE's dCreateConvex reads (it keeps pointers to
// them, so the mesh must outlive its geoms). Debian's ODE has no libccd, and its built-in
// cylinder-box test asserts on parallel axes (an upright can on a table), so cylinders collide
// as prisms.
#pragma once

#include <vector>

namespace tavis::engine {

struct ConvexPrism {
  std::vector<double> planes;         // (faces x 4) outward normal, offset: n . p = d
  std::vector<double> points;         // (vertices x 3)
  std::vector<unsigned int> polygons; // per face: vertex count, then indices (counter-clockwise outside)
  unsigned int face_count = 0;
  unsigned int point_count = 0;
};

// A prism with `sides` faces around the local z axis, inscribed radius close to `radius`
// (vertices on the circle), centred at the origin.
ConvexPrism MakeCylinderPrism(double radius, double height, int sides);

}  // namespace tavis::engine
