// Compares the generated closed-form kinematics of this tree (generated/<m>.h) with those of
// an earlier revision (old_<m>.h, namespace mech::<m>_old, made by compare_generated_ulps.sh),
// both in double, against the long double evaluation of this tree's formulas: the worst error
// of each over 2000 configurations per model (inputs over twice their range, default modes),
// in ulps of the largest entry of the vector (direction cosines from SolveTrig; K and L from
// Kinematics), and the worst difference between the two revisions; "per cond" is the worst
// difference divided by cond_1(Phi_phi) there, with the largest cond_1 met (K and L are solved
// with Phi_phi, so a change of the cosines reaches them amplified by up to its condition
// number). A second line compares SolvePositions (Solve: phi, the sin and cos it hands out,
// status and branch measure) and Coeffs on them, bit for bit: at how many configurations any
// entry differs.
// Built and run by tools/compare_generated_ulps.sh; MODELS_INCLUDE lists the models.
#include <algorithm>
#include <cmath>
#include <cstdio>

#include MODELS_INCLUDE
#include "mechgen/core/linear_algebra.h"

template <class A, class B> double Ulps(const A& a, const B& b) {
  double scale = 0, worst = 0;
  for (int i = 0; i < a.size(); ++i) scale = std::max({scale, std::abs(a.data()[i]), std::abs(b.data()[i])});
  const double u = std::nextafter(scale, INFINITY) - scale;
  for (int i = 0; i < a.size(); ++i) {
    const double x = a.data()[i], y = b.data()[i];
    if (std::isnan(x) && std::isnan(y)) continue;
    worst = std::max(worst, std::abs(x - y) / u);
  }
  return worst;
}
template <class A> bool Same(const A& a, const A& b) {
  for (int i = 0; i < a.size(); ++i)
    if (!(a.data()[i] == b.data()[i] || (std::isnan(a.data()[i]) && std::isnan(b.data()[i])))) return false;
  return true;
}
template <class V> Eigen::Matrix<double, V::RowsAtCompileTime, V::ColsAtCompileTime> D(const V& v) { return v.template cast<double>(); }
template <class M, class O> void Compare(const char* name) {
  typename M::template ParamsT<double> p;
  typename O::template ParamsT<double> po;
  typename M::template ParamsT<long double> pl;
  double e_new[3] = {0, 0, 0}, e_old[3] = {0, 0, 0};  // cosines, K, L against long double
  double diff[3] = {0, 0, 0};                         // cosines, K, L: new against old
  double per_cond[2] = {0, 0};                        // K, L: new against old / cond_1(Phi_phi)
  double max_cond = 0;
  int n = 0, solved = 0, solve_differs = 0, coeffs_differ = 0;
  for (int k = 0; k < 2000; ++k) {
    Eigen::Matrix<double, M::kNq, 1> q;
    for (int j = 0; j < M::kNq; ++j) {
      const double lo = M::kQMin[j], hi = M::kQMax[j], span = hi - lo;
      const double u = M::kNq == 1 ? k / 1999.0 : std::fmod(0.6180339887498949 * (k + 1) * (j + 1), 1.0);
      q(j) = lo - 0.5 * span + 2 * span * u;
    }
    {  // SolvePositions and Coeffs from its sin and cos, new against old, bit for bit
      Eigen::Matrix<double, M::kNphi, 1> phi, phio;
      for (int i = 0; i < M::kNphi; ++i) phi(i) = phio(i) = M::kAssemblyPhi[i];
      typename M::template TrigT<double> t; typename O::template TrigT<double> to;
      const auto r = M::Solve(p, q, &phi, M::kDefaultModes, 20, 0.0, &t);
      const auto ro = O::Solve(po, q, &phio, O::kDefaultModes, 20, 0.0, &to);
      if ((int)r.status != (int)ro.status) ++solve_differs;
      if ((int)r.status == 0 && (int)ro.status == 0) {
        ++solved;
        if (!Same(phi, phio) || !Same(t.cos_phi, to.cos_phi) || !Same(t.sin_phi, to.sin_phi) ||
            !Same(t.cos_q, to.cos_q) || !Same(t.sin_q, to.sin_q) || r.branch_measure != ro.branch_measure)
          ++solve_differs;
        typename M::template CoefficientsT<double> c; typename O::template CoefficientsT<double> co;
        M::Coeffs(p, q, phi, &c, &t); O::Coeffs(po, q, phio, &co, &to);
        if (!Same(c.K, co.K) || !Same(c.L, co.L) || !Same(c.Phi, co.Phi) || !Same(c.Phi_phi, co.Phi_phi))
          ++coeffs_differ;
      }
    }
    const Eigen::Matrix<long double, M::kNq, 1> ql = q.template cast<long double>();
    typename M::template TrigT<double> t; typename O::template TrigT<double> to; typename M::template TrigT<long double> tl;
    const auto r = M::SolveTrig(p, q, M::kDefaultModes, &t);
    const auto ro = O::SolveTrig(po, q, O::kDefaultModes, &to);
    const auto rl = M::SolveTrig(pl, ql, M::kDefaultModes, &tl);
    if ((int)r.status != 0 || (int)ro.status != 0 || (int)rl.status != 0) continue;
    ++n;
    e_new[0] = std::max({e_new[0], Ulps(t.cos_phi, D(tl.cos_phi)), Ulps(t.sin_phi, D(tl.sin_phi))});
    e_old[0] = std::max({e_old[0], Ulps(to.cos_phi, D(tl.cos_phi)), Ulps(to.sin_phi, D(tl.sin_phi))});
    diff[0] = std::max({diff[0], Ulps(t.cos_phi, to.cos_phi), Ulps(t.sin_phi, to.sin_phi)});
    if constexpr (M::kHasKinematics) {
      typename M::template KinematicsT<double> kin; typename O::template KinematicsT<double> kino; typename M::template KinematicsT<long double> kinl;
      M::Kinematics(p, q, M::kDefaultModes, &t, &kin); O::Kinematics(po, q, O::kDefaultModes, &to, &kino);
      M::Kinematics(pl, ql, M::kDefaultModes, &tl, &kinl);
      e_new[1] = std::max(e_new[1], Ulps(kin.K, D(kinl.K))); e_old[1] = std::max(e_old[1], Ulps(kino.K, D(kinl.K)));
      const double dK = Ulps(kin.K, kino.K), dL = M::kHasL ? Ulps(kin.L, kino.L) : 0.0;
      diff[1] = std::max(diff[1], dK);
      if constexpr (M::kHasL) {
        e_new[2] = std::max(e_new[2], Ulps(kin.L, D(kinl.L))); e_old[2] = std::max(e_old[2], Ulps(kino.L, D(kinl.L)));
        diff[2] = std::max(diff[2], dL);
      }
      double cond = 0, det = 0;
      mechgen::ConditionAndDeterminant(kin.Phi_phi, &cond, &det);
      max_cond = std::max(max_cond, cond);
      per_cond[0] = std::max(per_cond[0], dK / cond);
      per_cond[1] = std::max(per_cond[1], dL / cond);
    }
  }
  std::printf("%-18s %4d | cosines: new %4.1f old %4.1f (new-old %4.1f) | K: new %4.1f old %4.1f (%4.1f) | L: new %4.1f old %4.1f (%4.1f)\n",
              name, n, e_new[0], e_old[0], diff[0], e_new[1], e_old[1], diff[1], e_new[2], e_old[2], diff[2]);
  std::printf("%-18s      | new-old per cond_1 (largest %.3g): K %4.2f L %4.2f | Solve differs at %d of 2000,"
              " Coeffs at %d of the %d both solved\n", "", max_cond, per_cond[0], per_cond[1], solve_differs,
              coeffs_differ, solved);
}
int main() {
  std::printf("worst error against the long double evaluation, in ulps of the largest entry (SolveTrig, Kinematics)\n");
#define C(m) Compare<mech::m::Model, mech::m##_old::Model>(#m);
  MODELS_LIST
}
