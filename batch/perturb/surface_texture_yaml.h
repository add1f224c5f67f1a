// Reading one textured surface of the appearance perturbation axis (configs/perturbations/
// appearance.yaml, docs/perturbations.md) strictly: a mapping
//
//   pattern: checker            # solid, checker, stripes, noise or wood
//   scale_m: 0.08               # the feature size in metres, [0.001, 100]; not for solid
//   colours: [[0.8, 0.8, 0.75], [0.1, 0.1, 0.12]]   # linear [0, 1]; one for solid, else two;
//                               # or `random`: drawn per episode (seed, episode)
//   angle_deg: 30               # optional, [-180, 180]; not for solid
//   turbulence: 1.2             # optional, wood only, [0, 8] ring spacings (default 1)
//
// An unknown key, a key the pattern does not use, a value out of range or a wrong number of
// colours is a configs::ConfigError naming the file, the key path and the value.
#pragma once

#include <nlohmann/json.hpp>

#include "configs/yaml_reader.h"
#include "engine/surface_texture.h"

namespace tavis::batch::perturb {

struct SurfaceTextureEntry {
  engine::SurfaceTexture texture;
  nlohmann::ordered_json settings;  // the keys and values as the file gives them
};

SurfaceTextureEntry ReadSurfaceTexture(const configs::YamlValue& value);

}  // namespace tavis::batch::perturb
