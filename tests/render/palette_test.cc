// The five YCB stand-ins and the red cube can be told apart by colour at 224x224.
#include <gtest/gtest.h>

#include <array>
#include <string>
#include <vector>

#include "render/palette.h"
#include "tests/render/test_scenes.h"

namespace tavis::render {
namespace {

struct NamedObject {
  std::string name;
  ShapeGeometry shape;
};

TEST(PaletteTest, TabletopObjectsHaveDistinctColoursAt224) {
  // Reference sizes scaled by 0.75 (reference §2.3); boxes stand with their largest face forward.
  const std::vector<NamedObject> objects = {
      {"soup_can", MakeCylinder(0.0248, 0.0758)},
      {"meat_can", MakeBox(Vec3(0.0375, 0.0728, 0.0615))},
      {"tuna_fish_can", MakeCylinder(0.0319, 0.0248)},
      {"gelatin_box", MakeBox(Vec3(0.021, 0.0638, 0.0548))},
      {"pudding_box", MakeBox(Vec3(0.0263, 0.0825, 0.0668))},
      {"red_cube", MakeBox(Vec3::Constant(0.055))},
  };
  testing::TestScene scene;
  scene.Add(MakeBox(Vec3(0.9, 1.2, 0.04)), PaletteAppearance("table"), kBackgroundObjectId,
            MakeTransform(Vec3(0.6, -0.1, 0.98), Mat3::Identity()));
  for (std::size_t i = 0; i < objects.size(); ++i) {
    const double y = 0.25 - 0.1 * static_cast<double>(i);
    const Vec3 centre(0.45, y, 1.0 + 0.5 * objects[i].shape.size.z());
    scene.Add(objects[i].shape, PaletteAppearance(objects[i].name), static_cast<int32_t>(i),
              MakeTransform(centre, Mat3::Identity()));
  }
  scene.AddCamera(HeadCameraSpec(224, 224), testing::PitchedHeadCameraPose(45.0));
  RenderOptions options;
  options.with_object_id = true;
  BatchRenderer renderer(scene.layout, 1, options);
  ImageBatch images = renderer.MakeImageBatch();
  renderer.Render(scene.Inputs(), &images);

  std::vector<Eigen::Vector3d> mean_rgb(objects.size(), Eigen::Vector3d::Zero());
  std::vector<int> count(objects.size(), 0);
  const int32_t* ids = images.object_id(0, 0);
  const uint8_t* rgb = images.rgb(0, 0);
  for (int i = 0; i < 224 * 224; ++i) {
    if (ids[i] < 0) continue;
    const auto object = static_cast<std::size_t>(ids[i]);
    mean_rgb[object] += Eigen::Vector3d(rgb[3 * i], rgb[3 * i + 1], rgb[3 * i + 2]);
    ++count[object];
  }
  for (std::size_t i = 0; i < objects.size(); ++i) {
    ASSERT_GT(count[i], 40) << objects[i].name << " is too small to judge";
    mean_rgb[i] /= count[i];
  }
  for (std::size_t a = 0; a < objects.size(); ++a) {
    for (std::size_t b = a + 1; b < objects.size(); ++b) {
      EXPECT_GT((mean_rgb[a] - mean_rgb[b]).norm(), 30.0)
          << objects[a].name << " (" << mean_rgb[a].transpose() << ") vs " << objects[b].name << " ("
          << mean_rgb[b].transpose() << ")";
    }
  }
}

}  // namespace
}  // namespace tavis::render
