#include "suite/pooled.h"

#include <algorithm>
#include <cmath>
#include <map>

namespace mopad::suite {

std::vector<std::string> Groups(const std::vector<CaseResult>& cases) {
  std::vector<std::string> out;
  for (const auto& c : cases)
    if (std::find(out.begin(), out.end(), c.group) == out.end()) out.push_back(c.group);
  return out;
}

std::vector<PooledFigure> Pool(const std::vector<CaseResult>& cases) {
  std::vector<PooledFigure> out;
  for (const std::string& g : Groups(cases)) {
    std::map<std::string, std::vector<double>> values;  // in case order
    for (const auto& c : cases)
      if (c.group == g)
        for (const auto& [f, v] : c.figures) values[f].push_back(v);
    for (const auto& [f, v] : values) {
      PooledFigure p;
      p.group = g;
      p.figure = f;
      p.n = static_cast<int>(v.size());
      double sum = 0.0;
      for (double x : v) sum += x;
      p.mean = sum / p.n;
      double ss = 0.0;
      for (double x : v) ss += (x - p.mean) * (x - p.mean);
      p.sd = p.n > 1 ? std::sqrt(ss / (p.n - 1)) : 0.0;
      p.min = *std::min_element(v.begin(), v.end());
      p.max = *std::max_element(v.begin(), v.end());
      out.push_back(p);
    }
  }
  return out;
}

std::vector<CheckOutcome> PooledChecks(const Manifest& m, const std::vector<PooledFigure>& pooled,
                                       const std::vector<std::string>& groups) {
  std::vector<CheckOutcome> out;
  for (const std::string& g : groups) {
    for (const Check& c : m.pooled_checks) {
      Figures stat;
      for (const auto& p : pooled)
        if (p.group == g && p.figure == c.figure)
          stat[c.figure] = c.stat == "mean" ? p.mean : c.stat == "min" ? p.min : p.max;
      CheckOutcome o = ToOutcome(Evaluate(c, stat));
      o.group = g;
      o.stat = c.stat;
      out.push_back(o);
    }
  }
  return out;
}

}  // namespace mopad::suite
