#include "render/internal/flat_shades.h"

#include <algorithm>

#include "render/internal/textured_base.h"

namespace tavis::render::internal {

FlatShades::FlatShades(const SurfaceModel* surfaces, int n_instances)
    : surfaces_(surfaces),
      plain_kinds_(static_cast<std::size_t>(n_instances)),
      kinds_(static_cast<std::size_t>(n_instances)),
      faces_(12 * static_cast<std::size_t>(n_instances)) {
  for (int i = 0; i < n_instances; ++i) {
    const SurfaceModel& surface = surfaces[i];
    const bool flat =
        (surface.kind == ShapeKind::kBox || surface.kind == ShapeKind::kPlane) && HasConstantReflectance(surface);
    plain_kinds_[static_cast<std::size_t>(i)] = surface.appearance.emissive ? Kind::kEmissive
                                                : flat                      ? Kind::kFlat
                                                                            : Kind::kShaded;
  }
  kinds_ = plain_kinds_;
}

void FlatShades::Build(const InstanceFrame* frames, const Eigen::Vector3f* rgb_override,
                       const ProceduralTexture* textures, const LightingModel& lighting, const SrgbEncoder& encoder) {
  for (std::size_t i = 0; i < kinds_.size(); ++i) {
    kinds_[i] = plain_kinds_[i];
    // A texture replaces the flat colour (textured_base.h): such a face keeps its lighting only.
    if (kinds_[i] == Kind::kFlat && HasTexture(textures, static_cast<unsigned int>(i))) kinds_[i] = Kind::kTexturedFlat;
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
        if (kinds_[i] == Kind::kTexturedFlat) {
          f.local_normal = n_local;
          f.lit = lighting.Irradiance(f.normal, f.cosine);
          f.shadowed = lighting.Irradiance(f.normal, 0.0f);
        } else {
          f.colours = ShadeBoth(lighting, encoder, base, f.normal, f.cosine);
        }
      }
    }
  }
}

}  // namespace tavis::render::internal
