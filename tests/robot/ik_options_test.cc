// The inverse kinematics' options declared once (NominalIkOptions::Table, InverseKinematicsOptions::Table):
// a file sets every key (units, the numeric map, the configuration), an empty one gives the defaults, a
// bad value names its line and column, IsValid applies the same requirements to values set in code, and
// the documentation lists every key with its default.
#include <string>

#include <gtest/gtest.h>

#include "robot/nominal_ik.h"

namespace kincal {
namespace {

TEST(IkOptions, AFileSetsEveryKeyAndNoFileGivesTheDefaults) {
  const NominalIkOptions defaults;
  const NominalIkOptions none = NominalIkOptions::Table().Read(YAML::Node());
  EXPECT_EQ(none.position_tolerance, defaults.position_tolerance);
  EXPECT_EQ(none.singular_ratio, defaults.singular_ratio);
  EXPECT_EQ(none.numeric.restarts, defaults.numeric.restarts);
  EXPECT_TRUE(none.configuration.empty());

  const NominalIkOptions o = NominalIkOptions::Table().Read(YAML::Load(R"(
position_tolerance: 2um
orientation_tolerance: 3e-9
distance_tolerance: 0.5um
direction_tolerance: 4e-9
singular_ratio: 1e-5
configuration: [0, 0, 1, 0, -1, 0]
use_closed_form: false
numeric:
  max_iterations: 50
  stall_iterations: 7
  restarts: 3
  position_tolerance: 0.001um
  orientation_tolerance: 2e-10
  damping: 1e-5
  length_scale: 500mm
  seed: 9
)"));
  EXPECT_DOUBLE_EQ(o.position_tolerance, 2e-6);
  EXPECT_DOUBLE_EQ(o.orientation_tolerance, 3e-9);
  EXPECT_DOUBLE_EQ(o.distance_tolerance, 0.5e-6);
  EXPECT_DOUBLE_EQ(o.direction_tolerance, 4e-9);
  EXPECT_DOUBLE_EQ(o.singular_ratio, 1e-5);
  EXPECT_EQ(o.configuration, (std::vector<int>{0, 0, 1, 0, -1, 0}));
  EXPECT_FALSE(o.use_closed_form);
  EXPECT_EQ(o.numeric.max_iterations, 50);
  EXPECT_EQ(o.numeric.stall_iterations, 7);
  EXPECT_EQ(o.numeric.restarts, 3);
  EXPECT_DOUBLE_EQ(o.numeric.position_tolerance, 1e-9);
  EXPECT_DOUBLE_EQ(o.numeric.orientation_tolerance, 2e-10);
  EXPECT_DOUBLE_EQ(o.numeric.damping, 1e-5);
  EXPECT_DOUBLE_EQ(o.numeric.length_scale, 0.5);
  EXPECT_EQ(o.numeric.seed, 9u);
  std::string why;
  EXPECT_TRUE(o.IsValid(&why)) << why;
}

TEST(IkOptions, BadValuesNameTheirLineAndColumn) {
  const std::vector<std::pair<std::string, std::string>> cases = {
      {"singular_ratio: 1\n", "line 1, column 17:"},
      {"use_closed_form: true\nposition_tolerance: -1e-9\n", "line 2, column 21:"},
      {"configuration: [1, 0.5]\n", "line 1, column 16:"},
      {"numeric:\n  seed: -1\n", "line 2, column 9:"},
      {"numeric:\n  max_iterations: 0\n", "line 2, column 19:"},
      {"numeric:\n  restart: 3\n", "line 2, column 12:"},
      {"numeric: 3\n", "line 1, column 10:"},
      {"direction_tolerance: [1]\n", "line 1, column 22:"},
  };
  for (const auto& [text, where] : cases) {
    try {
      NominalIkOptions::Table().Read(YAML::Load(text));
      ADD_FAILURE() << "accepted: " << text;
    } catch (const std::invalid_argument& e) {
      EXPECT_NE(std::string(e.what()).find(where), std::string::npos) << text << " -> " << e.what();
    }
  }
}

TEST(IkOptions, IsValidAppliesTheTablesRequirementsToValuesSetInCode) {
  NominalIkOptions o;
  std::string why;
  EXPECT_TRUE(o.IsValid(&why)) << why;
  o.singular_ratio = 1.0;
  EXPECT_FALSE(o.IsValid(&why));
  EXPECT_NE(why.find("singular_ratio"), std::string::npos) << why;
  o = NominalIkOptions();
  o.configuration = {0, 2, 0, 0, 0, 0};
  EXPECT_FALSE(o.IsValid(&why));
  EXPECT_NE(why.find("configuration"), std::string::npos) << why;
  o = NominalIkOptions();
  o.numeric.stall_iterations = 0;
  EXPECT_FALSE(o.IsValid(&why));
  EXPECT_NE(why.find("numeric: stall_iterations"), std::string::npos) << why;
  o = NominalIkOptions();
  o.distance_tolerance = NAN;
  EXPECT_FALSE(o.IsValid(&why));
  EXPECT_NE(why.find("distance_tolerance"), std::string::npos) << why;
  InverseKinematicsOptions n;
  n.length_scale = 0.0;
  EXPECT_FALSE(n.IsValid(&why));
  EXPECT_NE(why.find("length_scale"), std::string::npos) << why;
}

TEST(IkOptions, DocumentationListsEveryKeyWithItsDefault) {
  const std::vector<OptionDoc> docs = NominalIkOptions::Table().Docs();
  std::vector<std::string> keys;
  for (const OptionDoc& d : docs) keys.push_back(d.key);
  EXPECT_EQ(keys, (std::vector<std::string>{"position_tolerance", "orientation_tolerance", "distance_tolerance",
                                            "direction_tolerance", "singular_ratio", "configuration", "use_closed_form",
                                            "numeric"}));
  EXPECT_EQ(docs[0].default_value, "1e-09 m");
  EXPECT_EQ(docs[4].default_value, "1e-06");
  const std::vector<OptionDoc> numeric = InverseKinematicsOptions::Table().Docs();
  ASSERT_EQ(numeric.size(), 8u);
  EXPECT_EQ(numeric[2].key, "restarts");
  EXPECT_EQ(numeric[2].default_value, "100");
  for (const OptionDoc& d : numeric) EXPECT_FALSE(d.doc.empty()) << d.key;
}

}  // namespace
}  // namespace kincal
