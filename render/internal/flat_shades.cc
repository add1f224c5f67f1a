#include "render/internal/flat_shades.h"

#include <algorithm>

namespace tavis::render::internal {

FlatShades::FlatShades(const SurfaceModel* surfaces, int n_instances)
    : surfaces_(surfaces),
      kinds_(static_cast<std::size_t>(n_instances)),
      faces_(12 * static_cast<std::size_t>(n_instances)) {
  for (int i = 0; i < n_instances; ++i) {
    const SurfaceModel& surface = surfaces[i];
    const bool flat =
        (surface.kind == ShapeKind::kBox || surface.kind == ShapeKind::kPlane) && HasConstantReflectance(surface);
    kinds_[static_cast<std::size_t>(i)] = surface.appearance.emissive ? Kind::kEmissive
                                          : flat                      ? Kind::kFlat
                                                                      : Kind::kShaded;
  }
}

void FlatShades::Build(const InstanceFrame* frames, const Eigen::Vector3f* rgb_override, const LightingModel& lighting,
                       const SrgbEncoder& encoder) {
  for (std::size_t i = 0; i < kinds_.size(); ++i) {
    if (kinds_[i] == Kind::kShaded) continue;
    const SurfaceModel& surface = surfaces_[i];
    const Eigen::Vector3f base = rgb_override != nullptr ? rgb_override[i] : surface.appearance.rgb;
    if (kinds_[i] == Kind::kEmissive) {
      encoder.Encode(base, faces_[12 * i].colours.lit);
      continue;
    }
    const int n_faces = surface.kind == ShapeKind::kPlane ? 1 : 6;
    for (int face = 0; face < n_faces; ++face) {
      // As the per-pixel path: the local normal of the face's first triangle, turned to world.
      const Eigen::Vector3f n_local = LocalNormal(surface, Eigen::Vector3f::Zero(), static_cast<uint32_t>(2 * face));
      const Eigen::Vector3f n = frames[i].RotateToWorld(n_local);
      for (int side = 0; side < 2; ++side) {
        Face& f = faces_[2 * (6 * i + static_cast<std::size_t>(face)) + static_cast<std::size_t>(side)];
        f.normal = side == 0 ? n : Eigen::Vector3f(-n);
        f.cosine = std::max(0.0f, f.normal.dot(lighting.to_light()));
        f.colours = ShadeBoth(lighting, encoder, base, f.normal, f.cosine);
      }
    }
  }
}

}  // namespace tavis::render::internal
