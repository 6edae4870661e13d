// The `assembly` section: values of coordinates (by name) near the wanted assembly mode.
// Its keys are coordinate names (theta_<link>, s_<joint>, psi_<joint>, u_<joint>); the
// validation stage checks that each names a coordinate.
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

}  // namespace mechgen
