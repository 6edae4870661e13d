// Grashof classification of every four-bar loop (Paul appendix A) — a loop of four links
// joined by four revolute joints — and the check that a driven link's declared range is
// one the loop can reach (a crank-rocker's crank turns fully; a rocker does not).
#pragma once

#include <string>
#include <vector>

#include "analysis/topology.h"
#include "model/model.h"

namespace mechgen {

struct FourBarLoop {
  int loop = -1;               ///< index into Topology::loops
  double s = 0, l = 0, p = 0, q = 0;  ///< shortest, longest, the other two lengths
  std::string links[4];        ///< link names in loop order
  double lengths[4] = {0, 0, 0, 0};
  std::string type;            ///< "crank-rocker", "double-crank", "double-rocker", "change point", "triple-rocker (non-Grashof)"
  std::string Text() const;    ///< "loop 1 (ground 4, crank 1, coupler 3.5, rocker 3): s + l = 5 < p + q = 6.5, Grashof crank-rocker"
  /// The transmission angle over the declared range of an input that drives a
  /// ground-adjacent link of the loop directly (from the triangle pin–joint–pivot:
  /// cos mu = (b^2 + c^2 - delta^2) / (2 b c), delta the pin's distance to the output's pivot).
  bool has_mu = false;
  std::string mu_input;  ///< the input joint
  double mu_min = 0, mu_max = 0, q_at_mu_min = 0, q_at_mu_max = 0;  ///< radians
  std::string MuText() const;
  /// The first input (index into Model::inputs) whose declared range the loop cannot
  /// reach, the driven link and the first angle it cannot reach; -1 if none.
  int unreachable_input = -1;
  int unreachable_link = -1;
  double unreachable_q = 0;  ///< "over input A's range mu = 32.1 deg (at 180.0 deg) ... 94.2 deg (at 0.0 deg)"
};

/// A loop of four links joined by four revolute joints.
bool IsFourBarLoop(const Model& m, const Loop& loop);

/// Classifies the four-bar loops, with lengths at the parameters' default values, and
/// notes a driven link's range that leaves the loop's reach.
std::vector<FourBarLoop> ClassifyFourBars(const Model& m, const Topology& t);

/// The validation stage's check: ModelError at the input if `f` notes an unreachable range.
void CheckFourBarRange(const Model& m, const FourBarLoop& f);

}  // namespace mechgen
