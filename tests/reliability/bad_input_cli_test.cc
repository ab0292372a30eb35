// The promise about bad input, from the command line (docs/RELIABILITY.md): whatever a file holds, kincal
// exits with status 0 or 2, and 2 comes with one line on stderr that names the file and, where there is
// one, the line and column. Each case here is a way to escape that promise (exit status 1, or a message
// without the file) or a shape of damage files really have: truncated, binary, wrong encoding.
#include <algorithm>
#include <cctype>
#include <cstdlib>
#include <filesystem>
#include <sstream>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "tests/support/test_util.h"

namespace kincal {
namespace {

using testing::RunKincal;
using testing::SourcePath;
using testing::TempDir;
using testing::WriteText;

std::string Example(const std::string& file) { return SourcePath("examples/robots/" + file); }

int LineCount(const std::string& text) { return static_cast<int>(std::count(text.begin(), text.end(), '\n')); }

// Exit status 2, one line, starting with "kincal: FILE" (then ":LINE:COLUMN" when `where` is given).
void ExpectBadInput(const std::string& arguments, const std::string& file, const std::string& where = "") {
  const auto r = RunKincal(arguments);
  EXPECT_EQ(r.exit_code, 2) << arguments << "\n" << r.err;
  EXPECT_EQ(LineCount(r.err), 1) << r.err;
  EXPECT_EQ(r.err.rfind("kincal: " + file + where, 0), 0u)
      << "expected 'kincal: " << file << where << "...', got: " << r.err;
}

const char* kSixJointHeader = "q1_deg,q2_deg,q3_deg,q4_deg,q5_deg,q6_deg,x_mm,y_mm,z_mm\n";

TEST(BadInput, AColumnIndexBeyondIntIsAnUnknownColumnAtItsPlace) {
  // This header once ended kincal with exit status 1 and "kincal: error: stoi".
  TempDir dir;
  const std::string data = dir.path("data.csv");
  WriteText(data, "q1_deg,q99999999999999999999_deg,x_mm,y_mm,z_mm\n1,2,3,4,5\n");
  ExpectBadInput("identify --nominal " + Example("seed_nominal.yaml") + " --data " + data + " --method none --out " +
                     dir.path("out.yaml"),
                 data, ":1:8: unknown column 'q99999999999999999999_deg'");
  const std::string targets = dir.path("targets.csv");
  WriteText(targets, "x_mm,y_mm,z_mm,q99999999999999999999_deg\n1,2,3,4\n");
  ExpectBadInput("compensate --nominal " + Example("seed_nominal.yaml") + " --identified " +
                     Example("seed_identified.yaml") + " --targets " + targets + " --method none --out " +
                     dir.path("out.csv"),
                 targets, ":1:16:");
}

TEST(BadInput, DamagedDatasetsEndInStatusTwoNamingFileLineAndColumn) {
  TempDir dir;
  const std::string data = dir.path("data.csv");
  const std::string identify = "identify --nominal " + Example("seed_nominal.yaml") + " --data " + data +
                               " --method least_squares --out " + dir.path("out.yaml");
  struct Case {
    std::string text, where;
  };
  const std::vector<Case> cases = {
      {std::string(kSixJointHeader) + "0,0,0,0,0,0,1,2,3\n0,0,0,0,0,0,1,2\n", ":3:1:"},  // truncated row
      {std::string(kSixJointHeader) + "0,0,0,0,0,0,1e400,2,3\n", ":2:13:"},              // overflows double
      {std::string(kSixJointHeader) + "0,0,0,0,0,0,nan,2,3\n", ":2:13:"},                // NaN
      {std::string(kSixJointHeader) + "0,0,0,0,0,0,\xff\xfe,2,3\n", ":2:13:"},           // not UTF-8
      {std::string("\x00\x01\x02", 3) + "binary", ":1:1:"},                              // binary
      {"q1_deg,q2_deg,q3_deg,q4_deg,q5_deg,q6_deg,x_mm,y_mm,z_mm,sweep\n0,0,0,0,0,0,1,2,3,99999999999\n", ":2:"},
      {"q1_deg,q2_deg,q3_deg,q4_deg,q5_deg,q6_deg,x_mm,y_mm,z_mm,enc1,enc2,enc3,enc4,enc5,enc6\n"
       "0,0,0,0,0,0,1,2,3,1e300,0,0,0,0,0\n",
       ":2:"},
      {"", ":1:1:"},  // empty
  };
  for (const Case& c : cases) {
    WriteText(data, c.text);
    ExpectBadInput(identify, data, c.where);
  }
}

TEST(BadInput, DamagedRobotFilesEndInStatusTwoNamingFileAndLine) {
  TempDir dir;
  const std::string robot = dir.path("robot.yaml");
  const std::vector<std::string> cases = {
      "name: r\nconvention: mdh\nunits: {length: mm, angle: deg}\njoints:\n  - {alpha: 1e400, a: 0, theta: 0, d: 0}\n",
      "name: r\nconvention: mdh\nunits: {length: mm, angle: deg}\njoints: [\n",        // truncated YAML
      "name: r\nconvention: mdh\nunits: {length: mm, angle: deg}\njoints: &a [*a]\n",  // alias loop
      std::string("\xef\xbb\xbf\0\0binary", 11),
  };
  for (const std::string& text : cases) {
    WriteText(robot, text);
    ExpectBadInput("fk " + robot + " --q=0", robot);
  }
  // Legal numbers at the edges: accepted (status 0, finite output) or refused (status 2, one line).
  for (const std::string value : {"1e300", "4.9e-324", "-1e300"}) {
    WriteText(robot, "name: r\nconvention: mdh\nunits: {length: mm, angle: deg}\njoints:\n  - {alpha: 0, a: " + value +
                         ", theta: 0, d: 0}\ndrives: {ratio: [" + value + "], counts_per_rev: [" + value + "]}\n");
    const auto r = RunKincal("fk " + robot + " --q=" + value);
    if (r.exit_code == 0) {
      EXPECT_EQ(r.out.find("null"), std::string::npos) << r.out;  // JSON writes NaN as null
    } else {
      EXPECT_EQ(r.exit_code, 2) << r.err;
      EXPECT_EQ(LineCount(r.err), 1) << r.err;
      EXPECT_EQ(r.err.rfind("kincal: " + robot, 0), 0u) << r.err;
    }
  }
}

// A URDF of the links and joints given (the joints one per line from line 3).
std::string Urdf(const std::vector<std::string>& links, const std::vector<std::string>& joints) {
  std::string text = "<robot name=\"r\">\n ";
  for (const std::string& link : links) text += " <link name=\"" + link + "\"/>";
  text += "\n";
  for (const std::string& joint : joints) text += "  " + joint + "\n";
  return text + "</robot>\n";
}
std::string Joint(const std::string& name, const std::string& type, const std::string& parent, const std::string& child,
                  const std::string& inner = "<axis xyz=\"0 0 1\"/>") {
  const std::string limit =
      type == "revolute" || type == "prismatic" ? "<limit lower=\"-1\" upper=\"1\" effort=\"1\" velocity=\"1\"/>" : "";
  return "<joint name=\"" + name + "\" type=\"" + type + "\"><parent link=\"" + parent + "\"/><child link=\"" + child +
         "\"/>" + inner + limit + "</joint>";
}

TEST(BadInput, DamagedUrdfsEndInStatusTwoNamingTheFile) {
  // Found by the urdf fuzz harness (fuzz/regressions/urdf/): loops hung kincal import, a number beyond
  // what a robot file holds was written as inf, a conversion's refusal did not name the file.
  TempDir dir;
  const std::string urdf = dir.path("robot.urdf");
  const auto import = [&](const std::string& tip, const std::string& more = "") {
    return "import " + urdf + " --base base_link --tip " + tip + " --out " + dir.path("robot.yaml") + more;
  };
  struct Case {
    std::string text, tip, more, where;
  };
  const std::vector<Case> cases = {
      // A link that is its own parent (joint on line 3), and a loop a -> b -> a apart from the root (line 4).
      {Urdf({"base_link", "a", "c"}, {Joint("j", "revolute", "base_link", "c"), Joint("aa", "revolute", "a", "a")}),
       "a", "", ":4:3: the joints above link 'a' form a loop"},
      {Urdf({"base_link", "a", "b", "c"}, {Joint("j", "revolute", "base_link", "c"), Joint("ab", "revolute", "a", "b"),
                                           Joint("ba", "fixed", "b", "a")}),
       "a", "", ":5:3: the joints above link 'a' form a loop"},
      {Urdf({"base_link", "a", "c"}, {Joint("j", "revolute", "base_link", "a"), Joint("j2", "revolute", "c", "a")}),
       "a", "", ":4:3: link 'a' has a second parent joint"},
      {Urdf({"base_link", "a"},
            {Joint("j", "revolute", "base_link", "a", "<origin xyz=\"0 1e308 0\"/><axis xyz=\"0 0 1\"/>")}),
       "a", "", ": joint 'j' has an origin coordinate 1e+308"},
      {Urdf({"base_link", "a"}, {Joint("j", "revolute", "base_link", "a", "<axis xyz=\"1e200 1e200 0\"/>")}), "a", "",
       ": joint 'j' has an axis of length inf"},
      {Urdf({"base_link", "a"}, {Joint("j", "revolute", "base_link", "a", "<axis xyz=\"0 0 0\"/>")}), "a", "",
       ": joint 'j' has an axis of length 0"},
      // Two perpendicular slides have no POE rows (a prismatic axis across its parent's z).
      {Urdf({"base_link", "a", "b"},
            {Joint("x", "prismatic", "base_link", "a", "<axis xyz=\"1 0 0\"/>"), Joint("z", "prismatic", "a", "b")}),
       "b", " --convention poe", ": the chain from 'base_link' to 'b' cannot be written in the poe convention"},
  };
  for (const Case& c : cases) {
    WriteText(urdf, c.text);
    ExpectBadInput(import(c.tip, c.more), urdf, c.where);
  }
}

TEST(BadInput, AGantryOfPerpendicularSlidesIsWrittenAsUrdf) {
  // Found by the urdf fuzz harness: `convert --to urdf` went through POE's rows, which cannot hold a
  // prismatic axis across its parent's z, and refused this robot (without naming the file).
  TempDir dir;
  const std::string robot = dir.path("gantry.yaml");
  WriteText(robot,
            "name: gantry\nconvention: dh\nunits: {length: mm, angle: deg}\njoints:\n"
            "  - {theta: 0, d: 100, a: 0, alpha: 90, type: prismatic}\n"
            "  - {theta: 0, d: 50, a: 20, alpha: 0, type: prismatic}\n"
            "  - {theta: 0, d: 10, a: 0, alpha: 0}\n"
            "limits: [[0, 500], [0, 300], [-90, 90]]\n");
  const auto r = RunKincal("convert " + robot + " --to urdf --out " + dir.path("gantry.urdf"));
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const auto back = RunKincal("import " + dir.path("gantry.urdf") + " --base world --tip tool0 --convention dh --out " +
                              dir.path("again.yaml"));
  ASSERT_EQ(back.exit_code, 0) << back.err;
  // The same pose from both robot files (JSON: the 4x4 matrix in mm), to rounding.
  const auto fk = [&](const std::string& file) {
    const auto result = RunKincal("fk " + file + " --q=120,80,30");
    EXPECT_EQ(result.exit_code, 0) << result.err;
    std::string text = result.out.substr(0, result.out.find("units"));
    for (char& c : text) {
      if (!std::isdigit(static_cast<unsigned char>(c)) && c != '.' && c != '-' && c != 'e') c = ' ';
    }
    std::istringstream in(text);
    std::vector<double> numbers;
    for (double v; in >> v;) numbers.push_back(v);
    return numbers;
  };
  const std::vector<double> a = fk(robot), b = fk(dir.path("again.yaml"));
  ASSERT_EQ(a.size(), 16u);
  ASSERT_EQ(b.size(), a.size());
  for (size_t i = 0; i < a.size(); ++i) EXPECT_NEAR(a[i], b[i], 1e-9) << i;
}

TEST(BadInput, AUrdfWithElementsBeforeTheRobotIsWrittenBack) {
  // Found by the urdf fuzz harness: urdfdom reads the <robot> element wherever it is, the writer took
  // the document's first element and ended in map::at (status 1).
  TempDir dir;
  const std::string urdf = dir.path("robot.urdf");
  WriteText(urdf,
            "<note/>\n" + Urdf({"base_link", "a", "b"}, {Joint("j", "revolute", "base_link", "a"),
                                                         Joint("t", "fixed", "a", "b", "<origin xyz=\"0.1 0 0\"/>")}));
  const auto imported = RunKincal("import " + urdf + " --base base_link --tip b --out " + dir.path("robot.yaml"));
  ASSERT_EQ(imported.exit_code, 0) << imported.err;
  const auto written = RunKincal("convert " + dir.path("robot.yaml") + " --to urdf --out " + dir.path("back.urdf"));
  EXPECT_EQ(written.exit_code, 0) << written.err;
}

TEST(BadInput, InvalidOptionsNameTheOptionsFile) {
  TempDir dir;
  const std::string options = dir.path("options.yaml");
  const std::string data = dir.path("data.csv");
  WriteText(data, std::string(kSixJointHeader) + "0,0,0,0,0,0,1,2,3\n");
  for (const std::string& text : {std::string("max_iterations: 1e300\n"), std::string("no_such_option: 1\n"),
                                  std::string("max_iterations: [1, 2]\n"), std::string("[1, 2]\n")}) {
    WriteText(options, text);
    ExpectBadInput("identify --nominal " + Example("seed_nominal.yaml") + " --data " + data +
                       " --method least_squares --options " + options + " --out " + dir.path("out.yaml"),
                   options);
  }
  WriteText(options, "max_iterations: -1e300\n");
  WriteText(dir.path("targets.csv"), "x_mm,y_mm,z_mm\n400,0,500\n");
  ExpectBadInput("compensate --nominal " + Example("seed_nominal.yaml") + " --identified " +
                     Example("seed_identified.yaml") + " --targets " + dir.path("targets.csv") +
                     " --method jacobian --options " + options + " --out " + dir.path("out.csv"),
                 options);
}

// A value out of its range is located like a value of the wrong type: the options file, the value's line
// and column (the options' table checks the requirement as it reads, framework/options.h).
TEST(BadInput, AnOptionOutOfRangeNamesItsLineAndColumn) {
  TempDir dir;
  const std::string options = dir.path("options.yaml");
  const std::string data = dir.path("data.csv");
  WriteText(data, std::string(kSixJointHeader) + "0,0,0,0,0,0,1,2,3\n");
  WriteText(options, "loss: huber\nmax_iterations: -3\n");
  const std::string identify = "identify --nominal " + Example("seed_nominal.yaml") + " --data " + data +
                               " --method least_squares --options " + options + " --out " + dir.path("out.yaml");
  ExpectBadInput(identify, options, ": line 2, column 17: ");
  EXPECT_NE(RunKincal(identify).err.find("'max_iterations': must be >= 0, got '-3'"), std::string::npos);
  WriteText(options, "length_scale: 0.5m\nrandom_starts: 100001\n");
  WriteText(dir.path("targets.csv"), "x_mm,y_mm,z_mm\n400,0,500\n");
  ExpectBadInput("compensate --nominal " + Example("seed_nominal.yaml") + " --identified " +
                     Example("seed_identified.yaml") + " --targets " + dir.path("targets.csv") +
                     " --method jacobian --options " + options + " --out " + dir.path("out.csv"),
                 options, ": line 2, column 16: ");
}

TEST(BadInput, AMissingOrUnreadableFileIsStatusTwo) {
  TempDir dir;
  ExpectBadInput("fk " + dir.path("missing.yaml") + " --q=0", dir.path("missing.yaml"));
  ExpectBadInput("fk " + dir.path("") + " --q=0", dir.path(""));  // a folder, not a file
}

TEST(BadInput, ADeviceWithoutEndIsRefusedBeforeTheMemoryRunsOut) {
  if (!std::filesystem::exists("/dev/zero")) GTEST_SKIP() << "no /dev/zero";
  ::setenv("KINCAL_MEMORY_LIMIT_MB", "200", 1);  // reads stop at half of it
  const auto r = RunKincal("fk /dev/zero --q=0");
  ::unsetenv("KINCAL_MEMORY_LIMIT_MB");
  EXPECT_EQ(r.exit_code, 2) << r.err;
  EXPECT_EQ(LineCount(r.err), 1) << r.err;
  EXPECT_NE(r.err.find("kincal: /dev/zero: more than 104 MB and still not at its end"), std::string::npos) << r.err;
}

}  // namespace
}  // namespace kincal
