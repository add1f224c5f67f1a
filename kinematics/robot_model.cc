#include "kinematics/robot_model.h"

#include <stdexcept>

namespace tavis::kinematics {
namespace {

template <typename Named>
int FindByName(const std::vector<Named>& items, const std::string& name, const char* what, const std::string& robot) {
  for (size_t i = 0; i < items.size(); ++i) {
    if (items[i].name == name) return static_cast<int>(i);
  }
  throw std::out_of_range("robot '" + robot + "' has no " + what + " named '" + name + "'");
}

}  // namespace

int RobotModel::LinkIndex(const std::string& link_name) const { return FindByName(links, link_name, "link", name); }

int RobotModel::JointIndex(const std::string& joint_name) const {
  return FindByName(joints, joint_name, "joint", name);
}

int RobotModel::CameraIndex(const std::string& camera_name) const {
  return FindByName(cameras, camera_name, "camera", name);
}

std::vector<double> RobotModel::DefaultPositions() const {
  std::vector<double> q(joints.size());
  for (size_t i = 0; i < joints.size(); ++i) q[i] = joints[i].default_position;
  return q;
}

}  // namespace tavis::kinematics
