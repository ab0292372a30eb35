#include "robot/urdf_io.h"

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <map>
#include <memory>
#include <set>
#include <stdexcept>
#include <string>
#include <utility>
#include <vector>

#include <console_bridge/console.h>
#include <tinyxml.h>
#include <urdf_parser/urdf_parser.h>

#include "framework/atomic_file.h"
#include "framework/error.h"
#include "framework/units.h"
#include "models/conversion.h"
#include "models/urdf_model.h"

namespace kincal {
namespace {

// A name a robot file can carry as text: valid UTF-8 without control characters. URDF allows any XML
// string (a character reference can put a newline in a joint's name); such a name would not survive the
// robot file's YAML unchanged.
bool IsPlainName(const std::string& name) {
  for (size_t i = 0; i < name.size();) {
    const unsigned char c = static_cast<unsigned char>(name[i]);
    if (c < 0x20 || c == 0x7f) return false;
    const int extra = c < 0x80 ? 0 : (c >> 5) == 0x6 ? 1 : (c >> 4) == 0xe ? 2 : (c >> 3) == 0x1e ? 3 : -1;
    if (extra < 0 || i + static_cast<size_t>(extra) >= name.size()) return false;
    for (int k = 1; k <= extra; ++k) {
      if ((static_cast<unsigned char>(name[i + k]) >> 6) != 0x2) return false;
    }
    i += 1 + extra;
  }
  return true;
}

// Keeps urdfdom's console messages off stderr and remembers the first error, for a one-line message.
class CaptureErrors : public console_bridge::OutputHandler {
 public:
  CaptureErrors() { console_bridge::useOutputHandler(this); }
  ~CaptureErrors() override { console_bridge::restorePreviousOutputHandler(); }
  void log(const std::string& text, console_bridge::LogLevel level, const char*, int) override {
    if (level >= console_bridge::CONSOLE_BRIDGE_LOG_ERROR && first_error.empty()) first_error = text;
  }
  std::string first_error;
};

Eigen::Isometry3d ToIsometry(const urdf::Pose& pose) {
  Eigen::Isometry3d T = Eigen::Isometry3d::Identity();
  T.linear() = Eigen::Quaterniond(pose.rotation.w, pose.rotation.x, pose.rotation.y, pose.rotation.z)
                   .normalized()
                   .toRotationMatrix();
  T.translation() = Eigen::Vector3d(pose.position.x, pose.position.y, pose.position.z);
  return T;
}

bool IsMoving(const urdf::Joint& joint) { return joint.type != urdf::Joint::FIXED; }

// urdfdom checks for a single root link, not for loops: it accepts a link that is its own parent, or
// joints a -> b and b -> a apart from the root. Its links own their children, so such a model is never
// freed (not even when it then refuses the file), and a walk up from such a link never ends. Refused
// here, at the joint, before urdfdom sees the file. A link with two parent joints is refused too (it
// is how a loop through the root starts; urdfdom would keep the last parent).
void CheckTree(const TiXmlDocument& xml, const std::string& path) {
  const TiXmlElement* robot = xml.FirstChildElement("robot");
  if (!robot) return;  // urdfdom says what is wrong
  struct Parent {
    std::string link;
    const TiXmlElement* joint;
  };
  std::map<std::string, Parent> parent_of;  // child link -> its parent link and joint
  for (const TiXmlElement* j = robot->FirstChildElement("joint"); j; j = j->NextSiblingElement("joint")) {
    const TiXmlElement* parent = j->FirstChildElement("parent");
    const TiXmlElement* child = j->FirstChildElement("child");
    const char* parent_link = parent ? parent->Attribute("link") : nullptr;
    const char* child_link = child ? child->Attribute("link") : nullptr;
    if (!parent_link || !child_link) continue;  // urdfdom refuses the joint
    if (!parent_of.emplace(child_link, Parent{parent_link, j}).second) {
      ThrowInputError(path, j->Row(), j->Column(),
                      std::string("link '") + child_link + "' has a second parent joint (a URDF must be a tree)");
    }
  }
  // Walk up from every link; links already known to reach a root end the walk (linear in the joints).
  std::set<std::string> reach_root;
  for (const auto& [start, unused] : parent_of) {
    std::set<std::string> path_links;
    std::string link = start;
    for (auto it = parent_of.find(link); it != parent_of.end() && !reach_root.count(link); it = parent_of.find(link)) {
      if (!path_links.insert(link).second) {
        ThrowInputError(path, it->second.joint->Row(), it->second.joint->Column(),
                        "the joints above link '" + link + "' form a loop (a URDF must be a tree)");
      }
      link = it->second.link;
    }
    reach_root.insert(path_links.begin(), path_links.end());
  }
}

struct Chain {
  urdf::ModelInterfaceSharedPtr model;
  std::vector<urdf::JointConstSharedPtr> joints;  // base to tip
};

// Parses `text` (from `path`) and finds the chain from base_link to tip_link.
Chain ParseChain(const std::string& text, const std::string& path, const std::string& base_link,
                 const std::string& tip_link) {
  TiXmlDocument xml;
  xml.Parse(text.c_str());
  if (xml.Error())
    ThrowInputError(path, xml.ErrorRow(), xml.ErrorCol(), std::string("invalid XML: ") + xml.ErrorDesc());
  CheckTree(xml, path);
  Chain chain;
  {
    CaptureErrors errors;
    chain.model = urdf::parseURDF(text);
    if (!chain.model) {
      ThrowInputError(path + ": not a valid URDF" +
                      (errors.first_error.empty() ? "" : " (" + errors.first_error + ")"));
    }
  }
  const auto& links = chain.model->links_;
  for (const std::string& name : {base_link, tip_link}) {
    if (!links.count(name)) ThrowInputError(path + ": no link '" + name + "'");
  }
  urdf::LinkConstSharedPtr link = chain.model->getLink(tip_link);
  while (link->name != base_link) {
    const urdf::JointConstSharedPtr joint = link->parent_joint;
    if (!joint) {
      ThrowInputError(path + ": no serial chain from '" + base_link + "' to '" + tip_link + "' ('" + tip_link +
                      "' is not below '" + base_link + "')");
    }
    if (joint->type == urdf::Joint::FLOATING || joint->type == urdf::Joint::PLANAR ||
        joint->type == urdf::Joint::UNKNOWN) {
      const char* type = joint->type == urdf::Joint::FLOATING ? "floating"
                         : joint->type == urdf::Joint::PLANAR ? "planar"
                                                              : "unknown";
      ThrowInputError(path + ": joint '" + joint->name + "' is " + type +
                      "; kincal models revolute, continuous, prismatic and fixed joints");
    }
    if (!IsPlainName(joint->name) || !IsPlainName(link->name) || !IsPlainName(joint->parent_link_name)) {
      ThrowInputError(path + ": a joint or link name of the chain from '" + base_link +
                      "' holds a control character or bytes that are not UTF-8 (robot files keep names as text)");
    }
    chain.joints.insert(chain.joints.begin(), joint);
    link = chain.model->getLink(joint->parent_link_name);
  }
  return chain;
}

Eigen::Vector3d Axis(const urdf::Joint& joint) { return {joint.axis.x, joint.axis.y, joint.axis.z}; }

// urdfdom reads any finite double. The robot file kincal import writes holds lengths in mm and angles
// in deg (and may be rewritten in um): a number beyond 1e300 (m, rad, m/s) would overflow there, so it
// is refused here. An axis is only a direction, but its length must be a finite, non-zero number.
void CheckNumbers(const urdf::Joint& joint, const std::string& path) {
  constexpr double kLargest = 1e300;
  const auto check = [&](double value, const char* what) {
    if (!(std::abs(value) <= kLargest)) {
      ThrowInputError(path + ": joint '" + joint.name + "' has " + what + " " + FormatExact(value) +
                      ", beyond the +-1e300 a robot file can hold");
    }
  };
  const urdf::Vector3& p = joint.parent_to_joint_origin_transform.position;
  for (const double v : {p.x, p.y, p.z}) check(v, "an origin coordinate");
  if (joint.limits) {
    check(joint.limits->lower, "a lower limit");
    check(joint.limits->upper, "an upper limit");
    check(joint.limits->velocity, "a velocity limit");
  }
  if (IsMoving(joint)) {
    const double norm = Axis(joint).norm();
    if (!(norm > 0.0) || !std::isfinite(norm)) {
      ThrowInputError(path + ": joint '" + joint.name + "' has an axis of length " + FormatExact(norm) +
                      " (expected a finite, non-zero direction)");
    }
  }
}

}  // namespace

Robot ImportUrdf(const std::string& path, const UrdfImportOptions& options) {
  if (options.base_link.empty() || options.tip_link.empty())
    ThrowInputError("kincal import needs --base and --tip links");
  const Chain chain = ParseChain(ReadFileToString(path), path, options.base_link, options.tip_link);
  std::vector<JointType> types;
  for (const auto& joint : chain.joints) {
    CheckNumbers(*joint, path);
    if (IsMoving(*joint))
      types.push_back(joint->type == urdf::Joint::PRISMATIC ? JointType::kPrismatic : JointType::kRevolute);
  }
  if (types.empty()) {
    ThrowInputError(path + ": no moving joint between '" + options.base_link + "' and '" + options.tip_link + "'");
  }
  UrdfModel model(types);
  Robot::UrdfSource source{
      std::filesystem::absolute(path).lexically_normal().string(), options.base_link, options.tip_link, {}};
  std::vector<std::pair<double, double>> limits;
  Eigen::VectorXd velocity(static_cast<Eigen::Index>(types.size()));
  bool limits_ok = true, velocity_ok = true;
  Eigen::Isometry3d pending = Eigen::Isometry3d::Identity();  // fixed joints since the last moving one
  for (const auto& joint : chain.joints) {
    const Eigen::Isometry3d origin = ToIsometry(joint->parent_to_joint_origin_transform);
    if (!IsMoving(*joint)) {
      pending = pending * origin;
      continue;
    }
    const int i = static_cast<int>(source.joints.size());
    model.SetJoint(i, pending * origin, Axis(*joint));
    pending = Eigen::Isometry3d::Identity();
    source.joints.push_back(joint->name);
    if (joint->type == urdf::Joint::CONTINUOUS) {
      limits.emplace_back(-M_PI, M_PI);
    } else if (joint->limits && joint->limits->lower < joint->limits->upper) {
      limits.emplace_back(joint->limits->lower, joint->limits->upper);
    } else {
      limits_ok = false;
    }
    if (joint->limits && joint->limits->velocity > 0.0)
      velocity[i] = joint->limits->velocity;
    else
      velocity_ok = false;
  }
  model.SetTool(pending);
  Robot urdf_robot(chain.model->getName().empty() ? std::string("robot") : chain.model->getName(), model.Clone());
  if (limits_ok) urdf_robot.limits = limits;
  if (velocity_ok) urdf_robot.velocity_limits = velocity;
  urdf_robot.urdf = source;
  // Not every chain has an exact form in every convention (a prismatic axis across its parent's z has
  // none in poe): the refusal names the file, as the reader's own errors do.
  std::unique_ptr<KinematicModel> converted;
  try {
    converted = ConvertModel(model, options.convention);
  } catch (const std::invalid_argument& e) {
    ThrowInputError(path + ": the chain from '" + options.base_link + "' to '" + options.tip_link +
                    "' cannot be written in the " + options.convention + " convention: " + e.what());
  }
  return urdf_robot.WithModel(std::move(converted));
}

namespace {

std::string Numbers(const Eigen::Vector3d& v) {
  return FormatExact(v.x()) + " " + FormatExact(v.y()) + " " + FormatExact(v.z());
}

TiXmlElement* Child(TiXmlElement* parent, const char* name) {
  TiXmlElement* e = parent->FirstChildElement(name);
  if (!e) e = parent->InsertEndChild(TiXmlElement(name))->ToElement();
  return e;
}

// Writes a joint's origin unless it equals the file's to 1e-12 (then the text stays as it was).
void SetOrigin(TiXmlElement* joint, const Eigen::Isometry3d& T, const Eigen::Isometry3d& T_file) {
  if ((T.matrix() - T_file.matrix()).cwiseAbs().maxCoeff() <= 1e-12) return;
  TiXmlElement* origin = Child(joint, "origin");
  origin->SetAttribute("xyz", Numbers(T.translation()));
  origin->SetAttribute("rpy", Numbers(RpyFromRotation(T.linear())));
}

void SetLimits(TiXmlElement* joint, const Robot& robot, int i, const urdf::Joint& parsed) {
  TiXmlElement* limit = joint->FirstChildElement("limit");
  if (!limit) return;
  if (!robot.limits.empty() && parsed.type != urdf::Joint::CONTINUOUS) {
    const auto [low, high] = robot.limits[i];
    if (!parsed.limits || std::abs(parsed.limits->lower - low) > 1e-12) limit->SetAttribute("lower", FormatExact(low));
    if (!parsed.limits || std::abs(parsed.limits->upper - high) > 1e-12)
      limit->SetAttribute("upper", FormatExact(high));
  }
  if (robot.velocity_limits.size() == robot.dof()) {
    const double v = robot.velocity_limits[i];
    if (!parsed.limits || std::abs(parsed.limits->velocity - v) > 1e-12)
      limit->SetAttribute("velocity", FormatExact(v));
  }
}

std::map<std::string, TiXmlElement*> JointElements(TiXmlDocument* doc) {
  std::map<std::string, TiXmlElement*> out;
  // The element urdfdom reads (not RootElement(): elements may come before <robot>).
  TiXmlElement* root = doc->FirstChildElement("robot");
  for (TiXmlElement* e = root ? root->FirstChildElement("joint") : nullptr; e; e = e->NextSiblingElement("joint")) {
    if (e->Attribute("name")) out[e->Attribute("name")] = e;
  }
  return out;
}

std::string Print(const TiXmlDocument& doc) {
  TiXmlPrinter printer;
  printer.SetIndent("  ");
  doc.Accept(&printer);
  return printer.Str();
}

// The calibrated robot at q = 0 in its measurement frame (the URDF's base link, as on import, where the
// base is the identity; a convention's base is its own frame 0, so only the measurement frame is common
// to all): axis directions and points, and T_meas_tool(0).
struct CalibratedAxes {
  std::vector<Eigen::Vector3d> direction, point;
  Eigen::Isometry3d T_base_tool;
};
CalibratedAxes AxesInBaseFrame(const KinematicModel& model) {
  const Eigen::VectorXd q0 = Eigen::VectorXd::Zero(model.dof());
  const Eigen::Isometry3d T_base_meas = Eigen::Isometry3d::Identity();
  CalibratedAxes out;
  const Eigen::Isometry3d T_meas_tool = model.ForwardKinematics(q0);
  out.T_base_tool = T_base_meas * T_meas_tool;
  const Matrix6Xd J = model.JointJacobian(q0);
  for (int i = 0; i < model.dof(); ++i) {
    const bool revolute = model.joint_type(i) == JointType::kRevolute;
    const Eigen::Vector3d w = (revolute ? J.col(i).tail<3>() : J.col(i).head<3>()).normalized();
    const Eigen::Vector3d p =
        revolute ? Eigen::Vector3d(T_meas_tool.translation() + w.cross(J.col(i).head<3>())) : T_meas_tool.translation();
    out.direction.push_back(T_base_meas.linear() * w);
    out.point.push_back(T_base_meas * p);
  }
  return out;
}

std::string EditSourceUrdf(const Robot& robot) {
  const Robot::UrdfSource& source = *robot.urdf;
  const std::string text = ReadFileToString(source.path);
  const Chain chain = ParseChain(text, source.path, source.base_link, source.tip_link);
  std::vector<int> moving;  // indices into chain.joints
  for (size_t k = 0; k < chain.joints.size(); ++k) {
    if (IsMoving(*chain.joints[k])) moving.push_back(static_cast<int>(k));
  }
  bool same = static_cast<int>(moving.size()) == robot.dof();
  for (size_t i = 0; same && i < moving.size(); ++i) same = chain.joints[moving[i]]->name == source.joints[i];
  if (!same)
    ThrowInputError(source.path + ": its chain from '" + source.base_link + "' no longer has the robot's joints");
  const CalibratedAxes cal = AxesInBaseFrame(robot.model());

  // The source's joint frames at q = 0 (base link coordinates), then the calibrated ones.
  std::vector<Eigen::Isometry3d> frame_file(chain.joints.size());
  Eigen::Isometry3d P = Eigen::Isometry3d::Identity();
  for (size_t k = 0; k < chain.joints.size(); ++k)
    frame_file[k] = P = P * ToIsometry(chain.joints[k]->parent_to_joint_origin_transform);
  std::vector<Eigen::Isometry3d> frame = frame_file;
  for (int i = 0; i < robot.dof(); ++i) {
    const urdf::Joint& joint = *chain.joints[moving[i]];
    Eigen::Isometry3d F = frame_file[moving[i]];
    const Eigen::Vector3d w_file = (F.linear() * Axis(joint)).normalized();
    const Eigen::Vector3d& w = cal.direction[i];
    if (w.dot(w_file) < 0.5) {
      ThrowInputError(source.path + ": joint '" + joint.name + "' of the robot turns about an axis " +
                      std::to_string(std::acos(std::clamp(w.dot(w_file), -1.0, 1.0)) * 180 / M_PI) +
                      " deg from the URDF's (a different joint direction convention?)");
    }
    F.linear() = Eigen::Quaterniond::FromTwoVectors(w_file, w).toRotationMatrix() * F.linear();
    if (robot.model().joint_type(i) == JointType::kRevolute) {
      F.translation() = cal.point[i] + w * w.dot(F.translation() - cal.point[i]);
    }
    frame[moving[i]] = F;
  }
  // Fixed joints after the last moving joint take the tool: the first of them is solved for.
  const size_t last = moving.back();
  if (last + 1 == chain.joints.size()) {
    // The tip is the last joint's child: that frame must already be the tool.
    Eigen::Isometry3d F = cal.T_base_tool;
    const Eigen::Vector3d w_tip = F.linear() * Axis(*chain.joints[last]).normalized();
    const bool on_axis = (w_tip - cal.direction.back()).norm() < 1e-9 &&
                         (robot.model().joint_type(robot.dof() - 1) == JointType::kPrismatic ||
                          (F.translation() - cal.point.back()).cross(cal.direction.back()).norm() < 1e-9);
    if (!on_axis) {
      ThrowInputError(source.path + ": the calibrated tool does not fit: no fixed joint between '" +
                      chain.joints[last]->name + "' and the tip '" + source.tip_link + "' to hold it");
    }
    frame[last] = F;
  } else {
    Eigen::Isometry3d after = Eigen::Isometry3d::Identity();
    for (size_t k = last + 2; k < chain.joints.size(); ++k)
      after = after * ToIsometry(chain.joints[k]->parent_to_joint_origin_transform);
    frame[last + 1] = cal.T_base_tool * after.inverse();
    for (size_t k = last + 2; k < chain.joints.size(); ++k)
      frame[k] = frame[k - 1] * ToIsometry(chain.joints[k]->parent_to_joint_origin_transform);
  }
  // Fixed joints between moving ones keep their origins: recompute their frames from the new parents.
  for (size_t k = 1; k <= last; ++k) {
    if (!IsMoving(*chain.joints[k]))
      frame[k] = frame[k - 1] * ToIsometry(chain.joints[k]->parent_to_joint_origin_transform);
  }

  TiXmlDocument doc;
  doc.Parse(text.c_str());
  auto elements = JointElements(&doc);
  Eigen::Isometry3d parent = Eigen::Isometry3d::Identity();
  int i = 0;
  for (size_t k = 0; k < chain.joints.size(); ++k) {
    const urdf::Joint& joint = *chain.joints[k];
    TiXmlElement* e = elements.at(joint.name);
    SetOrigin(e, parent.inverse() * frame[k], ToIsometry(joint.parent_to_joint_origin_transform));
    if (IsMoving(joint)) SetLimits(e, robot, i++, joint);
    parent = frame[k];
  }
  return Print(doc);
}

// A new URDF: urdfdom's model types and writer give the structure, the numbers are then written at full
// precision (urdfdom writes 6 digits).
std::string NewUrdf(const Robot& robot) {
  const auto converted = ConvertModel(robot.model(), "urdf");
  const auto& model = dynamic_cast<const UrdfModel&>(*converted);
  const int n = model.dof();
  urdf::ModelInterface m;
  m.name_ = robot.name;
  auto add_link = [&](const std::string& name) {
    auto link = std::make_shared<urdf::Link>();
    link->name = name;
    m.links_[name] = link;
  };
  std::vector<std::string> links = {"world", "base_link"};
  for (int i = 1; i <= n; ++i) links.push_back("link_" + std::to_string(i));
  links.push_back("tool0");
  for (const auto& name : links) add_link(name);
  std::vector<std::string> joints = {"base"};
  for (int i = 1; i <= n; ++i) joints.push_back("joint_" + std::to_string(i));
  joints.push_back("tool");
  for (size_t k = 0; k < joints.size(); ++k) {
    auto joint = std::make_shared<urdf::Joint>();
    joint->name = joints[k];
    joint->parent_link_name = links[k];
    joint->child_link_name = links[k + 1];
    joint->type = urdf::Joint::FIXED;
    const int i = static_cast<int>(k) - 1;
    if (i >= 0 && i < n) {
      joint->type = model.joint_type(i) == JointType::kRevolute ? urdf::Joint::REVOLUTE : urdf::Joint::PRISMATIC;
      joint->limits = std::make_shared<urdf::JointLimits>();
      joint->limits->lower = robot.Limit(i).first;
      joint->limits->upper = robot.Limit(i).second;
      joint->limits->velocity = robot.velocity_limits.size() == n ? robot.velocity_limits[i] : 0.0;
      joint->limits->effort = 0.0;  // kincal does not model effort
    }
    m.joints_[joints[k]] = joint;
  }
  std::unique_ptr<TiXmlDocument> doc(urdf::exportURDF(m));
  auto elements = JointElements(doc.get());
  const Eigen::Isometry3d never = Eigen::Isometry3d(Eigen::Matrix4d::Constant(std::nan("")));
  SetOrigin(elements.at("base"), model.base(), never);
  SetOrigin(elements.at("tool"), model.tool(), never);
  const Eigen::VectorXd& v = model.Parameters();
  for (int i = 0; i < n; ++i) {
    const Eigen::Vector3d axis = model.JointAxis(i);
    const double offset = v[model.ParameterIndex("offset_" + std::to_string(i + 1))];
    Eigen::Isometry3d origin = model.JointOrigin(i);
    // URDF has no joint offset: it turns (or moves) the origin about (along) the axis.
    if (model.joint_type(i) == JointType::kRevolute)
      origin.rotate(Eigen::AngleAxisd(offset, axis));
    else
      origin.translate(axis * offset);
    TiXmlElement* e = elements.at("joint_" + std::to_string(i + 1));
    SetOrigin(e, origin, never);
    Child(e, "axis")->SetAttribute("xyz", Numbers(axis));
    TiXmlElement* limit = Child(e, "limit");
    limit->SetAttribute("lower", FormatExact(robot.Limit(i).first));
    limit->SetAttribute("upper", FormatExact(robot.Limit(i).second));
    if (robot.velocity_limits.size() == n) limit->SetAttribute("velocity", FormatExact(robot.velocity_limits[i]));
  }
  return Print(*doc);
}

}  // namespace

std::string RobotToUrdf(const Robot& robot) { return robot.urdf ? EditSourceUrdf(robot) : NewUrdf(robot); }

}  // namespace kincal
