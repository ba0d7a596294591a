#include "roar/sensors/vehicle_looks.h"
#include "roar/config/text_file.h"

#include <urdf_model/model.h>
#include <urdf_parser/urdf_parser.h>

#include <cmath>
#include <fstream>
#include <sstream>
#include <stdexcept>

namespace roar::sensors {

namespace {

Eigen::Isometry3d toIsometry(const urdf::Pose& pose) {
  Eigen::Isometry3d t = Eigen::Isometry3d::Identity();
  t.translation() = Eigen::Vector3d(pose.position.x, pose.position.y, pose.position.z);
  t.linear() =
      Eigen::Quaterniond(pose.rotation.w, pose.rotation.x, pose.rotation.y, pose.rotation.z).toRotationMatrix();
  return t;
}

Eigen::Isometry3d linkInBase(const urdf::ModelInterface& model, urdf::LinkConstSharedPtr link) {
  Eigen::Isometry3d t = Eigen::Isometry3d::Identity();
  while (link && link->parent_joint) {
    t = toIsometry(link->parent_joint->parent_to_joint_origin_transform) * t;
    link = model.getLink(link->parent_joint->parent_link_name);
  }
  return t;
}

void addTriangle(VisualMesh* out, const Eigen::Vector3d& a, const Eigen::Vector3d& b, const Eigen::Vector3d& c,
                 const Eigen::Vector3f& colour) {
  const int base = static_cast<int>(out->mesh.vertices.size());
  out->mesh.vertices.insert(out->mesh.vertices.end(), {a, b, c});
  out->mesh.triangles.push_back({base, base + 1, base + 2});
  out->colours.push_back(colour);
}

void addBox(VisualMesh* out, const Eigen::Isometry3d& t, const Eigen::Vector3d& size, const Eigen::Vector3f& colour) {
  const Eigen::Vector3d h = 0.5 * size;
  Eigen::Vector3d c[8];
  for (int i = 0; i < 8; ++i)
    c[i] = t * Eigen::Vector3d((i & 1 ? 1 : -1) * h.x(), (i & 2 ? 1 : -1) * h.y(), (i & 4 ? 1 : -1) * h.z());
  const int faces[6][4] = {{0, 2, 3, 1}, {4, 5, 7, 6}, {0, 1, 5, 4}, {2, 6, 7, 3}, {0, 4, 6, 2}, {1, 3, 7, 5}};
  for (const auto& f : faces) {
    addTriangle(out, c[f[0]], c[f[1]], c[f[2]], colour);
    addTriangle(out, c[f[0]], c[f[2]], c[f[3]], colour);
  }
}

void addCylinder(VisualMesh* out, const Eigen::Isometry3d& t, double radius, double length,
                 const Eigen::Vector3f& colour) {
  constexpr int kSides = 16;
  for (int i = 0; i < kSides; ++i) {
    const double a0 = 2 * M_PI * i / kSides, a1 = 2 * M_PI * (i + 1) / kSides;
    const Eigen::Vector3d p0(radius * std::cos(a0), radius * std::sin(a0), 0),
        p1(radius * std::cos(a1), radius * std::sin(a1), 0);
    const Eigen::Vector3d top(0, 0, 0.5 * length), bottom(0, 0, -0.5 * length);
    addTriangle(out, t * (p0 + bottom), t * (p1 + bottom), t * (p1 + top), colour);
    addTriangle(out, t * (p0 + bottom), t * (p1 + top), t * (p0 + top), colour);
    addTriangle(out, t * top, t * (p0 + top), t * (p1 + top), colour);
    addTriangle(out, t * bottom, t * (p1 + bottom), t * (p0 + bottom), colour);
  }
}

}  // namespace

VisualMesh readVehicleLooks(const std::string& urdf_path) {
  const urdf::ModelInterfaceSharedPtr model =
      urdf::parseURDF(config::readTextFile<std::runtime_error>(urdf_path, config::kMaxUrdfBytes));
  if (!model) throw std::runtime_error(urdf_path + ": not a valid URDF");
  VisualMesh out;
  for (const auto& [name, link] : model->links_) {
    const Eigen::Isometry3d link_pose = linkInBase(*model, link);
    for (const auto& visual : link->visual_array) {
      if (!visual || !visual->geometry) continue;
      Eigen::Vector3f colour(0.5f, 0.5f, 0.5f);
      if (visual->material) {
        const auto& c = visual->material->color;
        colour = Eigen::Vector3f(c.r, c.g, c.b);
        if (visual->material_name == "body") colour = Eigen::Vector3f(-1, -1, -1);
      }
      const Eigen::Isometry3d t = link_pose * toIsometry(visual->origin);
      if (auto box = std::dynamic_pointer_cast<urdf::Box>(visual->geometry)) {
        addBox(&out, t, Eigen::Vector3d(box->dim.x, box->dim.y, box->dim.z), colour);
      } else if (auto cyl = std::dynamic_pointer_cast<urdf::Cylinder>(visual->geometry)) {
        addCylinder(&out, t, cyl->radius, cyl->length, colour);
      }
    }
  }
  if (out.mesh.triangles.empty())
    throw std::runtime_error(urdf_path + ": no box or cylinder visuals to draw the car with");
  return out;
}

}  // namespace roar::sensors
