// One formulation of the closed-form dyads serves the generated SolvePositions and the
// generator's own mode choice (symbolic/dyads.h). Here the two ends are compared on every
// shipped model whose blocks are closed forms: the compiled Model::Solve (double) against
// the generator's evaluation of the same formulation in GiNaC (EvaluateClosedForm), over
// the inputs' range, in the model's assembly modes and in the opposite ones; both must
// find the same positions, or both must find that the loop cannot close. The generator's
// mode choice must be the header's kDefaultModes.
#include <gtest/gtest.h>

#include <cmath>
#include <map>
#include <string>
#include <vector>

#include "all_models.h"
#include "analysis/kinematics.h"
#include "model/model.h"
#include "symbolic/dyads.h"
#include "symbolic/table.h"
#include "analysis/topology.h"

namespace {

template <typename M>
class DyadFormulationTest : public ::testing::Test {};
TYPED_TEST_SUITE(DyadFormulationTest, mechtest::AllModels, mechtest::ModelNames);

TYPED_TEST(DyadFormulationTest, GeneratedSolveMatchesTheGeneratorsEvaluation) {
  using M = TypeParam;
  const mechgen::Model m =
      mechgen::LoadModel(std::string(MECHGEN_SOURCE_DIR) + "/models/" + std::string(M::kName) + ".yaml");
  const mechgen::Topology t = mechgen::BuildTopology(m);
  const mechgen::Kinematics k = mechgen::DeriveKinematics(m, t);
  const mechgen::SymbolicTable table(m, k);
  ASSERT_EQ(static_cast<int>(table.blocks.size()), M::kNumBlocks);
  for (int b = 0; b < M::kNumBlocks; ++b) EXPECT_EQ(table.blocks[b].default_mode, M::kDefaultModes[b]) << b;
  if (!k.cam_laws.empty() || !k.cam_contours.empty()) GTEST_SKIP() << "cam laws and contours have no GiNaC value";
  for (const mechgen::Block& b : table.blocks)
    if (b.solve == mechgen::BlockSolve::kNewton) GTEST_SKIP() << "a Newton block";

  // Inputs over their range: 37 values of one input, a 9 x 9 grid of two.
  std::vector<std::vector<double>> qs;
  const int n = M::kNq == 1 ? 37 : 9;
  for (int i = 0; i < (M::kNq == 1 ? n : n * n); ++i) {
    std::vector<double> q(M::kNq);
    for (int j = 0; j < M::kNq; ++j) {
      const int step = j == 0 ? i % n : (i / n) % n;
      q[j] = M::kQMin[j] + (M::kQMax[j] - M::kQMin[j]) * step / (n - 1);
    }
    qs.push_back(q);
  }
  const typename M::template ParamsT<double> params;
  int compared = 0, not_assemblable = 0;
  for (const int flip : {1, -1}) {
    std::array<int, M::kNumBlocks> modes = M::kDefaultModes;
    for (int& mode : modes) mode *= flip;
    for (const auto& qv : qs) {
      Eigen::Matrix<double, M::kNq, 1> q;
      for (int j = 0; j < M::kNq; ++j) q(j) = qv[j];
      Eigen::Matrix<double, M::kNphi, 1> phi;
      for (int i = 0; i < M::kNphi; ++i) phi(i) = M::kAssemblyPhi[i];
      const auto report = M::Solve(params, q, &phi, modes);
      using Status = decltype(report.status);

      GiNaC::exmap v;
      for (const mechgen::Parameter& p : m.params) v[p.symbol] = p.value;
      for (int j = 0; j < M::kNq; ++j) v[k.q[j].symbol] = qv[j];
      bool ok = true;
      int failed_block = -1;
      for (size_t bi = 0; bi < table.blocks.size() && ok; ++bi) {
        const mechgen::ClosedForm f = mechgen::FormulateClosedForm(k, table.blocks[bi], static_cast<int>(bi));
        std::map<mechgen::DyadLocal, double> locals;
        std::map<int, double> solution;
        const mechgen::DyadStep* failed = nullptr;
        ok = mechgen::EvaluateClosedForm(f, v, modes[bi], &locals, &solution, &failed);
        if (!ok) failed_block = static_cast<int>(bi);
        for (const auto& [col, value] : solution) v[k.phi[col].symbol] = value;
      }
      if (!ok) {
        ++not_assemblable;
        EXPECT_EQ(report.status, Status::kNotAssemblable) << "q0 = " << qv[0];
        EXPECT_EQ(report.block, failed_block) << "q0 = " << qv[0];
        continue;
      }
      ASSERT_EQ(report.status, Status::kConverged) << "q0 = " << qv[0];
      ++compared;
      for (int i = 0; i < M::kNphi; ++i) {
        const GiNaC::ex e = v[k.phi[i].symbol].evalf();
        const double expected = GiNaC::ex_to<GiNaC::numeric>(e).to_double();
        const double d = M::kPhiIsAngle[i] ? std::remainder(phi(i) - expected, 2 * M_PI) : phi(i) - expected;
        EXPECT_NEAR(d, 0, 1e-9) << M::kPhiNames[i] << " at q0 = " << qv[0] << ", modes x" << flip;
      }
    }
  }
  EXPECT_GT(compared, 0);
  this->RecordProperty("not_assemblable", not_assemblable);
}

}  // namespace
