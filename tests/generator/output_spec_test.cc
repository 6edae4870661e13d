// The output descriptions (codegen/output_spec.h): every member of every output struct has a
// unit (or says it is dimensionless, "1") as a field of its description, and its sign
// convention where it has one; the header's text renders them. Oracles: the committed
// generated headers (the rendered lines must appear there verbatim) and the list, pinned
// here, of members whose unit today's headers state only in the struct's text or not at all.
#include "codegen/output_spec.h"

#include <gtest/gtest.h>

#include <fstream>
#include <set>
#include <sstream>
#include <string>
#include <vector>

#include "analysis/kinematics.h"
#include "analysis/validate.h"
#include "model/model.h"
#include "symbolic/table.h"

namespace mechgen {
namespace {

std::string Read(const std::string& path) {
  std::ifstream in(path);
  std::ostringstream s;
  s << in.rdbuf();
  return s.str();
}

// Every output struct, as if every function that fills one were generated.
std::vector<FunctionSpec> AllFilling() {
  std::vector<FunctionSpec> functions;
  for (OutputStruct o : {OutputStruct::kStatics, OutputStruct::kDynamics, OutputStruct::kExcess, OutputStruct::kShaking,
                         OutputStruct::kKinematics,
                         OutputStruct::kRhs, OutputStruct::kRhsConstants, OutputStruct::kDesign,
                         OutputStruct::kStaticsDesign, OutputStruct::kDynamicsDesign}) {
    FunctionSpec f;
    f.fills = o;
    functions.push_back(f);
  }
  return functions;
}

// The text says the unit the way the headers do: in parentheses, alone or before the sign
// convention ("(N)", "(N m, CCW +)"); a bare substring would find "N" in "kNumLinks".
bool SaysUnit(const std::string& text, const std::string& unit) {
  return text.find("(" + unit + ")") != std::string::npos || text.find("(" + unit + ", ") != std::string::npos;
}

struct Loaded {
  Model m;
  Kinematics k;
  std::unique_ptr<SymbolicTable> t;
  explicit Loaded(const std::string& name)
      : m(LoadModel(std::string(MECHGEN_SOURCE_DIR) + "/models/" + name + ".yaml")) {
    const Analysis a = Validate(m);
    k = DeriveKinematics(m, a.topology, &a.coordinates, &a.cams);
    t = std::make_unique<SymbolicTable>(m, k);
  }
};

TEST(OutputSpec, EveryMemberHasAUnitAndItsRenderedDocSaysWhatItsFieldsSay) {
  const Loaded l("slider_crank_friction");
  std::set<std::string> unit_only_in_the_struct_text;
  for (const OutputSpec& o : OutputSpecs(l.m, *l.t, AllFilling())) {
    ASSERT_TRUE(o.present()) << o.name;
    std::string struct_text;
    for (const std::string& line : o.doc) struct_text += line + "\n";
    std::vector<std::string> previous;  // a member with no doc is covered by the one before it
    for (const OutputMember& mem : o.members) {
      const std::string what = o.name + "::" + mem.names;
      EXPECT_FALSE(mem.unit.empty()) << what << " has no unit (\"1\" if dimensionless)";
      std::vector<std::string> doc = RenderedDoc(mem);
      if (doc.empty()) doc = previous;
      previous = doc;
      std::string text;
      for (const std::string& line : doc) text += line + "\n";
      EXPECT_EQ(text.find("{unit}"), std::string::npos) << what;
      EXPECT_EQ(text.find("{sign}"), std::string::npos) << what;
      bool says_unit = false, says_sign = false;
      for (const std::string& line : mem.doc) {
        says_unit = says_unit || line.find("{unit}") != std::string::npos;
        says_sign = says_sign || line.find("{sign}") != std::string::npos;
      }
      if (says_unit) EXPECT_TRUE(SaysUnit(text, mem.unit)) << what;
      if (says_sign) {
        EXPECT_FALSE(mem.sign.empty()) << what;
        EXPECT_NE(text.find(mem.sign), std::string::npos) << what;
      }
      EXPECT_TRUE(mem.sign.empty() || says_sign) << what << ": a sign convention the text does not say";
      if (!SaysUnit(text, mem.unit)) unit_only_in_the_struct_text.insert(what);
    }
  }
  // The members whose own documentation does not say their unit: the struct's text states it
  // ("Units follow the model's (SI: N, N m, J)"), or, for Excess, RhsConstants and Rhs::K and
  // Phi_phi, no text does. Rendering their units into their own lines changes every generated
  // header, which this step keeps byte-identical; the list says exactly which they are.
  const std::set<std::string> expected = {
      "Statics::Q",   "Statics::drive",  "Statics::stiffness", "Statics::V",     "Statics::dV_dq", "Statics::d2V_dq2",
      "Statics::R",   "Statics::normal", "Statics::gain",      "Statics::K_rel", "Dynamics::I",    "Dynamics::dI_dq",
      "Dynamics::C",  "Dynamics::h",     "Dynamics::Q",        "Dynamics::T",    "Dynamics::V",    "Dynamics::P_nc",
      "Excess::M",    "Excess::h",       "Excess::g",          "Excess::Phi_x",  "Excess::Phi",    "Excess::gamma",
      "Excess::T, V", "Shaking::F_link", "Shaking::M_link",    "Rhs::K",         "Rhs::I",         "Rhs::h",
      "Rhs::Q",       "Rhs::T, V, P_nc", "Rhs::Phi_phi",       "RhsConstants::c"};
  EXPECT_EQ(unit_only_in_the_struct_text, expected);
}

// The rendered lines are the committed headers' lines: units and signs substituted from their
// fields give the text the header had when they were part of it.
TEST(OutputSpec, RenderedDocsAreTheCommittedHeadersLines) {
  for (const std::string name : {"slider_crank_friction", "fourbar_balanced", "engine_single", "watt_sixbar"}) {
    const Loaded l(name);
    const std::string header = Read(std::string(MECHGEN_SOURCE_DIR) + "/generated/" + name + ".h");
    ASSERT_FALSE(header.empty()) << name;
    int checked = 0;
    for (const OutputSpec& o : OutputSpecs(l.m, *l.t, AllFilling()))
      for (const OutputMember& mem : o.members) {
        if (!mem.present) continue;
        bool substituted = false;
        for (const std::string& line : mem.doc) substituted = substituted || line.find('{') != std::string::npos;
        if (!substituted) continue;
        // Present in this model's header only where the model has the struct.
        if (header.find("struct " + o.name + " {") == std::string::npos) continue;
        for (const std::string& line : RenderedDoc(mem)) {
          EXPECT_NE(header.find("  /// " + line + "\n"), std::string::npos) << name << ": " << line;
          ++checked;
        }
      }
    EXPECT_GT(checked, 0) << name;
  }
}

}  // namespace
}  // namespace mechgen
