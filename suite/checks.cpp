#include "suite/checks.h"

#include <cmath>
#include <regex>

#include "common/error.h"
#include "common/format.h"

namespace mopad::suite {

namespace {

// Unit suffixes of a bound and their factor to SI.
const std::map<std::string, double> kUnits = {{"m", 1.0},   {"cm", 0.01}, {"mm", 0.001},
                                              {"deg", 1.0}, {"s", 1.0},   {"%", 0.01}};

}  // namespace

Check ParseCheck(const std::string& text, const std::string& where) {
  static const std::regex form(
      R"(^\s*(?:(mean|min|max)\(\s*([A-Za-z0-9_.\-]+)\s*\)|([A-Za-z0-9_.\-]+))\s*(>=|<=|==|!=|>|<)\s*([^\s]+)\s*([A-Za-z%]*)\s*$)");
  std::smatch m;
  const std::string expected =
      "FIGURE OP BOUND [UNIT] or mean|min|max(FIGURE) OP BOUND [UNIT], OP one of >= <= > < == !=";
  if (!std::regex_match(text, m, form)) throw InputError(where, "bad check", "'" + text + "'", expected);
  Check c;
  c.text = text;
  c.stat = m[1];
  c.figure = m[1].matched ? m[2].str() : m[3].str();
  c.op = m[4];
  const std::string bound = m[5], unit = m[6];
  if (!unit.empty() && !kUnits.count(unit))
    throw InputError(where, "unknown unit in check '" + text + "'", unit, "m, cm, mm, deg, s or %");
  char* end = nullptr;
  const double v = std::strtod(bound.c_str(), &end);
  if (end != nullptr && *end == '\0' && !bound.empty()) {
    if (!std::isfinite(v)) throw InputError(where, "bound not finite in check '" + text + "'");
    c.bound = v * (unit.empty() ? 1.0 : kUnits.at(unit));
  } else {
    if (!std::regex_match(bound, std::regex(R"([A-Za-z_][A-Za-z0-9_.\-]*)")))
      throw InputError(where, "bad bound in check '" + text + "'", bound, "a number or a figure");
    if (!c.stat.empty())
      throw InputError(where, "a pooled check's bound must be a number", "'" + text + "'");
    if (!unit.empty())
      throw InputError(where, "a figure bound takes no unit", "'" + text + "'");
    c.bound_figure = bound;
  }
  return c;
}

bool Compare(double value, const std::string& op, double bound) {
  if (op == ">=") return value >= bound;
  if (op == "<=") return value <= bound;
  if (op == ">") return value > bound;
  if (op == "<") return value < bound;
  if (op == "==") return value == bound;
  return value != bound;
}

CheckResult Evaluate(const Check& check, const Figures& figures) {
  CheckResult r;
  r.check = &check;
  if (auto it = figures.find(check.figure); it != figures.end()) r.value = it->second;
  if (check.bound_figure.empty()) {
    r.bound = check.bound;
  } else if (auto b = figures.find(check.bound_figure); b != figures.end()) {
    r.bound = b->second;
  }
  r.passed = r.value && r.bound && Compare(*r.value, check.op, *r.bound);
  return r;
}

std::string Describe(const CheckResult& r) {
  const Check& c = *r.check;
  std::string s = "check '" + c.text + "': ";
  if (!r.value) return s + "figure " + c.figure + " missing";
  if (!r.bound) return s + "figure " + c.bound_figure + " missing";
  return s + FormatShortest(*r.value) + (r.passed ? " " : " not ") + c.op + " " +
         FormatShortest(*r.bound);
}

}  // namespace mopad::suite
