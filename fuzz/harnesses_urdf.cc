// Harness of the URDF reader and writer (robot/urdf_io.h; fuzz/harnesses.h). `kincal import` reads a
// URDF file between two links and writes a robot file; `kincal convert --to urdf` writes the robot back
// into that URDF (or a new one). Both paths run here on whatever the reader accepts.
#include <unistd.h>

#include <algorithm>
#include <filesystem>
#include <fstream>
#include <set>
#include <string>
#include <utility>
#include <vector>

#include <console_bridge/console.h>
#include <tinyxml.h>
#include <urdf_parser/urdf_parser.h>

#include "models/model_factory.h"
#include "robot/robot_file.h"
#include "fuzz/harness_util.h"
#include "fuzz/harnesses.h"
#include "robot/urdf_io.h"

namespace kincal::fuzz {
namespace {

// urdfdom reports through console_bridge (ImportUrdf captures its errors; its writer may warn): the
// fuzzer's output stays readable.
class Quiet : public console_bridge::OutputHandler {
 public:
  Quiet() { console_bridge::useOutputHandler(this); }
  ~Quiet() override { console_bridge::restorePreviousOutputHandler(); }
  void log(const std::string&, console_bridge::LogLevel, const char*, int) override {}
};

// A folder of this process for the files: ImportUrdf reads a path, and the edited export reads its
// source again, as the command line does. Removed at exit (a crash leaves it in /tmp).
struct TemporaryFolder {
  TemporaryFolder() {
    path = (std::filesystem::temp_directory_path() / "kincal_fuzz_urdf_XXXXXX").string();
    if (!mkdtemp(path.data())) Finding("cannot make a temporary folder");
  }
  ~TemporaryFolder() {
    std::error_code ignored;
    std::filesystem::remove_all(path, ignored);
  }
  std::string path;
};
const std::string& Folder() {
  static const TemporaryFolder folder;
  return folder.path;
}

std::string WriteFile(const std::string& name, const std::string& text) {
  const std::string path = Folder() + "/" + name;
  std::ofstream out(path, std::ios::binary | std::ios::trunc);
  out.write(text.data(), static_cast<std::streamsize>(text.size()));
  if (!out.flush()) Finding("cannot write " + path);
  return path;
}

struct Request {
  std::string base, tip, convention = "urdf";
};

uint64_t Hash(const std::string& text) {
  uint64_t h = 1469598103934665603ull;  // FNV-1a
  for (unsigned char c : text) h = (h ^ c) * 1099511628211ull;
  return h;
}

// The pairs of links to import between: those a first line "@@ BASE TIP [CONVENTION]" names, or else
// the root link to each link (a few), and one pair and convention picked by the input's hash (any two
// links: chains that are not serial, reversed, or empty).
std::vector<Request> Requests(std::string* text) {
  if (text->compare(0, 3, "@@ ") == 0) {
    const size_t end = std::min(text->find('\n'), text->size());
    std::vector<std::string> words;
    urdf::split_string(words, text->substr(3, end - 3), " ");
    *text = end < text->size() ? text->substr(end + 1) : std::string();
    // The command line requires both links (empty names are its usage error, not a file's).
    if (words.size() < 2 || words[0].empty() || words[1].empty()) return {};
    Request r{words[0], words[1]};
    // --convention is the command line's choice, not the file's: only the conventions there are.
    for (const std::string& c : ModelConventions()) {
      if (c != "urdf" && words.size() > 2 && words[2] == c) r.convention = c;
    }
    return {r};
  }
  // The links and a root (a link no joint has as child), read with TinyXML: urdfdom itself would leak
  // the models of looped files that ImportUrdf refuses before urdfdom sees them.
  TiXmlDocument xml;
  xml.Parse(text->c_str());
  const TiXmlElement* robot = xml.FirstChildElement("robot");
  std::set<std::string> links, children;
  for (const TiXmlElement* e = robot ? robot->FirstChildElement("link") : nullptr; e;
       e = e->NextSiblingElement("link")) {
    // An empty name cannot be asked for (the command line refuses empty --base and --tip).
    if (e->Attribute("name") && *e->Attribute("name")) links.insert(e->Attribute("name"));
  }
  for (const TiXmlElement* e = robot ? robot->FirstChildElement("joint") : nullptr; e;
       e = e->NextSiblingElement("joint")) {
    const TiXmlElement* child = e->FirstChildElement("child");
    if (child && child->Attribute("link")) children.insert(child->Attribute("link"));
  }
  std::string root;
  for (const std::string& link : links) {
    if (!children.count(link)) root = link;
  }
  if (root.empty()) return {{"base_link", "tool0"}};  // ImportUrdf says what is wrong
  std::vector<Request> out;
  for (const std::string& link : links) {
    if (link != root && out.size() < 8) out.push_back({root, link});
  }
  const std::vector<std::string> names(links.begin(), links.end());
  const uint64_t h = Hash(*text);
  const std::vector<std::string> conventions = ModelConventions();
  out.push_back({names[h % names.size()], names[(h / 7) % names.size()], conventions[(h / 131) % conventions.size()]});
  return out;
}

// Joint values to compare kinematics at: zero, and two points inside the limits (at most 1 from zero).
std::vector<Eigen::VectorXd> Configurations(const Robot& robot) {
  std::vector<Eigen::VectorXd> qs(3, Eigen::VectorXd::Zero(robot.dof()));
  for (int j = 0; j < robot.dof(); ++j) {
    const auto [low, high] = robot.Limit(j);
    qs[1][j] = std::clamp(0.7, low, high);
    qs[2][j] = std::clamp(-0.4 - 0.1 * j, low, high);
  }
  return qs;
}

// The two robots have the same joints and forward kinematics (to rounding: tolerance grows with the
// lengths involved).
void ExpectSameKinematics(const Robot& a, const Robot& b, const std::string& what) {
  if (a.dof() != b.dof()) Finding(what + ": another number of joints");
  for (int j = 0; j < a.dof(); ++j) {
    if (a.model().joint_type(j) != b.model().joint_type(j)) Finding(what + ": another joint type");
  }
  for (const Eigen::VectorXd& q : Configurations(a)) {
    const Eigen::Isometry3d Ta = a.model().ForwardKinematics(q), Tb = b.model().ForwardKinematics(q);
    // Largest magnitudes, not sums or norms: lengths up to 1e300 are legal, their squares are not.
    double scale = 1.0 + q.cwiseAbs().maxCoeff();
    for (const Eigen::VectorXd& p : {a.model().Parameters(), b.model().Parameters()}) {
      scale = std::max(scale, p.cwiseAbs().maxCoeff());
    }
    scale *= 4.0 * (a.dof() + 2);
    const double dp = (Ta.translation() - Tb.translation()).cwiseAbs().maxCoeff();
    const double dr = (Ta.linear() - Tb.linear()).cwiseAbs().maxCoeff();
    if (!(dp <= 1e-9 * scale) || !(dr <= 4e-9 * (a.dof() + 2))) {
      Finding(what + ": other kinematics (position gap " + std::to_string(dp) + ", rotation gap " + std::to_string(dr) +
              ")");
    }
  }
}

// A step that must not fail on a robot the reader accepted: any exception is a finding, with its message.
template <typename Body>
void MustSucceed(const std::string& what, Body&& body) {
  try {
    body();
  } catch (const std::exception& e) {
    Finding(what + ": " + e.what());
  }
}

std::string Describe(const Request& r) { return "(" + r.base + " to " + r.tip + ", " + r.convention + ") "; }

// What a robot file and a URDF of an accepted robot must satisfy.
void CheckImported(const Robot& robot, const Request& request) {
  const std::string about = Describe(request);
  for (Eigen::Index i = 0; i < robot.model().Parameters().size(); ++i) {
    ExpectFinite(robot.model().Parameters()[i], "an imported parameter");
  }
  for (const auto& [low, high] : robot.limits) {
    ExpectFinite(low, "an imported limit");
    ExpectFinite(high, "an imported limit");
  }
  for (Eigen::Index i = 0; i < robot.velocity_limits.size(); ++i)
    ExpectFinite(robot.velocity_limits[i], "a velocity limit");

  // `kincal import` writes a robot file: it reads back with the same kinematics and provenance.
  const std::string yaml = RobotToYaml(robot);
  Robot again;
  try {
    again = ParseRobotYaml(yaml, "written.yaml");
  } catch (const std::exception& e) {
    Finding(std::string("the written robot file is refused: ") + e.what() + "\n" + yaml);
  }
  ExpectSameKinematics(robot, again, about + "the written robot file");
  if (!again.urdf || again.urdf->base_link != request.base || again.urdf->tip_link != request.tip ||
      again.urdf->joints != robot.urdf->joints || again.urdf->path != robot.urdf->path) {
    Finding("the written robot file names other links or joints of the URDF");
  }

  // `kincal convert --to urdf`: the source file edited, and a new file (a robot without provenance).
  // What is written reads back, between the same links, as the same chain.
  std::string edited;
  MustSucceed(about + "the imported robot cannot be written back", [&] { edited = RobotToUrdf(robot); });
  const std::string edited_path = WriteFile("edited.urdf", edited);
  Robot reread;
  MustSucceed(about + "the URDF written back is refused\n" + edited, [&] {
    reread = ImportUrdf(edited_path, {request.base, request.tip, "urdf"});
  });
  ExpectSameKinematics(robot, reread, about + "the URDF written back");

  Robot plain = robot;
  plain.urdf.reset();
  std::string fresh;
  MustSucceed(about + "the imported robot cannot be written as a new URDF", [&] { fresh = RobotToUrdf(plain); });
  const std::string fresh_path = WriteFile("new.urdf", fresh);
  Robot read_fresh;
  MustSucceed(about + "the new URDF is refused\n" + fresh, [&] {
    read_fresh = ImportUrdf(fresh_path, {"world", "tool0", "urdf"});
  });
  ExpectSameKinematics(robot, read_fresh, about + "the new URDF");
}

}  // namespace

int FuzzUrdf(const uint8_t* data, size_t size) {
  Quiet quiet;
  std::string text = Text(data, size);
  const std::vector<Request> requests = Requests(&text);
  const std::string path = WriteFile("robot.urdf", text);
  for (const Request& request : requests) {
    Robot robot;
    if (!Accepts(path, [&] { robot = ImportUrdf(path, {request.base, request.tip, request.convention}); })) continue;
    CheckImported(robot, request);
  }
  return 0;
}

}  // namespace kincal::fuzz
