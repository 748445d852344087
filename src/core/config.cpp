#include "plumetrace/core/config.hpp"

#include <cstdio>
#include <cstdlib>

namespace plumetrace {

std::string format_number(double value) {
  if (std::isinf(value)) return value > 0 ? "inf" : "-inf";
  if (value == 0.0) return "0.0";
  char buf[40];
  for (int precision = 15; precision <= 17; ++precision) {
    std::snprintf(buf, sizeof buf, "%.*g", precision, value);
    if (std::strtod(buf, nullptr) == value) break;
  }
  std::string s(buf);
  // keep it a float in TOML: 25 -> 25.0
  if (s.find_first_of(".eEn") == std::string::npos) s += ".0";
  return s;
}

std::string bound_text(double value) {
  char buf[40];
  std::snprintf(buf, sizeof buf, "%g", value);
  std::string s(buf);
  const auto e = s.find('e');
  if (e == std::string::npos) return s;
  // 1e+07 -> 1e7, 1.3e-06 -> 1.3e-6
  std::string exponent = s.substr(e + 1);
  const bool negative = exponent[0] == '-';
  exponent.erase(0, exponent.find_first_not_of("+-0"));
  return s.substr(0, e + 1) + (negative ? "-" : "") + exponent;
}

std::string format_value(const ConfigValue& value) {
  if (const auto* d = std::get_if<double>(&value)) return format_number(*d);
  if (const auto* i = std::get_if<std::int64_t>(&value)) return std::to_string(*i);
  if (const auto* b = std::get_if<bool>(&value)) return *b ? "true" : "false";
  return "'" + std::get<std::string>(value) + "'";
}

}  // namespace plumetrace
