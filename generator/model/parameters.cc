// The `parameters` section: named numbers, the defaults of the generated Params struct.
// A parameter is `name: 1.5` or `name: {value: 1.5, doc: ...}` (ParameterKeys).
#include <cmath>
#include <cstdlib>

#include "model/reader.h"

namespace mechgen {

const KeyTable& ParameterKeys() {
  static const KeyTable table{"parameter",
                              {{"value", "the default value: a plain number", true},
                               {"doc", "a sentence, copied into the generated Params struct", false}}};
  return table;
}

void ReadParameters(SectionReader& r, const YAML::Node& node) {
  Model& m = r.model();
  if (!node) return;
  for (const auto& [name, value] : r.Entries(node, "parameters")) {
    Parameter p;
    p.name = name;
    p.mark = r.KeyMark(value);
    CheckName(m, name, NameRole::kParameter, p.mark);
    YAML::Node v = value;
    if (value.IsMap()) {
      auto entries = r.Entries(value, "parameter '" + name + "'", &ParameterKeys());
      v = YAML::Node();
      for (auto& [k, n] : entries) {
        if (k == "value") v = n;
        if (k == "doc") {
          p.doc = r.Scalar(n, "doc");
          const std::string why = FreeTextProblem(p.doc, /*multiline=*/false);
          if (!why.empty())
            r.Fail(n, "the doc of parameter '" + name + "' " + why +
                          ", and is copied into a comment of the generated header; remove it");
        }
      }
      if (!v) r.Fail(value, "parameter '" + name + "' needs a value");
    }
    const std::string text = r.Scalar(v, "parameter '" + name + "'");
    char* end = nullptr;
    p.value = std::strtod(text.c_str(), &end);
    if (text.empty() || end == text.c_str() || *end != '\0' || !std::isfinite(p.value))
      r.Fail(v, "parameter '" + name + "' must be a number, not '" + text +
                  "' (parameter defaults are plain numbers; use expressions in geometry)");
    // The generator evaluates products of the defaults in double precision (CLN raises on
    // over- and underflow): 0, or a magnitude in [1e-100, 1e100].
    const bool nonzero_text = text.substr(0, text.find_first_of("eEpP")).find_first_of("123456789abcdefABCDEF") != std::string::npos;
    if ((p.value != 0 || nonzero_text) && !(std::abs(p.value) >= kMinMagnitude && std::abs(p.value) <= kMaxMagnitude))
      r.Fail(v, "parameter '" + name + "' = " + text +
                  " is outside the range of model numbers (0, or 1e-100 to 1e100 in magnitude); change the unit");
    p.symbol = GiNaC::symbol(name);
    m.params.push_back(p);
  }
}

}  // namespace mechgen
