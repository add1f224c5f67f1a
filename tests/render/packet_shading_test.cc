// The packet (structure-of-arrays) shading must give exactly the scalar shading's values, lane by
// lane: it replaced the scalar loop on the promise of byte-identical images. The scalar functions
// (LocalNormal, InstanceFrame, LightingModel::Shade, the encoder's original index formula) are the
// readers here.
#include <gtest/gtest.h>

#include <algorithm>
#include <cstring>
#include <random>
#include <vector>

#include <Eigen/Geometry>

#include "render/internal/lighting_model.h"
#include "render/internal/packet_shading.h"
#include "render/internal/shape_mesh.h"
#include "render/internal/surface_shading.h"

namespace tavis::render::internal {
namespace {

constexpr int K = 16;

// Bitwise equality: -0 and +0 or two NaNs would hide a changed operation order.
bool SameBits(float a, float b) { return std::memcmp(&a, &b, sizeof a) == 0; }

InstanceFrame RandomFrame(std::mt19937* rng) {
  std::uniform_real_distribution<float> unit(-1.0f, 1.0f);
  const Eigen::Matrix3f R =
      Eigen::Quaternionf(unit(*rng), unit(*rng), unit(*rng), unit(*rng)).normalized().toRotationMatrix();
  InstanceFrame frame;
  for (int column = 0; column < 3; ++column) {
    for (int row = 0; row < 3; ++row) frame.xfm[3 * column + row] = R(row, column);
  }
  for (int i = 0; i < 3; ++i) frame.xfm[9 + i] = unit(*rng);
  return frame;
}

struct ShapeCase {
  const char* name;
  ShapeGeometry geometry;
};

TEST(PacketShadingTest, HitGeometryMatchesTheScalarNormalsBitForBit) {
  const std::vector<ShapeCase> shapes = {{"box", MakeBox(Vec3(0.2, 0.3, 0.4))},
                                         {"cylinder", MakeCylinder(0.05, 0.12)},
                                         {"capsule", MakeCapsule(0.04, 0.2)},
                                         {"sphere", MakeSphere(0.09)},
                                         {"plane", MakePlane()}};
  const Eigen::Vector3f to_light = Eigen::Vector3f(0.342f, 0.321f, 0.883f).normalized();
  std::mt19937 rng(7);
  std::uniform_real_distribution<float> unit(-1.0f, 1.0f);
  std::uniform_real_distribution<float> distance(0.2f, 3.0f);
  for (const ShapeCase& shape : shapes) {
    const ShapeMesh mesh = TessellateShape(shape.geometry);
    const SurfaceModel surface = MakeSurfaceModel({shape.geometry, Appearance{}, 3}, mesh);
    std::uniform_int_distribution<uint32_t> primitive_of(0, mesh.triangle_count() - 1);
    for (int packet = 0; packet < 50; ++packet) {
      const Eigen::Vector3f origin(unit(rng), unit(rng), unit(rng));
      alignas(64) float dir[3][K];
      alignas(64) float t[K];
      uint32_t primitive[K];
      std::vector<InstanceFrame> frames;
      HitLanes<K> lanes;
      for (int k = 0; k < K; ++k) {
        const Eigen::Vector3f d = Eigen::Vector3f(unit(rng), unit(rng), unit(rng)).normalized();
        for (int c = 0; c < 3; ++c) dir[c][k] = d[c];
        t[k] = distance(rng);
        primitive[k] = primitive_of(rng);
        frames.push_back(RandomFrame(&rng));
        if (k == 0) {
          // A hit at the shape's origin: round shapes take the zero-length branch (the up vector).
          t[k] = 0.0f;
          for (int c = 0; c < 3; ++c) frames.back().xfm[9 + c] = origin[c];
        }
        lanes.GatherHit(k, surface, frames.back(), primitive[k], Eigen::Vector3f(0.3f, 0.4f, 0.5f));
      }
      HitGeometry<K> hit;
      ComputeHitGeometry<K>(origin, dir[0], dir[1], dir[2], t, to_light, lanes, &hit);
      for (int k = 0; k < K; ++k) {
        const Eigen::Vector3f direction(dir[0][k], dir[1][k], dir[2][k]);
        const Eigen::Vector3f p = origin + t[k] * direction;
        const Eigen::Vector3f p_local = frames[static_cast<std::size_t>(k)].ToLocal(p);
        const Eigen::Vector3f n_local = LocalNormal(surface, p_local, primitive[k]);
        Eigen::Vector3f n = frames[static_cast<std::size_t>(k)].RotateToWorld(n_local);
        if (n.dot(direction) > 0.0f) n = -n;
        const float cosine = std::max(0.0f, n.dot(to_light));
        for (int c = 0; c < 3; ++c) {
          EXPECT_TRUE(SameBits(hit.p_local[c][k], p_local[c])) << shape.name << " lane " << k << " p_local " << c;
          EXPECT_TRUE(SameBits(hit.n_local[c][k], n_local[c])) << shape.name << " lane " << k << " n_local " << c;
          EXPECT_TRUE(SameBits(hit.n[c][k], n[c])) << shape.name << " lane " << k << " n " << c;
        }
        EXPECT_TRUE(SameBits(hit.cosine[k], cosine)) << shape.name << " lane " << k << ": " << hit.cosine[k] << " vs " << cosine;
      }
    }
  }
}

TEST(PacketShadingTest, ShadeLanesMatchesShadeAndTableIndexClampsLikeTheScalarEncoder) {
  LightingSpec spec;
  spec.dome_rgb = Eigen::Vector3f(0.9f, 1.0f, 1.1f);
  spec.distant_rgb = Eigen::Vector3f(1.2f, 1.0f, 0.8f);
  spec.ground_bounce = 0.3f;
  const LightingModel lighting(spec);
  std::mt19937 rng(11);
  std::uniform_real_distribution<float> unit(-1.0f, 1.0f);
  std::uniform_real_distribution<float> reflectance(0.0f, 1.0f);
  for (int packet = 0; packet < 200; ++packet) {
    alignas(64) float rgb[3][K];
    alignas(64) float nz[K];
    alignas(64) float cosine[K];
    alignas(64) float out[3][K];
    std::vector<Eigen::Vector3f> normals;
    for (int k = 0; k < K; ++k) {
      normals.push_back(Eigen::Vector3f(unit(rng), unit(rng), unit(rng)).normalized());
      nz[k] = normals.back().z();
      cosine[k] = std::max(0.0f, unit(rng));
      for (int c = 0; c < 3; ++c) rgb[c][k] = reflectance(rng);
    }
    lighting.ShadeLanes<K>(rgb, nz, cosine, out);
    for (int k = 0; k < K; ++k) {
      const Eigen::Vector3f expected =
          lighting.Shade(Eigen::Vector3f(rgb[0][k], rgb[1][k], rgb[2][k]), normals[static_cast<std::size_t>(k)], cosine[k]);
      for (int c = 0; c < 3; ++c) {
        EXPECT_TRUE(SameBits(out[c][k], expected[c])) << "lane " << k << " channel " << c;
        // Values past both ends of [0, 1] too: the index clamps.
        const float linear = 2.0f * out[c][k] - 0.5f;
        const float scaled = linear * 4095.0f + 0.5f;
        const int reference = scaled <= 0.0f ? 0 : scaled >= 4095.0f ? 4095 : static_cast<int>(scaled);
        EXPECT_EQ(SrgbEncoder::TableIndex(linear), reference) << linear;
      }
    }
  }
}

}  // namespace
}  // namespace tavis::render::internal
