/**
 * \file study/tolerance.h
 * Tolerance analysis of a metric: first order from its gradient at the nominal design
 * (root-sum-square: sigma_m = sqrt(sum_p (dm/dp sigma_p)^2); worst case: sum_p |dm/dp| t_p,
 * t_p the tolerance, 3 sigma of a normal, the half-width of a uniform), a joint clearance c
 * taken as a change of its length parameter by c in the direction that is worst for the
 * metric (|dm/dp| c, added to the worst case), and the Monte-Carlo's mean and standard
 * deviation with their 95 % confidence intervals, side by side; the verdict says whether the
 * first-order sigma lies in the Monte-Carlo's interval (it does not near a toggle or a change
 * point, where the metric is not linear in the parameters over the tolerance).
 */
#pragma once

#include <cmath>
#include <string>
#include <vector>

namespace mechgen::study {

/// Mean and standard deviation of a sample with their 95 % confidence intervals.
struct Moments {
  long long n = 0;
  double mean = NAN, sigma = NAN;
  double mean_low = NAN, mean_high = NAN;    ///< mean -+ 1.96 sigma / sqrt(n)
  double sigma_low = NAN, sigma_high = NAN;  ///< sigma / (1 +- 1.96 / sqrt(2 (n - 1))) (large n)
};

/// The moments of the finite values of x (two passes: the mean, then the squares about it).
inline Moments MomentsOf(const std::vector<double>& x) {
  Moments m;
  double sum = 0;
  for (double v : x)
    if (std::isfinite(v)) sum += v, ++m.n;
  if (m.n < 2) return m;
  m.mean = sum / m.n;
  double squares = 0;
  for (double v : x)
    if (std::isfinite(v)) squares += (v - m.mean) * (v - m.mean);
  m.sigma = std::sqrt(squares / (m.n - 1));
  const double z = 1.959963984540054;
  m.mean_low = m.mean - z * m.sigma / std::sqrt(double(m.n));
  m.mean_high = m.mean + z * m.sigma / std::sqrt(double(m.n));
  const double h = z / std::sqrt(2.0 * (m.n - 1));
  m.sigma_low = m.sigma / (1 + h);
  m.sigma_high = h < 1 ? m.sigma / (1 - h) : INFINITY;
  return m;
}

/// The first-order figures of one metric.
struct FirstOrder {
  double rss = NAN;       ///< sqrt(sum (g_p sigma_p)^2)
  double worst = NAN;     ///< sum |g_p| t_p
  double clearance = 0;   ///< sum over clearances |g_p| c (worst direction)
  bool complete = false;  ///< every parameter had a derivative
};

/// g: dm/dp per parameter (NaN: none); sigma, tolerance: per parameter; clearance_of[p]: the
/// summed radial clearances acting on parameter p.
inline FirstOrder FirstOrderOf(const std::vector<double>& g,
                               const std::vector<double>& sigma,
                               const std::vector<double>& tolerance,
                               const std::vector<double>& clearance_of) {
  FirstOrder f;
  double rss = 0, worst = 0, clear = 0;
  f.complete = !g.empty();
  for (size_t p = 0; p < g.size(); ++p) {
    if (!std::isfinite(g[p])) {
      f.complete = false;
      continue;
    }
    rss += (g[p] * sigma[p]) * (g[p] * sigma[p]);
    worst += std::abs(g[p]) * tolerance[p];
    clear += std::abs(g[p]) * clearance_of[p];
  }
  if (f.complete) {
    f.rss = std::sqrt(rss);
    f.worst = worst;
    f.clearance = clear;
  }
  return f;
}

/// "agrees" when the first-order sigma lies in the Monte-Carlo's 95 % interval of sigma, else
/// a sentence with the figures.
inline std::string Verdict(const FirstOrder& f, const Moments& m) {
  if (!f.complete) return "no first-order figure";
  if (m.n < 2) return "no Monte-Carlo figure";
  if (f.rss >= m.sigma_low && f.rss <= m.sigma_high) return "agrees";
  char buffer[240];
  std::snprintf(buffer, sizeof(buffer),
                "DISAGREES: first-order sigma %.4g is outside the Monte-Carlo's [%.4g, %.4g] (ratio %.3g): the "
                "metric is not linear over the tolerances (near a toggle, a change point or a peak that moves)",
                f.rss, m.sigma_low, m.sigma_high, f.rss / m.sigma);
  return buffer;
}

}  // namespace mechgen::study
