// A study's model whose held-out RMS exceeds the geometry row's on the same data by more than half is
// flagged (studies/results_files.h FlagWorseThanGeometry); rows of other data, other trials, compensated
// rows and rows already not ok are left as they are.
#include <gtest/gtest.h>

#include "studies/results_files.h"

namespace kincal {
namespace {

ResultTable Table(const std::vector<std::vector<std::string>>& rows) {
  ResultTable t;
  t.header = {"dataset", "knob", "knob_value", "trial", "estimator", "compensator", "validation",
              "position_error_rms_mm", "status", "note"};
  t.rows = rows;
  return t;
}

TEST(HeldoutFlag, AModelAboveHalfAgainGeometrysRmsIsNotOk) {
  ResultTable t = Table({
      {"d", "", "", "0", "none", "-", "heldout", "0.9", "ok", ""},
      {"d", "", "", "0", "geometry", "-", "heldout", "0.5", "ok", ""},
      {"d", "", "", "0", "rich", "-", "heldout", "0.76", "ok", ""},       // 1.52 x: flagged
      {"d", "", "", "0", "fair", "-", "heldout", "0.74", "ok", ""},       // 1.48 x: ok
      {"d", "", "", "1", "geometry", "-", "heldout", "1.0", "ok", ""},
      {"d", "", "", "1", "rich", "-", "heldout", "1.2", "ok", ""},        // its own trial's geometry: ok
      {"e", "", "", "0", "rich", "-", "heldout", "9.0", "ok", ""},        // no geometry row for e: unchecked
      {"d", "", "", "0", "rich", "jacobian", "heldout", "9.0", "ok", ""}, // compensated: not the model's row
      {"d", "", "", "0", "diverged", "-", "heldout", "9.0", "estimate_failed", "x"},
  });
  FlagWorseThanGeometry(&t);
  const int status = t.Column("status"), note = t.Column("note");
  EXPECT_EQ(t.rows[2][status], "heldout_worse_than_geometry");
  EXPECT_NE(t.rows[2][note].find("1.52 x the geometry row's (0.5 mm)"), std::string::npos) << t.rows[2][note];
  for (int r : {0, 1, 3, 4, 5, 6, 7}) EXPECT_EQ(t.rows[r][status], "ok") << r;
  EXPECT_EQ(t.rows[8][status], "estimate_failed");
  EXPECT_EQ(t.rows[8][note], "x");
}

}  // namespace
}  // namespace kincal
