#include "suite/outputs.h"

#include <filesystem>
#include <set>

#include "common/format.h"
#include "io/text_file.h"
#include "suite/figures.h"
#include "suite/scoreboard.h"

namespace mopad::suite {

namespace fs = std::filesystem;

SuiteSummary Summarise(const Manifest& m, const std::vector<CaseResult>& cases) {
  SuiteSummary s;
  s.pooled = Pool(cases);
  s.pooled_checks = PooledChecks(m, s.pooled, Groups(cases));
  s.totals["cases"] = static_cast<int>(cases.size());
  for (const char* v : kVerdicts) s.totals[v] = 0;
  for (const auto& c : cases) ++s.totals[c.verdict];
  s.all_passed = s.totals["passed"] == s.totals["cases"];
  for (const auto& p : s.pooled_checks) s.all_passed &= p.passed;
  return s;
}

nlohmann::ordered_json SuiteJson(const Manifest& m, const std::vector<CaseResult>& cases,
                                 const SuiteSummary& s) {
  nlohmann::ordered_json j;
  j["format"] = "mopad-suite";
  j["version"] = 1;
  j["suite"] = m.name;
  j["manifest"] = m.path;
  // Every figure a case or check names: its direction and unit.
  std::set<std::string> names;
  for (const auto& f : MainFigures()) names.insert(f.name);
  for (const auto& c : cases)
    for (const auto& [k, v] : c.figures) names.insert(k);
  nlohmann::ordered_json info = nlohmann::ordered_json::object();
  auto add = [&](const FigureInfo& f) {
    info[f.name] = {{"better", f.better}, {"unit", f.unit}, {"label", f.label}};
  };
  for (const auto& f : MainFigures()) add(f);
  for (const auto& n : names)
    if (!info.contains(n)) add(InfoOf(n));
  j["figure_info"] = info;
  j["cases"] = nlohmann::ordered_json::array();
  for (const auto& c : cases) j["cases"].push_back(ToJson(c));
  j["pooled"] = nlohmann::ordered_json::array();
  for (const auto& p : s.pooled)
    j["pooled"].push_back({{"group", p.group},
                           {"figure", p.figure},
                           {"n", p.n},
                           {"mean", p.mean},
                           {"sd", p.sd},
                           {"min", p.min},
                           {"max", p.max}});
  j["pooled_checks"] = nlohmann::ordered_json::array();
  for (const auto& p : s.pooled_checks) j["pooled_checks"].push_back(ToJson(p));
  nlohmann::ordered_json totals;
  totals["cases"] = s.totals.at("cases");
  for (const char* v : kVerdicts) totals[v] = s.totals.at(v);
  j["totals"] = totals;
  return j;
}

std::string XmlEscape(const std::string& s) {
  std::string out;
  for (unsigned char ch : s) {
    switch (ch) {
      case '&': out += "&amp;"; break;
      case '<': out += "&lt;"; break;
      case '>': out += "&gt;"; break;
      case '"': out += "&quot;"; break;
      case '\'': out += "&apos;"; break;
      default:
        if (ch < 0x20 && ch != '\n' && ch != '\t') out += ' ';
        else out += static_cast<char>(ch);
    }
  }
  return out;
}

std::string JunitXml(const Manifest& m, const std::vector<CaseResult>& cases,
                     const SuiteSummary& s) {
  const int failures = s.totals.at("failed");
  const int errors = s.totals.at("error") + s.totals.at("timeout") + s.totals.at("crashed");
  double time = 0.0;
  for (const auto& c : cases) time += c.wall_s;
  std::string x = "<?xml version=\"1.0\" encoding=\"UTF-8\"?>\n";
  const std::string counts = " tests=\"" + std::to_string(cases.size()) + "\" failures=\"" +
                             std::to_string(failures) + "\" errors=\"" + std::to_string(errors) +
                             "\"";
  x += "<testsuites name=\"" + XmlEscape(m.name) + "\"" + counts + " time=\"" +
       FormatFixed(time, 3) + "\">\n";
  x += "  <testsuite name=\"" + XmlEscape(m.name) + "\"" + counts + " skipped=\"0\" time=\"" +
       FormatFixed(time, 3) + "\">\n";
  for (const auto& c : cases) {
    // classname: the group with dots (CI servers group by it); name: the seed.
    std::string cls = m.name + "." + c.group;
    for (char& ch : cls)
      if (ch == '/') ch = '.';
    x += "    <testcase classname=\"" + XmlEscape(cls) + "\" name=\"" + XmlEscape(c.id) +
         "\" time=\"" + FormatFixed(c.wall_s, 3) + "\"";
    if (c.verdict == "passed") {
      x += "/>\n";
      continue;
    }
    x += ">\n";
    const std::string tag = c.verdict == "failed" ? "failure" : "error";
    std::string body;
    for (const auto& k : c.checks)
      body += std::string(k.passed ? "pass" : "FAIL") + ": " + k.check + " (value " +
              (k.value ? FormatShortest(*k.value) : "null") + ", bound " +
              (k.bound ? FormatShortest(*k.bound) : "null") + ")\n";
    body += "folder: " + c.dir + "\n";
    x += "      <" + tag + " type=\"" + c.verdict + "\" message=\"" + XmlEscape(c.message) +
         "\">" + XmlEscape(body) + "</" + tag + ">\n";
    x += "    </testcase>\n";
  }
  x += "  </testsuite>\n</testsuites>\n";
  return x;
}

SuiteSummary WriteSuiteOutputs(const std::string& dir, const Manifest& m,
                               const std::vector<CaseResult>& cases) {
  const SuiteSummary s = Summarise(m, cases);
  const fs::path d(dir);
  io::WriteFileAtomically((d / "suite.json").string(), SuiteJson(m, cases, s).dump(1) + "\n");
  io::WriteFileAtomically((d / "junit.xml").string(), JunitXml(m, cases, s));
  io::WriteFileAtomically((d / "scoreboard.md").string(), ScoreboardMarkdown(m, cases, s));
  io::WriteFileAtomically((d / "scoreboard.html").string(), ScoreboardHtml(m, cases, s));
  return s;
}

}  // namespace mopad::suite
