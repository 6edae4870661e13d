// The derivative along the motion. See motion.h.
#include "symbolic/motion.h"

#include <algorithm>

namespace mechgen {

using GiNaC::ex;

Motion::Motion(const Kinematics& k, KFn K, LFn L) : nq_(k.nq()), K_(std::move(K)), L_(std::move(L)) {
  for (const Coordinate& c : k.q) x_.push_back(c.symbol);
  for (const Coordinate& c : k.phi) x_.push_back(c.symbol);
}

Motion::Motion(std::vector<GiNaC::symbol> inputs, const std::vector<GiNaC::symbol>& phi, KFn K, LFn L)
    : nq_(static_cast<int>(inputs.size())), x_(std::move(inputs)), K_(std::move(K)), L_(std::move(L)) {
  x_.insert(x_.end(), phi.begin(), phi.end());
}

ex Motion::V(int a, int j) const { return a < nq_ ? ex(a == j ? 1 : 0) : K_(a - nq_, j); }

ex Motion::L(int i, int j, int k) const { return L_(i, std::min(j, k), std::max(j, k)); }

ex Motion::Along(const ex& f, int j) const {
  ex s = f.diff(x_[j]);
  for (int a = nq_; a < nx(); ++a) s += f.diff(x_[a]) * K_(a - nq_, j);
  return s;
}

std::vector<ex> Motion::VelocityCoefficients(const ex& f) const {
  std::vector<ex> K_f;
  for (int j = 0; j < nq_; ++j) K_f.push_back(Along(f, j));
  return K_f;
}

std::vector<ex> Motion::CentripetalCoefficients(const ex& f, const std::vector<ex>& K_f) const {
  std::vector<ex> L_f(nq_ * nq_);
  for (int j = 0; j < nq_; ++j)
    for (int k = 0; k < nq_; ++k) {
      const int lo = std::min(j, k), hi = std::max(j, k);
      ex s = Along(K_f[lo], hi);
      for (int i = 0; i < nx() - nq_; ++i) s += f.diff(x_[nq_ + i]) * L(i, lo, hi);
      L_f[j + nq_ * k] = s;
    }
  return L_f;
}

ex Motion::Second(const ex& f, int j, int k) const {
  ex s = 0;
  for (int a = 0; a < nx(); ++a) {
    const ex fa = f.diff(x_[a]);
    if (fa.is_zero()) continue;
    if (a >= nq_) s += fa * L(a - nq_, j, k);
    for (int b = 0; b < nx(); ++b) {
      const ex fab = fa.diff(x_[b]);
      if (!fab.is_zero()) s += fab * V(a, j) * V(b, k);
    }
  }
  return s;
}

ex Motion::Rate(const ex& f, const std::vector<ex>& xdot) const {
  ex s = 0;
  for (size_t a = 0; a < xdot.size(); ++a) s += f.diff(x_[a]) * xdot[a];
  return s;
}

}  // namespace mechgen
