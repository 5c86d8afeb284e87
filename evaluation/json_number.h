#pragma once
// The one way evaluation output writes a double into JSON. JSON has no NaN or infinity, and
// the metrics use NaN for "no value" (an accuracy without samples, a ratio over zero area), so
// a non-finite number becomes null, which readers (docs/evaluation.md) take as "not defined".

#include <cmath>
#include <nlohmann/json.hpp>

namespace mopad::evaluation {

/// `x` as a JSON number, or null when it is NaN or infinite. `Json` is the document type it
/// goes into: nlohmann::json, or nlohmann::ordered_json where key order is kept.
template <class Json = nlohmann::json>
Json Num(double x) {
  return std::isfinite(x) ? Json(x) : Json(nullptr);
}

}  // namespace mopad::evaluation
