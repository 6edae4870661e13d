// The `assembly` section: values of coordinates (by name) near the wanted assembly mode.
// Its keys are coordinate names (theta_<link>, s_<joint>, psi_<joint>, u_<joint>); the
// validation stage checks that each names a coordinate. `assembly_modes` names more
// assemblies the same way: {name: {coordinate: value, ...}, ...}, each over `assembly`.
#include "model/reader.h"

namespace mechgen {

void ReadAssembly(SectionReader& r, const YAML::Node& node) {
  Model& m = r.model();
  if (!node) return;
  for (const auto& [name, value] : r.Entries(node, "assembly")) {
    GuessValue g;
    g.coordinate = name;
    g.mark = r.KeyMark(value);
    g.value = r.Number(value, "assembly value of '" + name + "'");
    m.guess.push_back(g);
  }
}

void ReadAssemblyModes(SectionReader& r, const YAML::Node& node) {
  Model& m = r.model();
  if (!node) return;
  for (const auto& [name, spec] : r.Entries(node, "assembly_modes")) {
    NamedMode mode;
    mode.name = name;
    mode.mark = r.KeyMark(spec);
    if (!IsIdentifier(name))
      m.Fail(mode.mark, "assembly mode name '" + name +
                            "' is not an identifier; use letters, digits and _ (it is looked up by name in code)");
    if (spec.IsNull())
      m.Fail(mode.mark, "assembly mode '" + name + "' has no values; write " + name +
                            ": {coordinate: value, ...}, or " + name + ": {} for the assembly's own");
    for (const auto& [coordinate, value] : r.Entries(spec, "assembly mode '" + name + "'")) {
      GuessValue g;
      g.coordinate = coordinate;
      g.mark = r.KeyMark(value);
      g.value = r.Number(value, "value of '" + coordinate + "' in assembly mode '" + name + "'");
      mode.guess.push_back(g);
    }
    m.assembly_modes.push_back(mode);
  }
}

}  // namespace mechgen
