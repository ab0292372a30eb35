// Rigid-transform helpers (roll-pitch-yaw, rotation log/exp) and unit conversion at the file edges.
#include <cmath>
#include <cstdio>
#include <limits>

#include <gtest/gtest.h>

#include "framework/math.h"
#include "framework/random.h"
#include "framework/units.h"

namespace kincal {
namespace {

double MaxAbs(const Eigen::Matrix3d& m) { return m.cwiseAbs().maxCoeff(); }

TEST(Math, RpyIsRollThenPitchThenYawAboutFixedAxes) {
  const Eigen::Vector3d rpy(0.3, -0.2, 1.1);
  const Eigen::Matrix3d expected = Eigen::AngleAxisd(1.1, Eigen::Vector3d::UnitZ()).toRotationMatrix() *
                                   Eigen::AngleAxisd(-0.2, Eigen::Vector3d::UnitY()).toRotationMatrix() *
                                   Eigen::AngleAxisd(0.3, Eigen::Vector3d::UnitX()).toRotationMatrix();
  EXPECT_LT(MaxAbs(RotationFromRpy(rpy) - expected), 1e-15);
  // URDF's example: a quarter turn of yaw maps x onto y.
  EXPECT_LT((RotationFromRpy({0, 0, M_PI / 2}) * Eigen::Vector3d::UnitX() - Eigen::Vector3d::UnitY()).norm(), 1e-15);
}

TEST(Math, RpyRoundTripAwayFromGimbalLock) {
  Rng rng(1);
  for (int i = 0; i < 1000; ++i) {
    const Eigen::Vector3d rpy(rng.Uniform(-M_PI, M_PI), rng.Uniform(-1.5, 1.5), rng.Uniform(-M_PI, M_PI));
    const Eigen::Vector3d back = RpyFromRotation(RotationFromRpy(rpy));
    EXPECT_LT((back - rpy).cwiseAbs().maxCoeff(), 1e-13) << rpy.transpose();
  }
}

TEST(Math, RpyReproducesTheRotationNearAndAtGimbalLock) {
  // Near pitch = +-90 deg roll and yaw are nearly interchangeable and each alone is ill-determined, but
  // the rotation they give back must still be the rotation we started from, to the last digits.
  Rng rng(2);
  for (double offset : {0.0, 1e-15, 1e-12, 1e-9, 1e-6, 1e-3}) {
    for (double sign : {1.0, -1.0}) {
      for (int i = 0; i < 50; ++i) {
        const Eigen::Vector3d rpy(rng.Uniform(-M_PI, M_PI), sign * (M_PI / 2 - offset), rng.Uniform(-M_PI, M_PI));
        const Eigen::Matrix3d R = RotationFromRpy(rpy);
        const Eigen::Vector3d back = RpyFromRotation(R);
        EXPECT_LT(MaxAbs(RotationFromRpy(back) - R), 4e-16 * 8) << "offset " << offset << ", rpy " << rpy.transpose();
        EXPECT_LE(std::abs(back.y()), M_PI / 2);
      }
    }
  }
}

TEST(Math, RpyAtExactGimbalLockPutsTheTurnIntoYaw) {
  for (double sign : {1.0, -1.0}) {
    Eigen::Matrix3d Ry;  // Ry(+-90 deg) with exact zeros
    Ry << 0, 0, sign, 0, 1, 0, -sign, 0, 0;
    const Eigen::Matrix3d R = Eigen::AngleAxisd(0.3, Eigen::Vector3d::UnitZ()).toRotationMatrix() * Ry;
    const Eigen::Vector3d rpy = RpyFromRotation(R);
    EXPECT_EQ(rpy.x(), 0.0);
    EXPECT_EQ(rpy.y(), sign * M_PI / 2);
    EXPECT_NEAR(rpy.z(), 0.3, 1e-16);
    EXPECT_LT(MaxAbs(RotationFromRpy(rpy) - R), 1e-15);
  }
}

TEST(Math, RotationLogAndExpAreInversesIncludingNearZeroAndPi) {
  Rng rng(3);
  for (double angle : {0.0, 1e-300, 1e-12, 1e-8, 0.5, 2.0, M_PI - 1e-6, M_PI - 1e-10, M_PI}) {
    for (int i = 0; i < 20; ++i) {
      const Eigen::Vector3d axis = Eigen::Vector3d(rng.Normal(), rng.Normal(), rng.Normal()).normalized();
      const Eigen::Vector3d omega = axis * angle;
      const Eigen::Matrix3d R = RotationExp(omega);
      EXPECT_LT(MaxAbs(R.transpose() * R - Eigen::Matrix3d::Identity()), 1e-15);
      const Eigen::Vector3d back = RotationLog(R);
      EXPECT_NEAR(back.norm(), angle, 4e-16 * std::max(1.0, angle)) << "angle " << angle;
      // At exactly pi, axis and -axis are the same rotation; compare rotations there.
      EXPECT_LT(MaxAbs(RotationExp(back) - R), 1e-15) << "angle " << angle;
      if (angle < M_PI - 1e-3) {
        EXPECT_LT((back - omega).norm(), 1e-15 * std::max(1.0, angle)) << "angle " << angle;
      }
    }
  }
  // Tiny rotations keep their relative precision: log(exp(w)) = w for |w| = 1e-12.
  const Eigen::Vector3d tiny(3e-13, -4e-13, 0.0);
  EXPECT_LT((RotationLog(RotationExp(tiny)) - tiny).norm(), 1e-27);
}

TEST(Math, PoseErrorMatchesTheJacobianLayout) {
  const Eigen::Isometry3d from = PoseFromXyzRpy({0.1, 0.2, 0.3}, {0.1, -0.2, 0.3});
  const Eigen::Vector3d dp(1e-3, -2e-3, 5e-4), dw(2e-4, 1e-4, -3e-4);
  Eigen::Isometry3d to = from;
  to.translation() += dp;
  to.linear() = RotationExp(dw) * from.linear();
  const Vector6d e = PoseError(from, to);
  EXPECT_LT((e.head<3>() - dp).norm(), 1e-17);
  EXPECT_LT((e.tail<3>() - dw).norm(), 1e-16);
  EXPECT_NEAR(RotationAngleBetween(from.linear(), to.linear()), dw.norm(), 1e-16);
}

TEST(Math, WrapAngle) {
  EXPECT_DOUBLE_EQ(WrapAngle(3 * M_PI / 2), -M_PI / 2);
  EXPECT_DOUBLE_EQ(WrapAngle(-3 * M_PI / 2), M_PI / 2);
  EXPECT_DOUBLE_EQ(WrapAngle(M_PI), M_PI);
  EXPECT_DOUBLE_EQ(WrapAngle(-M_PI), M_PI);  // (-pi, pi]
  EXPECT_DOUBLE_EQ(WrapAngle(0.25), 0.25);
}

TEST(Math, SkewIsTheCrossProduct) {
  const Eigen::Vector3d a(1, -2, 3), b(0.5, 4, -1);
  EXPECT_EQ(Skew(a) * b, a.cross(b));
}

// ---- Units ---------------------------------------------------------------------------------------

TEST(Units, KnownUnitsAndTheirErrors) {
  EXPECT_EQ(LengthUnit("mm").to_si, 1e-3);
  EXPECT_EQ(LengthUnit("um").to_si, 1e-6);
  EXPECT_EQ(LengthUnit("\xC2\xB5m").name, "um");
  EXPECT_EQ(AngleUnit("deg").to_si, M_PI / 180.0);
  try {
    LengthUnit("inch");
    FAIL();
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("expected m, cm, mm or um"), std::string::npos);
  }
  EXPECT_THROW(AngleUnit("grad"), std::invalid_argument);
}

TEST(Units, ParseLengthWithAndWithoutUnit) {
  const Unit mm = LengthUnit("mm");
  EXPECT_DOUBLE_EQ(ParseLength("10um", mm), 10e-6);
  EXPECT_DOUBLE_EQ(ParseLength("0.05 mm", mm), 0.05e-3);
  EXPECT_DOUBLE_EQ(ParseLength("0.01", mm), 0.01e-3);
  EXPECT_DOUBLE_EQ(ParseLength("1e-3m", mm), 1e-3);
  EXPECT_DOUBLE_EQ(ParseLength("2cm", mm), 0.02);
  EXPECT_THROW(ParseLength("ten", mm), std::invalid_argument);
  EXPECT_THROW(ParseLength("10 furlongs", mm), std::invalid_argument);
  EXPECT_THROW(ParseLength("", mm), std::invalid_argument);
}

TEST(Units, ParseDoubleIsStrict) {
  double v = 0.0;
  EXPECT_TRUE(ParseDouble(" 12.5 ", &v));
  EXPECT_EQ(v, 12.5);
  EXPECT_TRUE(ParseDouble("+3", &v));
  EXPECT_EQ(v, 3.0);
  EXPECT_TRUE(ParseDouble("-1e-7", &v));
  EXPECT_EQ(v, -1e-7);
  for (const char* bad : {"", "  ", "nan", "inf", "-inf", "1e999", "12abc", "1,5", "0x10", ".nan", "1 2"}) {
    EXPECT_FALSE(ParseDouble(bad, &v)) << "'" << bad << "'";
  }
}

TEST(Units, FormatExactIsTheShortestRoundTrip) {
  EXPECT_EQ(FormatExact(0.1), "0.1");
  EXPECT_EQ(FormatExact(-2.0), "-2");
  EXPECT_EQ(FormatExact(1e-7), "1e-07");
  EXPECT_EQ(FormatExact(0.1 + 0.2), "0.30000000000000004");
  Rng rng(4);
  for (int i = 0; i < 10000; ++i) {
    const double x = std::ldexp(rng.Uniform(-1, 1), static_cast<int>(rng.Uniform(-60, 60)));
    double back = 0.0;
    ASSERT_TRUE(ParseDouble(FormatExact(x), &back));
    EXPECT_EQ(back, x);
  }
}

TEST(Units, FormatInUnitGivesTheFilesDecimalBack) {
  // The decimals people write: reading them and writing them back gives the same text.
  const char* decimals[] = {"0",
                            "1",
                            "-2.11",
                            "247.5",
                            "291.53",
                            "0.06",
                            "89.98",
                            "-90.09",
                            "4815.6",
                            "1e-05",
                            "0.1",
                            "0.3",
                            "1000.1",
                            "123456.789",
                            "-0.0203",
                            "7.00000000000001",
                            "33.3333333333333"};
  for (const char* unit_name : {"mm", "m", "cm", "um", "deg", "rad"}) {
    const Unit unit = (std::string(unit_name) == "deg" || std::string(unit_name) == "rad") ? AngleUnit(unit_name)
                                                                                           : LengthUnit(unit_name);
    for (const char* text : decimals) {
      double v = 0.0;
      ASSERT_TRUE(ParseDouble(text, &v));
      EXPECT_EQ(FormatInUnit(v * unit.to_si, unit), FormatExact(v)) << text << " " << unit_name;
    }
  }
}

TEST(Units, FormatInUnitIsExactForEveryValueThatCameFromAFile) {
  // Any double read from a file in a unit (17 significant digits, all exponents) writes back to a text
  // that reads to the same SI bits.
  Rng rng(5);
  for (const char* unit_name : {"mm", "um", "cm", "deg"}) {
    const Unit unit = std::string(unit_name) == "deg" ? AngleUnit(unit_name) : LengthUnit(unit_name);
    for (int i = 0; i < 20000; ++i) {
      char text[40];
      std::snprintf(text, sizeof(text), "%.17g",
                    std::ldexp(rng.Uniform(-1, 1), static_cast<int>(rng.Uniform(-30, 30))));
      double v = 0.0;
      ASSERT_TRUE(ParseDouble(text, &v));
      const double si = v * unit.to_si;
      double back = 0.0;
      ASSERT_TRUE(ParseDouble(FormatInUnit(si, unit), &back));
      EXPECT_EQ(back * unit.to_si, si) << text << " " << unit_name;
    }
  }
}

}  // namespace
}  // namespace kincal
