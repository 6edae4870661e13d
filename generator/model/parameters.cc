// The `parameters` section: named numbers, the defaults of the generated Params struct.
// A parameter is `name: 1.5` or `name: {value: 1.5, doc: ...}` (ParameterKeys); a derived
// parameter is `name: {derived: <expression of the parameters above it>, doc: ...}`: no
// Params member, its expression is inlined wherever it is named (Model::derived).
#include <cmath>
#include <cstdlib>

#include "model/reader.h"

namespace mechgen {

const KeyTable& ParameterKeys() {
  static const KeyTable table{"parameter",
                              {{"value", "the default value: a plain number (or `derived`)", false},
                               {"derived", "instead of `value`: an expression of the parameters above it", false},
                               {"doc", "a sentence, copied into the generated Params struct", false}}};
  return table;
}

void ReadParameters(SectionReader& r, const YAML::Node& node) {
  Model& m = r.model();
  if (!node) return;
  const auto entries = r.Entries(node, "parameters");
  for (size_t index = 0; index < entries.size(); ++index) {
    const auto& [name, value] = entries[index];
    Parameter p;
    p.name = name;
    p.mark = r.KeyMark(value);
    CheckName(m, name, NameRole::kParameter, p.mark);
    YAML::Node v = value, derived;
    bool has_value = true, has_derived = false;
    if (value.IsMap()) {
      auto keys = r.Entries(value, "parameter '" + name + "'", &ParameterKeys());
      has_value = false;
      for (auto& [k, n] : keys) {
        if (k == "value") v = n, has_value = true;
        if (k == "derived") derived = n, has_derived = true;
        if (k == "doc") {
          p.doc = r.Scalar(n, "doc");
          const std::string why = FreeTextProblem(p.doc, /*multiline=*/false);
          if (!why.empty())
            r.Fail(n, "the doc of parameter '" + name + "' " + why +
                          ", and is copied into a comment of the generated header; remove it");
        }
      }
      if (has_value && has_derived)
        r.Fail(derived, "parameter '" + name + "' has both value and derived; give one: value: <number> for a free "
                        "parameter, derived: <expression> for one computed from the parameters above it");
      if (has_derived) {
        // Names below this one (and itself) are not defined yet: naming one is an error
        // that says so (no forward references, hence no cycles).
        std::vector<std::pair<std::string, SourceMark>> pending;
        for (size_t k = index; k < entries.size(); ++k) pending.emplace_back(entries[k].first, r.KeyMark(entries[k].second));
        r.SetPendingNames(pending);
        DerivedParameter d;
        d.name = name;
        d.mark = p.mark;
        d.doc = p.doc;
        d.value = r.Expression(derived, "derived parameter '" + name + "'");
        r.SetPendingNames({});
        m.derived.push_back(d);
        continue;
      }
      if (!has_value) r.Fail(value, "parameter '" + name + "' needs a value (value: <number>, or derived: <expression>)");
    }
    const std::string text = r.Scalar(v, "parameter '" + name + "'");
    char* end = nullptr;
    p.value = std::strtod(text.c_str(), &end);
    if (text.empty() || end == text.c_str() || *end != '\0' || !std::isfinite(p.value))
      r.Fail(v, "parameter '" + name + "' must be a number, not '" + text +
                  "'; a default is a plain number (a parameter computed from others is written " + name +
                  ": {derived: <expression>})");
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
