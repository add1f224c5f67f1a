// The TAVIS objects as primitives: the five TAVIS-Head YCB objects at 0.75x their real sizes
// (cans as cylinders, boxes as boxes) with real YCB masses scaled by volume, and the 5.5 cm red
// cube (reference 2.3, 4.3).
#pragma once

#include <string>
#include <vector>

#include "engine/world_model.h"

namespace tavis::engine {

constexpr double kYcbScale = 0.75;
constexpr double kTableHeight = 1.0;  // world z of the table top

// Sampling order matters: TAVIS_HEAD_OBJECT_NAMES.
const std::vector<std::string>& TavisHeadObjectNames();

// Every catalog object, the ones a task can make its target: TavisHeadObjectNames() and red_cube.
const std::vector<std::string>& CatalogObjectNames();

// Throws std::out_of_range for an unknown name.
ObjectSpec MakeCatalogObject(const std::string& name);

// The shared table: a static box whose top is at kTableHeight.
StaticPart MakeTable();

}  // namespace tavis::engine
