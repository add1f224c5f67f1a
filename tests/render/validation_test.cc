// Bad input is rejected with std::invalid_argument naming the value.
#include <gtest/gtest.h>

#include <limits>
#include <string>

#include "render/palette.h"
#include "tests/render/test_scenes.h"

namespace tavis::render {
namespace {

// Runs `action`, expects std::invalid_argument and that its message contains `fragment`.
template <typename Action>
void ExpectInvalid(const Action& action, const std::string& fragment) {
  try {
    action();
    ADD_FAILURE() << "no exception; expected one mentioning '" << fragment << "'";
  } catch (const std::invalid_argument& error) {
    EXPECT_NE(std::string(error.what()).find(fragment), std::string::npos) << error.what();
  }
}

TEST(ValidationTest, LayoutErrorsNameTheCameraOrInstance) {
  testing::TestScene scene = testing::GoldenScene(64, 48);
  SceneLayout zero_width = scene.layout;
  zero_width.cameras[2].width = 0;
  ExpectInvalid([&] { BatchRenderer(zero_width, 1); }, "camera 'left_wrist': width = 0");

  SceneLayout bad_far = scene.layout;
  bad_far.cameras[0].far_m = 0.05;
  ExpectInvalid([&] { BatchRenderer(bad_far, 1); }, "far_m = 0.05");

  SceneLayout bad_radius = scene.layout;
  bad_radius.instances[7].geometry = MakeCylinder(-0.01, 0.1);
  ExpectInvalid([&] { BatchRenderer(bad_radius, 1); }, "instance 7: cylinder size (-0.01");

  SceneLayout bad_colour = scene.layout;
  bad_colour.instances[0].appearance.rgb.x() = 2.0f;
  ExpectInvalid([&] { BatchRenderer(bad_colour, 1); }, "instance 0: rgb (2");

  SceneLayout duplicate = scene.layout;
  duplicate.cameras[3].name = "head";
  ExpectInvalid([&] { BatchRenderer(duplicate, 1); }, "camera name 'head' is used twice");

  ExpectInvalid([&] { BatchRenderer(scene.layout, 0); }, "num_envs = 0");
  ExpectInvalid([] { PaletteAppearance("banana"); }, "unknown palette appearance 'banana'");
}

TEST(ValidationTest, InputErrorsNameTheArrayAndIndex) {
  testing::TestScene scene = testing::GoldenScene(64, 48);
  scene.Replicate(2);
  BatchRenderer renderer(scene.layout, 2);
  ImageBatch images = renderer.MakeImageBatch();
  EXPECT_NO_THROW(renderer.Validate(scene.Inputs()));

  testing::TestScene nan_pose = scene;
  nan_pose.X_WI[scene.layout.instances.size() + 6].translation().x() = std::numeric_limits<double>::quiet_NaN();
  ExpectInvalid([&] { renderer.Validate(nan_pose.Inputs()); }, "X_WI[env 1][instance 6] is not finite");
  // Render itself tolerates the bad pose (the instance is left out), it does not throw.
  EXPECT_NO_THROW(renderer.Render(nan_pose.Inputs(), &images));

  testing::TestScene scaled = scene;
  scaled.X_WC[1].linear() *= 2.0;
  ExpectInvalid([&] { renderer.Validate(scaled.Inputs()); }, "X_WC[env 0][camera 1] rotation is not orthonormal");

  testing::TestScene bad_flag = scene;
  bad_flag.camera_enabled[5] = 7;
  ExpectInvalid([&] { renderer.Validate(bad_flag.Inputs()); }, "camera_enabled[env 1][camera 1] = 7");

  testing::TestScene short_poses = scene;
  short_poses.X_WI.pop_back();
  ExpectInvalid([&] { renderer.Render(short_poses.Inputs(), &images); },
                "X_WI has 17 elements, expected 18 (num_envs x n_instances)");

  BatchRenderer one_env(scene.layout, 1);
  ImageBatch wrong_batch = one_env.MakeImageBatch();
  ExpectInvalid([&] { renderer.Render(scene.Inputs(), &wrong_batch); }, "ImageBatch does not match");
}

}  // namespace
}  // namespace tavis::render
