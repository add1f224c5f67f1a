#include "engine/object_catalog.h"

#include <stdexcept>

namespace tavis::engine {
namespace {

ObjectSpec ScaledCylinder(const std::string& name, double diameter_mm, double height_mm, double real_mass_kg) {
  const double radius = 0.5 * diameter_mm * 1e-3 * kYcbScale;
  const double height = height_mm * 1e-3 * kYcbScale;
  return {name,
          {ShapeKind::kCylinder, Vec3(radius, radius, height)},
          real_mass_kg * kYcbScale * kYcbScale * kYcbScale,
          Material::kObject,
          name};
}

ObjectSpec ScaledBox(const std::string& name, Vec3 size_mm, double real_mass_kg) {
  return {name,
          {ShapeKind::kBox, size_mm * 1e-3 * kYcbScale},
          real_mass_kg * kYcbScale * kYcbScale * kYcbScale,
          Material::kObject,
          name};
}

}  // namespace

const std::vector<std::string>& TavisHeadObjectNames() {
  static const std::vector<std::string> names = {"soup_can", "meat_can", "tuna_fish_can", "gelatin_box", "pudding_box"};
  return names;
}

const std::vector<std::string>& CatalogObjectNames() {
  static const std::vector<std::string> names = [] {
    std::vector<std::string> all = TavisHeadObjectNames();
    all.push_back("red_cube");
    return all;
  }();
  return names;
}

// Sizes: reference 2.3 nominal YCB dimensions (the boxes stand on their largest-footprint
// upright face: x, y horizontal, z up). Masses: published YCB object masses.
ObjectSpec MakeCatalogObject(const std::string& name) {
  if (name == "soup_can") return ScaledCylinder(name, 66.0, 101.0, 0.349);
  if (name == "meat_can") return ScaledBox(name, Vec3(50.0, 97.0, 82.0), 0.370);
  if (name == "tuna_fish_can") return ScaledCylinder(name, 85.0, 33.0, 0.171);
  if (name == "gelatin_box") return ScaledBox(name, Vec3(28.0, 85.0, 73.0), 0.097);
  if (name == "pudding_box") return ScaledBox(name, Vec3(35.0, 110.0, 89.0), 0.187);
  if (name == "red_cube") {
    const double edge = 0.055;
    // No mass is set in the reference: PhysX's default density, 1000 kg/m^3.
    return {name, {ShapeKind::kBox, Vec3(edge, edge, edge)}, 1000.0 * edge * edge * edge, Material::kObject, name};
  }
  throw std::out_of_range("unknown object '" + name + "'");
}

StaticPart MakeTable() {
  StaticPart table;
  table.name = "table";
  const double thickness = 0.05;
  // The reference table asset's size is unknown; this top covers every placement region
  // (x 0.19..0.80, y -0.40..0.40) with margin and leaves the robots' bodies clear.
  table.shape = {ShapeKind::kBox, Vec3(0.85, 1.2, thickness)};
  table.X_WS = MakeTransform(Vec3(0.625, -0.05, kTableHeight - 0.5 * thickness), Mat3::Identity());
  table.material = Material::kTable;
  table.appearance = "table";
  return table;
}

}  // namespace tavis::engine
