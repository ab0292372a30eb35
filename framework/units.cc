#include "framework/units.h"

#include <charconv>
#include <cmath>
#include <cstdio>
#include <stdexcept>

#include "framework/error.h"

namespace kincal {

Unit LengthUnit(const std::string& name) {
  if (name == "m") return {"m", 1.0};
  if (name == "cm") return {"cm", 1e-2};
  if (name == "mm") return {"mm", 1e-3};
  if (name == "um" || name == "\xC2\xB5m") return {"um", 1e-6};
  ThrowInputError("unknown length unit '" + name + "' (expected m, cm, mm or um)");
}

Unit AngleUnit(const std::string& name) {
  if (name == "rad") return {"rad", 1.0};
  if (name == "deg") return {"deg", M_PI / 180.0};
  ThrowInputError("unknown angle unit '" + name + "' (expected rad or deg)");
}

bool ParseDouble(const std::string& text, double* value) {
  size_t begin = text.find_first_not_of(" \t\r");
  size_t end = text.find_last_not_of(" \t\r");
  if (begin == std::string::npos) return false;
  const char* first = text.data() + begin;
  const char* last = text.data() + end + 1;
  if (*first == '+') ++first;
  double v = 0.0;
  auto [ptr, ec] = std::from_chars(first, last, v);
  if (ec != std::errc() || ptr != last || !std::isfinite(v)) return false;
  *value = v;
  return true;
}

double ParseLength(const std::string& text, const Unit& default_unit) {
  size_t split = text.find_first_not_of("0123456789.eE+- \t");
  // "1e-3m": an 'e' followed by a unit letter is ambiguous only for "em", which is not a unit.
  std::string number = text.substr(0, split);
  std::string unit = split == std::string::npos ? "" : text.substr(split);
  while (!unit.empty() && unit.back() == ' ') unit.pop_back();
  double value = 0.0;
  if (!ParseDouble(number, &value)) {
    ThrowInputError("expected a length such as '0.01', '10um' or '0.05mm', got '" + text + "'");
  }
  const Unit u = unit.empty() ? default_unit : LengthUnit(unit);
  return value * u.to_si;
}

std::string FormatExact(double value) {
  // The shortest digits that read back to `value`, written the way people write numbers (as Python's
  // repr does): positional for decimal exponents -5 < e < 16 ("0.0001", "20000"), scientific otherwise
  // ("1e-05"). std::to_chars alone picks whichever text is shorter, which turns 0.0001 into "1e-04".
  if (value == 0.0) value = 0.0;  // no "-0" in files
  // Writers refuse non-finite values before they get here; should one slip through, it is written as
  // text that every kincal reader refuses (never as a number).
  if (std::isnan(value)) return "nan";
  if (std::isinf(value)) return value > 0 ? "inf" : "-inf";
  char buffer[400];  // fixed notation of 1e15 needs 16 digits, of 1e-5 (shortest) 7 characters
  const std::to_chars_result scientific =
      std::to_chars(buffer, buffer + sizeof(buffer), value, std::chars_format::scientific);
  const std::string text(buffer, scientific.ptr);
  const int exponent = std::stoi(text.substr(text.find('e') + 1));
  if (value != 0.0 && (exponent <= -5 || exponent >= 16)) return text;
  const std::to_chars_result fixed = std::to_chars(buffer, buffer + sizeof(buffer), value, std::chars_format::fixed);
  return std::string(buffer, fixed.ptr);
}

std::string FormatInUnit(double si, const Unit& unit) {
  if (unit.to_si == 1.0) return FormatExact(si);
  const double in_unit = si / unit.to_si;
  for (int precision = 1; precision <= 17; ++precision) {
    // std::to_chars with a precision writes what printf's "%.*g" writes (the standard says so), several
    // times faster than glibc's printf: a million predicted rows are six million of these searches.
    char buffer[64];
    const std::to_chars_result end =
        std::to_chars(buffer, buffer + sizeof(buffer), in_unit, std::chars_format::general, precision);
    double parsed = 0.0;
    if (ParseDouble(std::string(buffer, end.ptr), &parsed) && parsed * unit.to_si == si) return FormatExact(parsed);
  }
  // No decimal maps back exactly (rare); the nearest 17-digit value is within one ulp.
  return FormatExact(in_unit);
}

}  // namespace kincal
