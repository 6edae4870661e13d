// Compiled once per shipped model with -Wall -Wextra -Werror -std=c++17 and only the
// model's generated directory and Eigen on the include path (tests/kinematics/
// CMakeLists.txt): the generated header must be self-contained and warning-clean. It
// defines MECH_<NAME>_INSTANTIATING so that every function body is instantiated here, for
// double, float and long double, and runs them once at the model's assembly guess (the
// position solver must converge from there).
//
// MECH_MODEL_HEADER ("<name>.h") and MECH_MODEL_NAMESPACE (mech::<name>) come from CMake.
#include MECH_MODEL_HEADER

#include <cmath>
#include <cstddef>
#include <cstdio>
#include <type_traits>

namespace {

template <typename Scalar>
const char* TypeName() {
  return sizeof(Scalar) == sizeof(float)    ? "float"
         : sizeof(Scalar) == sizeof(double) ? "double"
                                            : "long double";
}

// Models with four-bar loops have EvalTransmissionAngles (and Model::TransmissionAngles).
template <class M, class = void>
struct HasTransmissionAngles : std::false_type {};
template <class M>
struct HasTransmissionAngles<M, std::void_t<decltype(&M::template TransmissionAngles<double>)>>
    : std::true_type {};

template <class M, typename Scalar, class P, class Q, class Phi>
bool TransmissionAnglesFinite(const P& p, const Q& q, const Phi& phi) {
  if constexpr (HasTransmissionAngles<M>::value) {
    MECH_MODEL_NAMESPACE::Vec<Scalar, M::kNumTransmissionAngles> mu;
    M::TransmissionAngles(p, q, phi, &mu);
    return mu.allFinite() && (mu.array() >= Scalar(0)).all() && (mu.array() <= Scalar(3.15)).all();
  } else {
    static_assert(M::kNumTransmissionAngles == 0, "transmission angles without the function");
    return true;
  }
}

template <typename Scalar>
bool RunAll() {
  using M = MECH_MODEL_NAMESPACE::Model;
  const MECH_MODEL_NAMESPACE::Params<Scalar> p;
  MECH_MODEL_NAMESPACE::Vec<Scalar, M::kNq> q;
  MECH_MODEL_NAMESPACE::Vec<Scalar, M::kNphi> phi;
  for (int j = 0; j < M::kNq; ++j) q(j) = Scalar(M::kAssemblyQ[static_cast<std::size_t>(j)]);
  for (int i = 0; i < M::kNphi; ++i) phi(i) = Scalar(M::kAssemblyPhi[static_cast<std::size_t>(i)]);
  MECH_MODEL_NAMESPACE::Vec<Scalar, M::kNc> Phi;
  MECH_MODEL_NAMESPACE::Mat<Scalar, M::kNc, M::kNphi> Phi_phi;
  MECH_MODEL_NAMESPACE::Mat<Scalar, M::kNc, M::kNq> Phi_q;
  MECH_MODEL_NAMESPACE::EvalPhi(p, q, phi, &Phi, &Phi_phi, &Phi_q);
  MECH_MODEL_NAMESPACE::EvalPhi(p, q, phi, &Phi);
  MECH_MODEL_NAMESPACE::Coefficients<Scalar> coeffs;
  MECH_MODEL_NAMESPACE::EvalCoefficients(p, q, phi, &coeffs);
  MECH_MODEL_NAMESPACE::Mat<Scalar, 2, M::kNumScenePoints> scene;
  MECH_MODEL_NAMESPACE::EvalScene(p, q, phi, &scene);
  M::Phi(p, q, phi, &Phi, &Phi_phi, &Phi_q);
  M::Coeffs(p, q, phi, &coeffs);
  M::Scene(p, q, phi, &scene);
  Scalar det = Scalar(0);
  MECH_MODEL_NAMESPACE::EvalDetPhiPhi(p, q, phi, &det);
  M::DetPhiPhi(p, q, phi, &det);
  MECH_MODEL_NAMESPACE::Vec<Scalar, M::kNphi> phi_solved = phi;
  const auto report = MECH_MODEL_NAMESPACE::SolvePositions(p, q, &phi_solved, M::kDefaultModes);
  const auto report_traits = M::Solve(p, q, &phi_solved);
  const auto p_double = p.template Cast<double>();
  (void)p_double;
  bool ok = true;
  const auto check = [&ok](bool good, const char* what) {
    if (!good) {
      std::printf("%s<%s>: %s\n", M::kName, TypeName<Scalar>(), what);
      ok = false;
    }
  };
  check(report.status == MECH_MODEL_NAMESPACE::SolveStatus::kConverged,
        "SolvePositions did not converge from the assembly guess");
  check(report_traits.status == MECH_MODEL_NAMESPACE::SolveStatus::kConverged,
        "Model::Solve did not converge from the assembly guess");
  check(phi_solved.allFinite(), "non-finite solved phi");
  check(std::isfinite(static_cast<double>(det)), "non-finite det Phi_phi");
  check(Phi.allFinite() && Phi_phi.allFinite() && Phi_q.allFinite(), "non-finite Phi");
  check(coeffs.K.allFinite() && coeffs.L.allFinite(), "non-finite K or L");
  check(coeffs.r_P.allFinite() && coeffs.K_P.allFinite() && coeffs.L_P.allFinite(),
        "non-finite r_P, K_P or L_P");
  check(scene.allFinite(), "non-finite scene");
  check(TransmissionAnglesFinite<M, Scalar>(p, q, phi_solved), "transmission angle not in [0, pi]");
  return ok;
}

}  // namespace

int main() {
  const bool ok_d = RunAll<double>();
  const bool ok_f = RunAll<float>();
  const bool ok_ld = RunAll<long double>();
  const bool ok = ok_d && ok_f && ok_ld;
  std::printf("%s: %s\n", MECH_MODEL_NAMESPACE::Model::kName, ok ? "ok" : "non-finite output");
  return ok ? 0 : 1;
}
