// Procedural textures (render/procedural_texture.h): each pattern's values at known points, its
// period and its two colours; the face projection; the checks; and rendered: a texture changes
// the pixels of its own instance only, no texture leaves every pixel as it was, and a texture
// moves with its instance, and a textured box face is the same bytes by the flat-face path and the
// per-pixel path; the packet path's lanes (texture, local frame, sRGB encoding) are the same floats
// and bytes as one point at a time.
#include "render/procedural_texture.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <stdexcept>
#include <string>
#include <vector>

#include "render/internal/env_scenes.h"
#include "render/internal/lighting_model.h"
#include "render/internal/texture_evaluation.h"
#include "tests/render/test_scenes.h"

namespace tavis::render {
namespace {

using engine::TexturePattern;

const Eigen::Vector3f kLight(0.9f, 0.8f, 0.1f);
const Eigen::Vector3f kDark(0.05f, 0.1f, 0.4f);
const Eigen::Vector3f kUp = Eigen::Vector3f::UnitZ();

ProceduralTexture Texture(TexturePattern pattern, double scale_m, double angle_deg = 0.0, double turbulence = 0.0) {
  // SurfaceTexture's members in their order: the level's two colours, not random ones.
  return MakeProceduralTexture(
      engine::SurfaceTexture{pattern, scale_m, kLight, kDark, angle_deg, turbulence, /*random_colours=*/false});
}

// The reflectance on an upward face at (x, y).
Eigen::Vector3f On(const ProceduralTexture& texture, float x, float y) {
  return TextureReflectance(texture, Eigen::Vector3f(x, y, 0.02f), kUp);
}

TEST(ProceduralTexture, CheckerAlternatesItsTwoColoursInSquaresOfTheScale) {
  const ProceduralTexture checker = Texture(TexturePattern::kChecker, 0.1);
  EXPECT_EQ(On(checker, 0.05f, 0.05f), kLight);
  EXPECT_EQ(On(checker, 0.15f, 0.05f), kDark);
  EXPECT_EQ(On(checker, 0.05f, 0.15f), kDark);
  EXPECT_EQ(On(checker, 0.15f, 0.15f), kLight);
  EXPECT_EQ(On(checker, -0.05f, 0.05f), kDark) << "negative cells keep alternating";
  EXPECT_EQ(On(checker, -0.05f, -0.05f), kLight);
  // Period: two squares along either axis.
  for (const float x : {0.013f, 0.071f, 0.133f}) {
    for (const float y : {0.021f, 0.089f}) {
      EXPECT_EQ(On(checker, x + 0.2f, y), On(checker, x, y));
      EXPECT_EQ(On(checker, x, y + 0.2f), On(checker, x, y));
      EXPECT_NE(On(checker, x + 0.1f, y), On(checker, x, y));
    }
  }
}

TEST(ProceduralTexture, StripesRunAlongTheSecondCoordinateAndTurnWithTheAngle) {
  const ProceduralTexture stripes = Texture(TexturePattern::kStripes, 0.05);
  for (const float y : {-0.3f, 0.0f, 0.07f, 0.41f}) {
    EXPECT_EQ(On(stripes, 0.025f, y), kLight);
    EXPECT_EQ(On(stripes, 0.075f, y), kDark);
    EXPECT_EQ(On(stripes, 0.125f, y), kLight) << "period: two stripe widths";
  }
  // Turned 90 degrees the stripes run along x instead.
  const ProceduralTexture turned = Texture(TexturePattern::kStripes, 0.05, 90.0);
  for (const float x : {-0.3f, 0.0f, 0.07f}) {
    EXPECT_EQ(On(turned, x, 0.025f), kLight);
    EXPECT_EQ(On(turned, x, 0.075f), kDark);
  }
  // Turned 45 degrees: constant along the diagonal (1, -1), alternating along (1, 1).
  const ProceduralTexture diagonal = Texture(TexturePattern::kStripes, 0.05, 45.0);
  const float step = 0.05f / std::sqrt(2.0f);
  EXPECT_EQ(On(diagonal, 0.3f * step, 0.3f * step), On(diagonal, 0.3f * step + 0.2f, 0.3f * step - 0.2f));
  EXPECT_NE(On(diagonal, 0.3f * step, 0.3f * step), On(diagonal, 1.3f * step, 1.3f * step));
}

TEST(ProceduralTexture, ValueNoiseIsTheLatticeValueAtCornersAndSmoothBetween) {
  // At lattice corners the noise is the corner's value; half-way between two corners their mean.
  for (const int i : {-3, 0, 5}) {
    const float left = ValueNoise(static_cast<float>(i), 2.0f);
    const float right = ValueNoise(static_cast<float>(i + 1), 2.0f);
    EXPECT_NEAR(ValueNoise(i + 0.5f, 2.0f), 0.5f * (left + right), 1e-6f);
  }
  // In [0, 1], not constant, continuous, and a fixed function (the same values every call).
  float low = 1.0f, high = 0.0f;
  for (int k = 0; k < 400; ++k) {
    const float x = 0.173f * k;
    const float y = 0.091f * k - 7.0f;
    const float value = ValueNoise(x, y);
    ASSERT_GE(value, 0.0f);
    ASSERT_LE(value, 1.0f);
    EXPECT_NEAR(ValueNoise(x + 1e-3f, y), value, 0.01f);
    EXPECT_EQ(ValueNoise(x, y), value);
    low = std::min(low, value);
    high = std::max(high, value);
  }
  EXPECT_LT(low, 0.2f);
  EXPECT_GT(high, 0.8f);
  // The texture blends its two colours by the noise at the point in lattice units (cell = scale).
  const ProceduralTexture noise = Texture(TexturePattern::kNoise, 0.2);
  const float value = ValueNoise(3.0f, -2.0f);
  EXPECT_TRUE(On(noise, 0.6f, -0.4f).isApprox(kLight + value * (kDark - kLight), 1e-6f));
}

TEST(ProceduralTexture, WoodRingsAreTheScaleApartAndTurbulenceBendsThem) {
  // Without turbulence: straight rings across y, colour_a at a ring's start, darkening as t^2.
  const ProceduralTexture straight = Texture(TexturePattern::kWood, 0.01);
  for (const float x : {-0.2f, 0.0f, 0.33f}) {
    EXPECT_TRUE(On(straight, x, 0.0f).isApprox(kLight, 1e-6f));
    EXPECT_TRUE(On(straight, x, 0.005f).isApprox(kLight + 0.25f * (kDark - kLight), 1e-5f));
    EXPECT_TRUE(On(straight, x, 0.0075f).isApprox(On(straight, x, 0.0175f), 1e-4f)) << "period 1 cm";
  }
  // Turbulence moves the rings by different amounts along the grain.
  const ProceduralTexture bent = Texture(TexturePattern::kWood, 0.01, 0.0, 1.5);
  int moved = 0;
  for (int k = 0; k < 50; ++k) {
    const Eigen::Vector2f uv(0.37f * k, 0.0031f * k);
    const float value = PatternValue(bent, uv);
    EXPECT_GE(value, 0.0f);
    EXPECT_LE(value, 1.0f);
    if (std::fabs(value - PatternValue(straight, uv)) > 0.05f) ++moved;
  }
  EXPECT_GT(moved, 25);
}

TEST(ProceduralTexture, SolidIsColourAEverywhere) {
  const ProceduralTexture solid = Texture(TexturePattern::kSolid, 0.1);
  for (const float x : {-1.0f, 0.0f, 0.37f}) EXPECT_EQ(On(solid, x, 0.2f * x), kLight);
}

TEST(ProceduralTexture, FacesAreProjectedAcrossTheirNormal) {
  const Eigen::Vector3f p(0.1f, 0.2f, 0.3f);
  EXPECT_EQ(FaceCoordinates(p, Eigen::Vector3f(0.0f, 0.0f, -1.0f)), Eigen::Vector2f(0.1f, 0.2f));
  EXPECT_EQ(FaceCoordinates(p, Eigen::Vector3f(1.0f, 0.0f, 0.0f)), Eigen::Vector2f(0.2f, 0.3f));
  EXPECT_EQ(FaceCoordinates(p, Eigen::Vector3f(0.1f, -0.9f, 0.2f)), Eigen::Vector2f(0.1f, 0.3f));
  // A side face shows the pattern across its own two axes.
  const ProceduralTexture stripes = Texture(TexturePattern::kStripes, 0.05);
  const Eigen::Vector3f side = Eigen::Vector3f::UnitX();
  EXPECT_EQ(TextureReflectance(stripes, Eigen::Vector3f(0.4f, 0.025f, 0.0f), side), kLight);
  EXPECT_EQ(TextureReflectance(stripes, Eigen::Vector3f(0.4f, 0.075f, 0.0f), side), kDark);
}

// The shading loop evaluates a packet of hits on one face as arrays (render/internal/
// texture_evaluation.h, env_scenes.h, lighting_model.h); every lane must be exactly what the
// one-point functions give, or a textured face would differ between packets that all hit it and
// packets that do not.
TEST(ProceduralTexture, PacketLanesAreTheSameFloatsAsOnePointAtATime) {
  constexpr int K = 16;
  const std::vector<ProceduralTexture> textures = {
      Texture(TexturePattern::kChecker, 0.07, 30.0), Texture(TexturePattern::kStripes, 0.05, -45.0),
      Texture(TexturePattern::kNoise, 0.11, 10.0), Texture(TexturePattern::kWood, 0.03, 80.0, 2.5),
      Texture(TexturePattern::kSolid, 0.1)};
  const std::vector<Eigen::Vector3f> normals = {Eigen::Vector3f::UnitZ(), -Eigen::Vector3f::UnitX(),
                                                Eigen::Vector3f(0.1f, 0.9f, -0.2f)};
  // A turned, moved instance frame (column-major [R | t]): a rotation about z by 0.6 rad.
  const float c = std::cos(0.6f), s = std::sin(0.6f);
  const internal::InstanceFrame frame{{c, s, 0.0f, -s, c, 0.0f, 0.0f, 0.0f, 1.0f, 0.3f, -0.2f, 0.75f}};
  const internal::SrgbEncoder encoder;
  int mismatches = 0;
  for (int round = 0; round < 20; ++round) {
    float x[K], y[K], z[K];
    for (int k = 0; k < K; ++k) {  // points spread over several features, negative coordinates too
      x[k] = -1.3f + 0.173f * static_cast<float>(k) + 0.0917f * static_cast<float>(round);
      y[k] = 0.9f - 0.061f * static_cast<float>(k * k % 23) - 0.113f * static_cast<float>(round);
      z[k] = 0.75f + 0.029f * static_cast<float>((k * 7 + round) % 11);
    }
    float local[3][K];
    frame.ToLocalLanes<K>(x, y, z, local);
    for (int k = 0; k < K; ++k) {
      const Eigen::Vector3f one = frame.ToLocal(Eigen::Vector3f(x[k], y[k], z[k]));
      mismatches += one != Eigen::Vector3f(local[0][k], local[1][k], local[2][k]) ? 1 : 0;
    }
    const float* const axes[3] = {local[0], local[1], local[2]};
    for (const ProceduralTexture& texture : textures) {
      for (const Eigen::Vector3f& n : normals) {
        float r[K], g[K], b[K];
        internal::EvaluateTextureLanes<K>(texture, axes, internal::FaceUvAxes(n), r, g, b);
        uint8_t lanes[K][3];
        encoder.EncodeLanes<K>(r, g, b, lanes[0], 3);
        for (int k = 0; k < K; ++k) {
          const Eigen::Vector3f p(local[0][k], local[1][k], local[2][k]);
          const Eigen::Vector3f one = TextureReflectance(texture, p, n);
          EXPECT_EQ(one, Eigen::Vector3f(r[k], g[k], b[k]))
              << "pattern " << static_cast<int>(texture.pattern) << " lane " << k << " round " << round;
          uint8_t encoded[3];
          encoder.Encode(one, encoded);
          mismatches += std::memcmp(encoded, lanes[k], 3) != 0 ? 1 : 0;
        }
      }
    }
  }
  EXPECT_EQ(mismatches, 0);
  // Encoding clamps as the one-colour path does, at both ends.
  float low[K], high[K];
  std::fill_n(low, K, -0.5f);
  std::fill_n(high, K, 3.0f);
  uint8_t clamped[K][3];
  encoder.EncodeLanes<K>(low, high, low, clamped[0], 3);
  uint8_t expected[3];
  encoder.Encode(Eigen::Vector3f(-0.5f, 3.0f, -0.5f), expected);
  for (int k = 0; k < K; ++k) EXPECT_EQ(std::memcmp(clamped[k], expected, 3), 0) << "lane " << k;
}

TEST(ProceduralTexture, BadValuesAreRefusedNamingThem) {
  auto error_of = [](const engine::SurfaceTexture& texture) {
    try {
      MakeProceduralTexture(texture);
    } catch (const std::invalid_argument& error) {
      return std::string(error.what());
    }
    return std::string();
  };
  engine::SurfaceTexture texture;
  texture.pattern = TexturePattern::kChecker;
  EXPECT_EQ(error_of(texture), "");
  engine::SurfaceTexture tiny = texture;
  tiny.scale_m = 1e-4;
  EXPECT_NE(error_of(tiny).find("scale"), std::string::npos) << error_of(tiny);
  engine::SurfaceTexture bright = texture;
  bright.colour_b = Eigen::Vector3f(1.5f, 0.0f, 0.0f);
  EXPECT_NE(error_of(bright).find("1.5"), std::string::npos) << error_of(bright);
  engine::SurfaceTexture wild = texture;
  wild.turbulence = 9.0;
  EXPECT_NE(error_of(wild).find("turbulence"), std::string::npos) << error_of(wild);
  engine::SurfaceTexture spun = texture;
  spun.angle_deg = 720.0;
  EXPECT_NE(error_of(spun).find("720"), std::string::npos) << error_of(spun);
}

// Rendered: the golden scene with its table top as object 10, so its pixels can be told apart.
constexpr int kWidth = 160;
constexpr int kHeight = 120;
constexpr int32_t kTableTopId = 10;
constexpr std::size_t kTableTop = 1;  // GoldenScene's instance order: floor, table top, legs...

using Rendered = testing::EnvImages;

Rendered RenderScene(const testing::TestScene& scene, const std::vector<ProceduralTexture>& textures) {
  RenderInputs inputs = scene.Inputs();
  inputs.instance_texture = textures;
  return testing::RenderEnvZero(scene, inputs);
}

testing::TestScene SceneWithTableTopId() {
  testing::TestScene scene = testing::GoldenScene(kWidth, kHeight);
  scene.layout.instances[kTableTop].object_id = kTableTopId;
  return scene;
}

TEST(ProceduralTextureRender, WithoutTexturesEveryPixelIsAsBefore) {
  const testing::TestScene scene = SceneWithTableTopId();
  const Rendered plain = RenderScene(scene, {});
  const std::vector<ProceduralTexture> none(scene.layout.instances.size());
  const Rendered all_none = RenderScene(scene, none);
  EXPECT_EQ(all_none.rgb, plain.rgb);
  EXPECT_EQ(all_none.ids, plain.ids);
}

TEST(ProceduralTextureRender, ATableTextureChangesTheTablesPixelsAndNoOthers) {
  const testing::TestScene scene = SceneWithTableTopId();
  const Rendered plain = RenderScene(scene, {});
  std::vector<ProceduralTexture> textures(scene.layout.instances.size());
  textures[kTableTop] = Texture(TexturePattern::kChecker, 0.05);
  const Rendered textured = RenderScene(scene, textures);
  EXPECT_EQ(textured.ids, plain.ids);
  for (std::size_t c = 0; c < plain.rgb.size(); ++c) {
    SCOPED_TRACE(scene.layout.cameras[c].name);
    int table_pixels = 0, table_changed = 0, other_changed = 0;
    for (std::size_t p = 0; p < plain.ids[c].size(); ++p) {
      const bool changed = std::memcmp(&plain.rgb[c][3 * p], &textured.rgb[c][3 * p], 3) != 0;
      if (plain.ids[c][p] == kTableTopId) {
        ++table_pixels;
        table_changed += changed ? 1 : 0;
      } else {
        other_changed += changed ? 1 : 0;
      }
    }
    EXPECT_EQ(other_changed, 0) << "the floor, the legs and the objects are untouched";
    ASSERT_GT(table_pixels, 200);
    EXPECT_GT(table_changed, table_pixels / 2) << "both checker colours differ from the table's grey";
  }
}

// A textured box face takes the flat-face path (its lighting once per face); a labelled box is
// shaded per pixel. A stripes label leaves the top face unlabelled, so the table's top is drawn
// by the two paths: its pixels must be the same bytes. The label's colour has no green, so every
// other table pixel (its sides) shows the label in the labelled image.
TEST(ProceduralTextureRender, ATexturedBoxFaceIsTheSameBytesAsThePerPixelPathDrawsIt) {
  const testing::TestScene scene = SceneWithTableTopId();
  std::vector<ProceduralTexture> textures(scene.layout.instances.size());
  textures[kTableTop] = Texture(TexturePattern::kNoise, 0.05);
  const Rendered flat = RenderScene(scene, textures);
  testing::TestScene labelled_scene = scene;
  labelled_scene.layout.instances[kTableTop].appearance.label = LabelPattern::kStripes;
  labelled_scene.layout.instances[kTableTop].appearance.label_rgb = Eigen::Vector3f(1.0f, 0.0f, 1.0f);
  const Rendered per_pixel = RenderScene(labelled_scene, textures);
  for (std::size_t c = 0; c < flat.rgb.size(); ++c) {
    SCOPED_TRACE(scene.layout.cameras[c].name);
    int same = 0, label = 0, other = 0;
    for (std::size_t p = 0; p < flat.ids[c].size(); ++p) {
      if (flat.ids[c][p] != kTableTopId) continue;
      if (std::memcmp(&flat.rgb[c][3 * p], &per_pixel.rgb[c][3 * p], 3) == 0) {
        ++same;
      } else if (per_pixel.rgb[c][3 * p + 1] == 0) {
        ++label;
      } else {
        ++other;
      }
    }
    EXPECT_GT(same, 200) << "the top face";
    EXPECT_EQ(other, 0) << "a top-face pixel the two paths shade differently";
  }
}

TEST(ProceduralTextureRender, ATextureMovesWithItsInstance) {
  // The table top alone, seen by the head camera; then the table and the camera moved together by
  // a translation that is not a multiple of the checker's period: the image stays (up to a few
  // pixels on square edges, where the rounding of the hit point differs).
  testing::TestScene scene;
  const testing::TestScene golden = SceneWithTableTopId();
  scene.Add(golden.layout.instances[kTableTop].geometry, golden.layout.instances[kTableTop].appearance, kTableTopId,
            golden.X_WI[kTableTop]);
  scene.AddCamera(golden.layout.cameras[0], golden.X_WC[0]);
  const std::vector<ProceduralTexture> textures = {Texture(TexturePattern::kChecker, 0.05, 30.0)};
  const Rendered before = RenderScene(scene, textures);
  const Vec3 shift(0.37, -0.21, 0.0);
  scene.X_WI[0].pretranslate(shift);
  scene.X_WC[0].pretranslate(shift);
  const Rendered after = RenderScene(scene, textures);
  int differ = 0;
  for (std::size_t p = 0; p < before.ids[0].size(); ++p)
    differ += std::memcmp(&before.rgb[0][3 * p], &after.rgb[0][3 * p], 3) != 0 ? 1 : 0;
  EXPECT_LT(differ, static_cast<int>(before.ids[0].size()) / 100);
  // The control: the table moved under a still camera shows the checker shifted.
  testing::TestScene moved = scene;
  moved.X_WC[0].pretranslate(-shift);
  const Rendered shifted = RenderScene(moved, textures);
  int differ_shifted = 0;
  for (std::size_t p = 0; p < before.ids[0].size(); ++p)
    differ_shifted += std::memcmp(&before.rgb[0][3 * p], &shifted.rgb[0][3 * p], 3) != 0 ? 1 : 0;
  EXPECT_GT(differ_shifted, static_cast<int>(before.ids[0].size()) / 5);
}

TEST(ProceduralTextureRender, ValidateNamesABadTexture) {
  const testing::TestScene scene = SceneWithTableTopId();
  BatchRenderer renderer(scene.layout, 1);
  std::vector<ProceduralTexture> textures(scene.layout.instances.size());
  textures[2] = Texture(TexturePattern::kChecker, 0.05);
  textures[2].colour_a = Eigen::Vector3f(0.0f, 2.0f, 0.0f);
  RenderInputs inputs = scene.Inputs();
  inputs.instance_texture = textures;
  try {
    renderer.Validate(inputs);
    FAIL() << "a colour of 2 was accepted";
  } catch (const std::invalid_argument& error) {
    EXPECT_NE(std::string(error.what()).find("instance_texture[env 0][instance 2]"), std::string::npos) << error.what();
  }
  inputs.instance_texture = ArrayRef<ProceduralTexture>(textures.data(), 3);
  EXPECT_THROW(renderer.Validate(inputs), std::invalid_argument) << "wrong size";
}

}  // namespace
}  // namespace tavis::render
