#include "batch/dataset/frame_capture.h"

#include <cstddef>
#include <vector>

namespace tavis::batch::dataset {
namespace {

void Append(std::vector<float>& rows, const float* values, int size) { rows.insert(rows.end(), values, values + size); }

}  // namespace

void AppendFrameState(const batch::ProprioceptionBatch& proprioception, int slot, const kinematics::Action& action,
                      RecordedEpisode* episode) {
  for (double value : action) episode->action.push_back(static_cast<float>(value));
  Append(episode->state, proprioception.state(slot), proprioception.state_size());
  Append(episode->left_eef_pos, proprioception.eef_position(slot, kinematics::Side::kLeft), 3);
  Append(episode->left_eef_quat, proprioception.eef_quaternion(slot, kinematics::Side::kLeft), 4);
  Append(episode->right_eef_pos, proprioception.eef_position(slot, kinematics::Side::kRight), 3);
  Append(episode->right_eef_quat, proprioception.eef_quaternion(slot, kinematics::Side::kRight), 4);
  ++episode->frames;
}

void AppendFrameImage(const render::ImageBatch& images, int slot, int camera, video::EpisodeEncoder* encoder,
                      ImageStats* stats) {
  const uint8_t* rgb = images.rgb(slot, camera);
  const std::size_t size =
      static_cast<std::size_t>(images.width(camera)) * static_cast<std::size_t>(images.height(camera)) * 3;
  encoder->WriteFrame(rgb, size);
  stats->AddFrame(rgb, images.width(camera), images.height(camera));
}

}  // namespace tavis::batch::dataset
