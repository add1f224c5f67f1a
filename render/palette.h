// The named appearances of the TAVIS scene: static parts, robot, the five YCB stand-ins, the red
// cube and the task props. Colours are linear reflectance, chosen so that every object is
// recognisable at 224x224 (see palette.cc for the real-object look each one imitates).
#pragma once

#include <string>
#include <vector>

#include "render/appearance.h"

namespace tavis::render {

// Names: floor, table, robot_link, gripper, soup_can, meat_can, tuna_fish_can, gelatin_box,
// pudding_box, red_cube, cue_card, signal_light, wood, screen_frame, screen_panel, distractor.
// Throws std::invalid_argument for any other name.
const Appearance& PaletteAppearance(const std::string& name);

std::vector<std::string> PaletteNames();

}  // namespace tavis::render
