#pragma once
// Units live at the edges: files carry their units, the library works in SI (metres, radians).
#include <cmath>
#include <string>

namespace kincal {

// One degree, in radians: for the places where a format fixes degrees (robot programs, tables).
inline constexpr double kDegree = M_PI / 180.0;

struct Unit {
  std::string name;    // as written in files: "mm", "deg", ...
  double to_si = 1.0;  // SI value = file value * to_si
};

// "m", "cm", "mm", "um" (also "µm"); throws std::invalid_argument naming the accepted units.
Unit LengthUnit(const std::string& name);
// "rad", "deg".
Unit AngleUnit(const std::string& name);

// A length such as "10um", "0.01 mm" or "0.01" (then in `default_unit`), in metres.
double ParseLength(const std::string& text, const Unit& default_unit);

// Shortest decimal text t such that parse(t) * unit.to_si == si exactly, so that file -> SI -> file
// keeps every digit the file had (the robot-file round trip). Falls back to 17 significant digits.
std::string FormatInUnit(double si, const Unit& unit);

// Shortest text that parses back to exactly `value`.
std::string FormatExact(double value);

// Strict number parsing: the whole text must be a finite number.
bool ParseDouble(const std::string& text, double* value);

}  // namespace kincal
