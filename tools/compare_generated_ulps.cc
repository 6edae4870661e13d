// Compares the generated closed-form kinematics of this tree (generated/<m>.h) with those of
// an earlier revision (old_<m>.h, namespace mech::<m>_old, made by compare_generated_ulps.sh),
// both in double, against the long double evaluation of this tree's formulas: the worst error
// of each over 2000 configurations per model (inputs over twice their range, default modes),
// in ulps of the largest entry of the vector (direction cosines from SolveTrig; K and L from
// Kinematics), and the worst difference between the two revisions.
// Built and run by tools/compare_generated_ulps.sh; MODELS_INCLUDE lists the models.
#include <algorithm>
#include <cmath>
#include <cstdio>

#include MODELS_INCLUDE

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
template <class V> Eigen::Matrix<double, V::RowsAtCompileTime, V::ColsAtCompileTime> D(const V& v) { return v.template cast<double>(); }
template <class M, class O> void Compare(const char* name) {
  typename M::template ParamsT<double> p;
  typename O::template ParamsT<double> po;
  typename M::template ParamsT<long double> pl;
  double e_new[3] = {0, 0, 0}, e_old[3] = {0, 0, 0};  // cosines, K, L against long double
  double diff[3] = {0, 0, 0};                         // cosines, K, L: new against old
  int n = 0;
  for (int k = 0; k < 2000; ++k) {
    Eigen::Matrix<double, M::kNq, 1> q;
    for (int j = 0; j < M::kNq; ++j) {
      const double lo = M::kQMin[j], hi = M::kQMax[j], span = hi - lo;
      const double u = M::kNq == 1 ? k / 1999.0 : std::fmod(0.6180339887498949 * (k + 1) * (j + 1), 1.0);
      q(j) = lo - 0.5 * span + 2 * span * u;
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
      diff[1] = std::max(diff[1], Ulps(kin.K, kino.K));
      if constexpr (M::kHasL) {
        e_new[2] = std::max(e_new[2], Ulps(kin.L, D(kinl.L))); e_old[2] = std::max(e_old[2], Ulps(kino.L, D(kinl.L)));
        diff[2] = std::max(diff[2], Ulps(kin.L, kino.L));
      }
    }
  }
  std::printf("%-18s %4d | cosines: new %4.1f old %4.1f (new-old %4.1f) | K: new %4.1f old %4.1f (%4.1f) | L: new %4.1f old %4.1f (%4.1f)\n",
              name, n, e_new[0], e_old[0], diff[0], e_new[1], e_old[1], diff[1], e_new[2], e_old[2], diff[2]);
}
int main() {
  std::printf("worst error against the long double evaluation, in ulps of the largest entry (SolveTrig, Kinematics)\n");
#define C(m) Compare<mech::m::Model, mech::m##_old::Model>(#m);
  MODELS_LIST
}
