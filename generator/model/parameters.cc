// The `parameters` section: named numbers, the defaults of the generated Params struct.
// A parameter is `name: 1.5` or `name: {value: 1.5, doc: ...}` (ParameterKeys).
#include <cmath>
#include <cstdlib>
#include <set>

#include "model/reader.h"

namespace mechgen {
namespace {

// Names of the expression language, and C++ keywords (parameters become struct members).
const std::set<std::string>& ReservedNames() {
  static const std::set<std::string> names = {
      "deg", "Pi", "pi", "sin", "cos", "tan", "sqrt", "atan2", "exp", "log", "abs", "pow", "I",
      "Euler", "Catalan", "Scalar", "Cast", "alignas", "auto", "bool", "break", "case", "catch",
      "char", "class", "const", "constexpr", "continue", "default", "delete", "do", "double",
      "else", "enum", "explicit", "extern", "false", "float", "for", "friend", "goto", "if",
      "inline", "int", "long", "mutable", "namespace", "new", "noexcept", "nullptr", "operator",
      "private", "protected", "public", "register", "return", "short", "signed", "sizeof",
      "static", "struct", "switch", "template", "this", "throw", "true", "try", "typedef",
      "typename", "union", "unsigned", "using", "virtual", "void", "volatile", "while"};
  return names;
}

}  // namespace

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
    if (!IsIdentifier(name) || ReservedNames().count(name))
      m.Fail(p.mark, "parameter name '" + name +
                          "' must be a C++ identifier and neither a C++ keyword nor a name of the " +
                          "expression language (deg, Pi, sin, cos, sqrt, ...); rename it");
    YAML::Node v = value;
    if (value.IsMap()) {
      auto entries = r.Entries(value, "parameter '" + name + "'", &ParameterKeys());
      v = YAML::Node();
      for (auto& [k, n] : entries) {
        if (k == "value") v = n;
        if (k == "doc") p.doc = r.Scalar(n, "doc");
      }
      if (!v) r.Fail(value, "parameter '" + name + "' needs a value");
    }
    const std::string text = r.Scalar(v, "parameter '" + name + "'");
    char* end = nullptr;
    p.value = std::strtod(text.c_str(), &end);
    if (text.empty() || end == text.c_str() || *end != '\0' || !std::isfinite(p.value))
      r.Fail(v, "parameter '" + name + "' must be a number, not '" + text +
                  "' (parameter defaults are plain numbers; use expressions in geometry)");
    p.symbol = GiNaC::symbol(name);
    m.params.push_back(p);
  }
}

}  // namespace mechgen
