#include "engine/world_model.h"

#include <stdexcept>

namespace tavis::engine {

int WorldModel::ObjectIndex(const std::string& name) const {
  for (int i = 0; i < num_objects(); ++i) {
    if (objects[i].name == name) return i;
  }
  throw std::out_of_range("the world has no object named '" + name + "'");
}

}  // namespace tavis::engine
