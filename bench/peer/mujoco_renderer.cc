#include "bench/peer/mujoco_renderer.h"

#include <GL/osmesa.h>
#include <mujoco/mujoco.h>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <sstream>
#include <stdexcept>

#include "render/camera.h"

namespace tavis::peer {
namespace {

// What the eye sees of a linear reflectance in our renderer, roughly: MuJoCo's pipeline has no
// sRGB encoding, so colours are given encoded.
float Encoded(float linear) {
  const float v = std::clamp(linear, 0.0f, 1.0f);
  return v <= 0.0031308f ? 12.92f * v : 1.055f * std::pow(v, 1.0f / 2.4f) - 0.055f;
}

std::string GeomOf(const render::ShapeGeometry& shape) {
  std::ostringstream s;
  s.precision(9);
  switch (shape.kind) {
    case ShapeKind::kBox:
      s << "type=\"box\" size=\"" << 0.5 * shape.size.x() << ' ' << 0.5 * shape.size.y() << ' ' << 0.5 * shape.size.z()
        << '"';
      break;
    case ShapeKind::kCylinder:
      s << "type=\"cylinder\" size=\"" << shape.size.x() << ' ' << 0.5 * shape.size.z() << '"';
      break;
    case ShapeKind::kCapsule:
      s << "type=\"capsule\" size=\"" << shape.size.x() << ' ' << 0.5 * shape.size.z() << '"';
      break;
    case ShapeKind::kSphere: s << "type=\"sphere\" size=\"" << shape.size.x() << '"'; break;
    case ShapeKind::kPlane: s << "type=\"plane\" size=\"20 20 1\""; break;
  }
  return s.str();
}

std::string BuildMjcf(const render::SceneLayout& layout, bool shadows) {
  int max_side = 0;
  for (const render::CameraSpec& c : layout.cameras) max_side = std::max({max_side, c.width, c.height});
  const Eigen::Vector3d d = layout.lighting.distant_direction.normalized().cast<double>();
  std::ostringstream xml;
  xml.precision(9);
  xml << "<mujoco model=\"tavis_peer_render\">\n";
  // Scene extent 2 m about the workspace: the shadow map and clip planes scale with it.
  xml << "  <statistic extent=\"2\" center=\"0.5 0 1\"/>\n";
  xml << "  <visual>\n    <global offwidth=\"" << max_side << "\" offheight=\"" << max_side << "\"/>\n";
  // Shadow map: about twice the image side (1024 to 4096 texels), kinder to MuJoCo on small
  // images than its default 4096.
  int shadow_size = 1024;
  while (shadow_size < 2 * max_side && shadow_size < 4096) shadow_size *= 2;
  xml << "    <quality shadowsize=\"" << shadow_size << "\" offsamples=\"0\"/>\n";
  xml << "    <map znear=\"0.02\" zfar=\"5\" shadowclip=\"1\"/>\n";
  // The dome: an ambient term; the distant light does the rest.
  xml << "    <headlight ambient=\"0.45 0.45 0.45\" diffuse=\"0 0 0\" specular=\"0 0 0\"/>\n  </visual>\n";
  // Rays that hit nothing see the dome; MuJoCo's equivalent is a flat skybox of its colour.
  const float dome = Encoded(layout.lighting.dome_intensity * 3.14159265f * layout.lighting.exposure);
  xml << "  <asset><texture type=\"skybox\" builtin=\"flat\" rgb1=\"" << dome << ' ' << dome << ' ' << dome
      << "\" rgb2=\"" << dome << ' ' << dome << ' ' << dome << "\" width=\"16\" height=\"16\"/></asset>\n";
  xml << "  <worldbody>\n";
  xml << "    <light directional=\"true\" castshadow=\"" << (shadows ? "true" : "false") << "\" pos=\""
      << 0.5 - 3.0 * d.x() << ' ' << -3.0 * d.y() << ' ' << 1.0 - 3.0 * d.z() << "\" dir=\"" << d.x() << ' ' << d.y()
      << ' ' << d.z() << "\" diffuse=\"0.6 0.6 0.6\" specular=\"0 0 0\"/>\n";
  for (std::size_t i = 0; i < layout.instances.size(); ++i) {
    const render::InstanceSpec& instance = layout.instances[i];
    const Eigen::Vector3f& rgb = instance.appearance.rgb;
    xml << "    <body name=\"i" << i << "\" mocap=\"true\"><geom " << GeomOf(instance.geometry)
        << " contype=\"0\" conaffinity=\"0\" rgba=\"" << Encoded(rgb.x()) << ' ' << Encoded(rgb.y()) << ' '
        << Encoded(rgb.z()) << " 1\"/></body>\n";
  }
  for (std::size_t c = 0; c < layout.cameras.size(); ++c) {
    const render::CameraSpec& camera = layout.cameras[c];
    const double fovy =
        2.0 * std::atan(0.5 * camera.height / render::IntrinsicsOf(camera).fy) * 180.0 / 3.14159265358979;
    xml << "    <body name=\"c" << c << "\" mocap=\"true\"><camera name=\"" << camera.name << "\" fovy=\"" << fovy
        << "\"/></body>\n";
  }
  xml << "  </worldbody>\n</mujoco>\n";
  return xml.str();
}

}  // namespace

struct MujocoRenderer::Impl {
  render::SceneLayout layout;
  std::string xml;
  mjModel* model = nullptr;
  mjData* data = nullptr;
  OSMesaContext gl = nullptr;
  std::vector<uint8_t> framebuffer;
  mjvScene scene;
  mjvOption option;
  mjvCamera camera;
  mjrContext context;
  std::vector<std::vector<uint8_t>> images;  // [camera], bottom row first while reading
  std::vector<uint8_t> row;
};

MujocoRenderer::MujocoRenderer(const render::SceneLayout& layout, bool shadows) : impl_(std::make_unique<Impl>()) {
  Impl& s = *impl_;
  s.layout = layout;
  s.xml = BuildMjcf(layout, shadows);
  mjVFS vfs;
  mj_defaultVFS(&vfs);
  mj_makeEmptyFileVFS(&vfs, "render.xml", static_cast<int>(s.xml.size()));
  std::memcpy(vfs.filedata[mj_findFileVFS(&vfs, "render.xml")], s.xml.data(), s.xml.size());
  char error[1000] = "";
  s.model = mj_loadXML("render.xml", &vfs, error, sizeof(error));
  mj_deleteVFS(&vfs);
  if (s.model == nullptr) throw std::runtime_error(std::string("MuJoCo rejected the render model: ") + error);
  s.data = mj_makeData(s.model);
  const int side = s.model->vis.global.offwidth;
  s.gl = OSMesaCreateContextExt(OSMESA_RGBA, 24, 8, 8, nullptr);
  s.framebuffer.resize(static_cast<std::size_t>(side) * static_cast<std::size_t>(side) * 4);
  if (s.gl == nullptr || !OSMesaMakeCurrent(s.gl, s.framebuffer.data(), GL_UNSIGNED_BYTE, side, side)) {
    throw std::runtime_error("OSMesa: cannot create or bind a software OpenGL context");
  }
  mjv_defaultScene(&s.scene);
  mjv_defaultOption(&s.option);
  mjv_defaultCamera(&s.camera);
  mjr_defaultContext(&s.context);
  mjv_makeScene(s.model, &s.scene, 2000);
  mjr_makeContext(s.model, &s.context, mjFONTSCALE_100);
  mjr_setBuffer(mjFB_OFFSCREEN, &s.context);
  if (s.context.currentBuffer != mjFB_OFFSCREEN) throw std::runtime_error("MuJoCo: no offscreen framebuffer");
  s.camera.type = mjCAMERA_FIXED;
  for (const render::CameraSpec& c : layout.cameras) {
    s.images.emplace_back(static_cast<std::size_t>(c.width) * static_cast<std::size_t>(c.height) * 3);
  }
}

MujocoRenderer::~MujocoRenderer() {
  Impl& s = *impl_;
  mjr_freeContext(&s.context);
  mjv_freeScene(&s.scene);
  OSMesaDestroyContext(s.gl);
  mj_deleteData(s.data);
  mj_deleteModel(s.model);
}

void MujocoRenderer::Render(const RigidTransform* X_WI, const RigidTransform* X_WC, const uint8_t* visible) {
  Impl& s = *impl_;
  const int n_instances = static_cast<int>(s.layout.instances.size());
  auto set_mocap = [&](int body, const Vec3& p, const Mat3& R) {
    const int m = s.model->body_mocapid[body];
    const Quat q(R);
    s.data->mocap_pos[3 * m] = p.x();
    s.data->mocap_pos[3 * m + 1] = p.y();
    s.data->mocap_pos[3 * m + 2] = p.z();
    s.data->mocap_quat[4 * m] = q.w();
    s.data->mocap_quat[4 * m + 1] = q.x();
    s.data->mocap_quat[4 * m + 2] = q.y();
    s.data->mocap_quat[4 * m + 3] = q.z();
  };
  for (int i = 0; i < n_instances; ++i) {
    // A hidden instance moves far below the floor, out of every view and shadow.
    const Vec3 p = visible[i] != 0 ? X_WI[i].translation() : Vec3(0.0, 0.0, -1000.0);
    set_mocap(1 + i, p, X_WI[i].linear());
  }
  for (std::size_t c = 0; c < s.layout.cameras.size(); ++c) {
    // Ours: x forward, y left, z up. MuJoCo's camera: x right, y up, looking along -z.
    const Mat3& R = X_WC[c].linear();
    Mat3 R_mj;
    R_mj.col(0) = -R.col(1);
    R_mj.col(1) = R.col(2);
    R_mj.col(2) = -R.col(0);
    set_mocap(1 + n_instances + static_cast<int>(c), X_WC[c].translation(), R_mj);
  }
  mj_kinematics(s.model, s.data);
  mj_camlight(s.model, s.data);
  for (std::size_t c = 0; c < s.layout.cameras.size(); ++c) {
    const render::CameraSpec& spec = s.layout.cameras[c];
    s.camera.fixedcamid = static_cast<int>(c);
    mjv_updateScene(s.model, s.data, &s.option, nullptr, &s.camera, mjCAT_ALL, &s.scene);
    const mjrRect viewport = {0, 0, spec.width, spec.height};
    mjr_render(viewport, &s.scene, &s.context);
    std::vector<uint8_t>& image = s.images[c];
    mjr_readPixels(image.data(), nullptr, viewport, &s.context);
    // OpenGL reads bottom-up.
    const std::size_t stride = static_cast<std::size_t>(spec.width) * 3;
    s.row.resize(stride);
    for (int y = 0; y < spec.height / 2; ++y) {
      uint8_t* top = image.data() + static_cast<std::size_t>(y) * stride;
      uint8_t* bottom = image.data() + static_cast<std::size_t>(spec.height - 1 - y) * stride;
      std::memcpy(s.row.data(), top, stride);
      std::memcpy(top, bottom, stride);
      std::memcpy(bottom, s.row.data(), stride);
    }
  }
}

const std::vector<uint8_t>& MujocoRenderer::image(int camera) const {
  return impl_->images[static_cast<std::size_t>(camera)];
}

std::string MujocoRenderer::mjcf() const { return impl_->xml; }

}  // namespace tavis::peer
