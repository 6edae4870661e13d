// The N-loop chain of make_dyn_chain.sh in Simbody 3.7 (crank and rockers on Pins to Ground,
// each coupler on a Pin to the previous crank or rocker, each loop closed at C by
// Constraint::PointOnLine), for the growth of one right-hand side with N.
#pragma once

namespace bench_multi {

class SimbodyChain {
 public:
  explicit SimbodyChain(int n);
  ~SimbodyChain();
  SimbodyChain(const SimbodyChain&) = delete;
  SimbodyChain& operator=(const SimbodyChain&) = delete;

  /// Stores `count` states along 1 s released from rest at theta_crank = 90 deg (RKMerson 1e-8).
  void RecordStates(int count);
  /// One right-hand side at recorded state k: set t, q, u, realize(Acceleration); the crank's
  /// acceleration.
  double Rhs(int k);

 private:
  struct Impl;
  Impl* impl_;
};

}  // namespace bench_multi
