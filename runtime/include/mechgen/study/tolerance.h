/**
 * \file study/tolerance.h
 * Tolerance analysis of a metric: first order from its gradient at the nominal design
 * (root-sum-square: sigma_m = sqrt(sum_p (dm/dp sigma_p)^2); worst case: sum_p |dm/dp| t_p,
 * t_p the tolerance, 3 sigma of a normal, the half-width of a uniform), a joint clearance c
 * taken as a change of its length parameter by c in the direction that is worst for the
 * metric (|dm/dp| c, added to the worst case), and the Monte-Carlo's mean and standard
 * deviation with their standard errors and 95 % intervals, side by side.
 *
 * The verdict (issue 45) is a decision on the ratio R = first-order sigma / Monte-Carlo sigma,
 * whose only uncertainty is the Monte-Carlo's (the first order is exact for its gradient):
 *  - the Monte-Carlo sigma's standard error is the delta method's on the sample variance,
 *    se(s) = s sqrt((kappa - (n - 3)/(n - 1)) / (4 n)), kappa = m4 / s^4 the sample kurtosis
 *    (3 for a normal metric: then se(s) = s / sqrt(2 (n - 1)), the normal-theory figure; a
 *    metric with heavier tails is known less well);
 *  - R's interval is R exp(-+z se(s)/s) with z the normal quantile of a Sidak-corrected level:
 *    the study prints `family` verdicts together, so each is taken at 1 - (1 - alpha)^(1/family)
 *    (alpha = 5 % for all of them together; one false alarm in twenty studies, not in twenty
 *    metrics);
 *  - DISAGREES only when the difference is both significant (the interval excludes 1) and
 *    practically large (R outside [1 - delta, 1 + delta], delta = 5 %); "agrees" when the
 *    interval lies inside [1 - delta, 1 + delta]; otherwise "inconclusive" with the
 *    Monte-Carlo's uncertainty and about how many samples would decide.
 * A DISAGREES names curvature as the cause only when the samples show it: the metric regressed
 * on the standardized parameters z_p = (x_p - nominal_p) / sigma_p, linear (1, z) and quadratic
 * (1, z, z_p z_q), the quadratic terms explain a share of the variance that is both significant
 * (their F test at the same corrected level) and at least kCurvatureShare; the metric's slope
 * over the samples is named when a linear fit to them gives a sigma outside [1 - delta,
 * 1 + delta] of the first order (the slope at the nominal is not the slope over the
 * tolerances: near a toggle, a square root of a margin); else the cause is said to be
 * unidentified (a kink, a failure region, a heavy tail), with those figures.
 */
#pragma once

#include <algorithm>
#include <atomic>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <string>
#include <thread>
#include <vector>

#include "mechgen/study/random.h"

namespace mechgen::study {

/// Mean and standard deviation of a sample with their standard errors and 95 % intervals.
struct Moments {
  long long n = 0;
  double mean = NAN, sigma = NAN;
  double mean_low = NAN, mean_high = NAN;  ///< mean -+ 1.96 sigma / sqrt(n)
  double kurtosis = NAN;                   ///< m4 / sigma^4 (3 for a normal)
  /// The standard error of sigma: sigma sqrt((kurtosis - (n - 3)/(n - 1)) / (4 n)) (the delta
  /// method on the sample variance's variance (mu4 - sigma^4 (n - 3)/(n - 1)) / n).
  double sigma_se = NAN;
  double sigma_low = NAN, sigma_high = NAN;  ///< sigma exp(-+1.96 sigma_se / sigma)
};

/// The samples of one block of MomentsOf's sums: a constant, so that the sums (and so the
/// bytes of every figure) depend on the values alone, never on the threads or the chunks.
constexpr uint64_t kMomentBlock = 4096;

/// fn(b, t) for every block b in 0 .. blocks - 1 on `threads` threads (t: the thread's index,
/// 0 the calling thread's), each block once.
template <class Fn>
void ForEachBlock(uint64_t blocks, int threads, Fn&& fn) {
  const int workers =
      static_cast<int>(std::min<uint64_t>(static_cast<uint64_t>(std::max(threads, 1)), std::max<uint64_t>(blocks, 1)));
  std::atomic<uint64_t> next{0};
  auto work = [&](int t) {
    for (uint64_t b; (b = next.fetch_add(1)) < blocks;) fn(b, t);
  };
  std::vector<std::thread> pool;
  for (int t = 1; t < workers; ++t) pool.emplace_back(work, t);
  work(0);
  for (std::thread& t : pool) t.join();
}

/// The moments of the finite values of x (two passes: the mean, then the powers about it;
/// each pass sums blocks of kMomentBlock values in order, then the blocks' sums in block
/// order), on `threads` threads: the same bits for any number.
inline Moments MomentsOf(const std::vector<double>& x, int threads = 1) {
  Moments m;
  const uint64_t size = x.size(), blocks = (size + kMomentBlock - 1) / kMomentBlock;
  std::vector<double> sum(blocks, 0.0), squares(blocks, 0.0), fourth(blocks, 0.0);
  std::vector<long long> count(blocks, 0);
  ForEachBlock(blocks, threads, [&](uint64_t b, int) {
    for (uint64_t i = b * kMomentBlock; i < std::min(size, (b + 1) * kMomentBlock); ++i)
      if (std::isfinite(x[i])) sum[b] += x[i], ++count[b];
  });
  double total = 0;
  for (uint64_t b = 0; b < blocks; ++b) total += sum[b], m.n += count[b];
  if (m.n < 2) return m;
  const double n = static_cast<double>(m.n);
  m.mean = total / n;
  ForEachBlock(blocks, threads, [&](uint64_t b, int) {
    for (uint64_t i = b * kMomentBlock; i < std::min(size, (b + 1) * kMomentBlock); ++i)
      if (std::isfinite(x[i])) {
        const double d2 = (x[i] - m.mean) * (x[i] - m.mean);
        squares[b] += d2, fourth[b] += d2 * d2;
      }
  });
  double sq = 0, fo = 0;
  for (uint64_t b = 0; b < blocks; ++b) sq += squares[b], fo += fourth[b];
  m.sigma = std::sqrt(sq / (n - 1));
  const double z = 1.959963984540054;
  m.mean_low = m.mean - z * m.sigma / std::sqrt(n);
  m.mean_high = m.mean + z * m.sigma / std::sqrt(n);
  if (m.sigma > 0) {
    const double s2 = m.sigma * m.sigma;
    m.kurtosis = fo / n / (s2 * s2);
    // kurtosis >= ((n - 1)/n)^2 > (n - 3)/(n - 1): the root is real.
    const double relative = std::sqrt(std::max(0.0, m.kurtosis - (n - 3) / (n - 1)) / (4 * n));
    m.sigma_se = m.sigma * relative;
    m.sigma_low = m.sigma * std::exp(-z * relative);
    m.sigma_high = m.sigma * std::exp(z * relative);
  } else {
    m.sigma_se = m.sigma_low = m.sigma_high = 0;
  }
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

/// The regularized incomplete beta function I_x(a, b), a, b > 0, x in [0, 1] (the continued
/// fraction by Lentz's method, on the side of x where it converges fast).
inline double RegularizedBeta(double a, double b, double x) {
  if (!(x > 0)) return 0;
  if (!(x < 1)) return 1;
  if (x > (a + 1) / (a + b + 2)) return 1 - RegularizedBeta(b, a, 1 - x);
  const double front = std::exp(std::lgamma(a + b) - std::lgamma(a) - std::lgamma(b) + a * std::log(x) +
                                b * std::log1p(-x)) / a;
  if (front == 0) return 0;
  constexpr double tiny = 1e-300;
  double c = 1, d = 1 - (a + b) * x / (a + 1);
  d = 1 / (std::abs(d) < tiny ? tiny : d);
  double f = d;
  for (int m = 1; m <= 100000; ++m) {
    for (int half = 0; half < 2; ++half) {
      const double numerator = half == 0 ? m * (b - m) * x / ((a + 2 * m - 1) * (a + 2 * m))
                                         : -(a + m) * (a + b + m) * x / ((a + 2 * m) * (a + 2 * m + 1));
      d = 1 + numerator * d;
      d = 1 / (std::abs(d) < tiny ? tiny : d);
      c = 1 + numerator / c;
      if (std::abs(c) < tiny) c = tiny;
      f *= c * d;
      if (half == 1 && std::abs(c * d - 1) < 1e-15) return front * f;
    }
  }
  return front * f;
}

/// P(F > f) for F with (d1, d2) degrees of freedom.
inline double FTestP(double f, double d1, double d2) {
  if (!(f > 0)) return 1;
  return RegularizedBeta(d2 / 2, d1 / 2, d2 / (d2 + d1 * f));
}

/// The curvature of a metric over the samples (see the file comment).
struct Curvature {
  bool estimated = false;
  long long n = 0;  ///< samples in the fit
  int terms = 0;    ///< regressors of the quadratic model (1 + P + P (P + 1) / 2, or 1 + 2 P: squares only)
  bool cross_terms = false;
  /// (RSS_linear - RSS_quadratic) / TSS: the share of the metric's variance over the samples
  /// that the quadratic terms explain beyond the linear ones.
  double share = NAN;
  double p = NAN;   ///< the F test's p-value of the quadratic terms (0: below the smallest double)
  /// The standard deviation of the linear fit's values, sqrt((TSS - RSS_linear) / (n - 1)): the
  /// metric's sigma as far as its average slope over the samples explains it.
  double linear_sigma = NAN;
  std::string why;  ///< when not estimated
};

/// The most regressors CurvatureOf fits (a P x P quadratic needs (P + 1)(P + 2)/2: P <= 9 with
/// the cross terms, P <= 31 with the squares alone).
constexpr int kMaxCurvatureTerms = 64;

/**
 * \brief The metric y (one value per sample; a non-finite value leaves the sample out)
 *        regressed on its standardized parameters: linear, then quadratic.
 * \param x        the samples' parameter values, x[i * P + p]
 * \param nominal  the parameters' nominal values, sigma their standard deviations
 */
inline Curvature CurvatureOf(const std::vector<double>& y, const std::vector<double>& x,
                             const std::vector<double>& nominal, const std::vector<double>& sigma) {
  Curvature c;
  const size_t P = nominal.size();
  if (P == 0 || x.size() < y.size() * P) return c.why = "no parameters", c;
  c.cross_terms = static_cast<int>((P + 1) * (P + 2) / 2) <= kMaxCurvatureTerms;
  c.terms = static_cast<int>(c.cross_terms ? (P + 1) * (P + 2) / 2 : 1 + 2 * P);
  if (c.terms > kMaxCurvatureTerms) return c.why = "too many parameters for a quadratic fit", c;
  const int k = c.terms, linear = static_cast<int>(1 + P);
  double mean = 0;
  for (double v : y)
    if (std::isfinite(v)) mean += v, ++c.n;
  if (c.n < 2 * k + 10)
    return c.why = "too few samples for a quadratic fit (" + std::to_string(c.n) + " of " + std::to_string(k) +
                   " terms)",
           c;
  mean /= static_cast<double>(c.n);
  // The regressors of sample i: 1, z_p, then z_p z_q (q >= p) or z_p^2.
  std::vector<double> f(k);
  auto features = [&](size_t i) {
    f[0] = 1;
    for (size_t p = 0; p < P; ++p) f[1 + p] = (x[i * P + p] - nominal[p]) / sigma[p];
    int at = linear;
    for (size_t p = 0; p < P; ++p)
      for (size_t q = p; q < (c.cross_terms ? P : p + 1); ++q) f[at++] = f[1 + p] * f[1 + q];
  };
  // The normal equations (the lower triangle of X'X, and X'y), then their Cholesky factor L:
  // its leading (1 + P) block is the factor of the linear fit's equations, so one
  // factorization solves both fits.
  std::vector<double> L(static_cast<size_t>(k) * k, 0.0), Xty(k, 0.0);
  double tss = 0;
  for (size_t i = 0; i < y.size(); ++i) {
    if (!std::isfinite(y[i])) continue;
    features(i);
    const double yi = y[i] - mean;
    for (int a = 0; a < k; ++a) {
      for (int b = 0; b <= a; ++b) L[a * k + b] += f[a] * f[b];
      Xty[a] += f[a] * yi;
    }
    tss += yi * yi;
  }
  if (!(tss > 0)) return c.why = "the metric does not vary", c;
  for (int j = 0; j < k; ++j) {
    const double diagonal = L[j * k + j];
    for (int m = 0; m < j; ++m) L[j * k + j] -= L[j * k + m] * L[j * k + m];
    if (!(L[j * k + j] > 1e-12 * diagonal)) return c.why = "the quadratic fit failed (dependent regressors)", c;
    L[j * k + j] = std::sqrt(L[j * k + j]);
    for (int a = j + 1; a < k; ++a) {
      for (int m = 0; m < j; ++m) L[a * k + j] -= L[a * k + m] * L[j * k + m];
      L[a * k + j] /= L[j * k + j];
    }
  }
  // L L' b = X'y over the leading `terms` regressors.
  auto solve = [&](int terms) {
    std::vector<double> b(Xty.begin(), Xty.begin() + terms);
    for (int a = 0; a < terms; ++a) {
      for (int m = 0; m < a; ++m) b[a] -= L[a * k + m] * b[m];
      b[a] /= L[a * k + a];
    }
    for (int a = terms; a-- > 0;) {
      for (int m = a + 1; m < terms; ++m) b[a] -= L[m * k + a] * b[m];
      b[a] /= L[a * k + a];
    }
    return b;
  };
  const std::vector<double> b_quad = solve(k), b_lin = solve(linear);
  // The residuals themselves (a second pass: no cancellation in y'y - b'X'y).
  double rss_quad = 0, rss_lin = 0;
  for (size_t i = 0; i < y.size(); ++i) {
    if (!std::isfinite(y[i])) continue;
    features(i);
    double eq = y[i] - mean, el = eq;
    for (int a = 0; a < k; ++a) eq -= f[a] * b_quad[a];
    for (int a = 0; a < linear; ++a) el -= f[a] * b_lin[a];
    rss_quad += eq * eq, rss_lin += el * el;
  }
  if (!std::isfinite(rss_quad) || !std::isfinite(rss_lin)) return c.why = "the quadratic fit failed", c;
  c.estimated = true;
  c.share = std::max(0.0, rss_lin - rss_quad) / tss;
  c.linear_sigma = std::sqrt(std::max(0.0, tss - rss_lin) / static_cast<double>(c.n - 1));
  const double d1 = k - linear, d2 = static_cast<double>(c.n - k);
  c.p = rss_quad > 0 ? FTestP((std::max(0.0, rss_lin - rss_quad) / d1) / (rss_quad / d2), d1, d2)
                     : (rss_lin > 0 ? 0.0 : 1.0);
  return c;
}

/// The verdict's thresholds.
struct VerdictOptions {
  double delta = 0.05;  ///< the practical threshold: the ratio R is "the same" inside [1 - delta, 1 + delta]
  double alpha = 0.05;  ///< the level of all the study's verdicts together
  int family = 1;       ///< how many verdicts the study prints (Sidak: each at 1 - (1 - alpha)^(1/family))
};

/// Curvature is named as a DISAGREES' cause when its quadratic terms explain at least this
/// share of the variance (alone they move sigma by 1/sqrt(1 - 0.05) - 1 = 2.6 %: half the
/// practical threshold) and are significant.
constexpr double kCurvatureShare = 0.05;

enum class Outcome { kNone, kAgrees, kInconclusive, kDisagrees };

inline const char* OutcomeName(Outcome o) {
  switch (o) {
    case Outcome::kAgrees:
      return "agrees";
    case Outcome::kInconclusive:
      return "inconclusive";
    case Outcome::kDisagrees:
      return "DISAGREES";
    case Outcome::kNone:
      break;
  }
  return "none";
}

/// The decision on one metric and its sentence.
struct Decision {
  Outcome outcome = Outcome::kNone;
  double ratio = NAN, ratio_low = NAN, ratio_high = NAN;  ///< R and its corrected interval (NaN: none)
  double level = NAN;  ///< each verdict's confidence, 1 - (1 - (1 - alpha)^(1/family))
  double z = NAN;      ///< its two-sided normal quantile
  std::string text;
};

namespace tolerance_internal {
// (512: the longest verdict's format, ~230 characters, with five numbers of at most ~25 each.)
inline std::string Format(const char* format, double a, double b = 0, double c = 0, double d = 0, double e = 0) {
  char buffer[512];
  std::snprintf(buffer, sizeof(buffer), format, a, b, c, d, e);
  return buffer;
}
}  // namespace tolerance_internal

/// The per-verdict level and its quantile for `options` (Sidak).
inline void CorrectedLevel(const VerdictOptions& options, double* level, double* z) {
  const int family = std::max(options.family, 1);
  const double each = -std::expm1(std::log1p(-options.alpha) / family);  // 1 - (1 - alpha)^(1/family)
  *level = 1 - each;
  *z = -NormalQuantile(each / 2);
}

/// The decision (file comment) on the first order f against the Monte-Carlo m; `curvature`:
/// CurvatureOf the same samples (not estimated: no cause is named).
inline Decision Decide(const FirstOrder& f, const Moments& m, const Curvature& curvature,
                       const VerdictOptions& options = VerdictOptions()) {
  using tolerance_internal::Format;
  Decision d;
  CorrectedLevel(options, &d.level, &d.z);
  if (!f.complete) return d.text = "no first-order figure", d;
  if (m.n < 2) return d.text = "no Monte-Carlo figure", d;
  const double lo_band = 1 - options.delta, hi_band = 1 + options.delta;
  const std::string band = Format("%g %%", 100 * options.delta);
  if (m.sigma == 0) {
    if (f.rss == 0) {
      d.outcome = Outcome::kAgrees;
      return d.text = "agrees: the metric does not move (both sigmas 0)", d;
    }
    d.outcome = Outcome::kDisagrees;
    d.text = "DISAGREES: first-order sigma " + Format("%.4g", f.rss) + " but the Monte-Carlo's samples do not move the metric";
    return d;
  }
  const double relative = m.sigma_se / m.sigma;  // the Monte-Carlo sigma's relative standard error
  const double half = d.z * relative;
  d.ratio = f.rss / m.sigma;
  d.ratio_low = d.ratio * std::exp(-half);
  d.ratio_high = d.ratio * std::exp(half);
  const std::string interval = Format("ratio %.4g [%.4g, %.4g]", d.ratio, d.ratio_low, d.ratio_high);
  const std::string uncertainty =
      Format("the Monte-Carlo's sigma %.4g +- %.2g (standard error, n = %.0f, kurtosis %.3g)", m.sigma, m.sigma_se,
             static_cast<double>(m.n), m.kurtosis);
  const bool significant = d.ratio == 0 || std::abs(std::log(d.ratio)) > half;
  const bool large = d.ratio < lo_band || d.ratio > hi_band;
  if (significant && large) {
    d.outcome = Outcome::kDisagrees;
    d.text = "DISAGREES: first-order sigma " + Format("%.4g is %.3g times ", f.rss, d.ratio) + uncertainty + " (" +
             interval + ", beyond " + band + ")";
    // The first order against the samples' own average slope (a linear fit's sigma).
    const bool slope_differs = curvature.estimated && curvature.linear_sigma > 0 &&
                               !(f.rss / curvature.linear_sigma >= lo_band && f.rss / curvature.linear_sigma <= hi_band);
    if (curvature.estimated && curvature.share >= kCurvatureShare && curvature.p < 1 - d.level) {
      d.text += Format(": the metric is not linear over the tolerances: curvature (its quadratic terms in the "
                       "parameters explain %.3g %% of its variance over the samples",
                       100 * curvature.share);
      d.text += curvature.p > 0 ? Format(", p = %.2g)", curvature.p) : std::string(", p < 1e-300)");
    } else if (slope_differs) {
      d.text += Format(": the metric is not linear over the tolerances: its slope at the nominal (the first order) "
                       "is not its slope over the samples (a linear fit to them gives sigma %.4g: first order / fit "
                       "%.3g; their quadratic terms explain %.3g %% of the variance)",
                       curvature.linear_sigma, f.rss / curvature.linear_sigma, 100 * curvature.share);
    } else if (curvature.estimated) {
      d.text += Format(": cause not identified from the samples (a linear fit to them gives sigma %.4g, their "
                       "quadratic terms explain %.3g %% of the variance): a kink (a max or min whose row changes), "
                       "a failure region or a heavy tail",
                       curvature.linear_sigma, 100 * curvature.share);
    } else {
      d.text += ": cause not identified (no quadratic fit: " + curvature.why + ")";
    }
    if (slope_differs || (curvature.estimated && curvature.share >= kCurvatureShare && curvature.p < 1 - d.level))
      d.text += ", as near a toggle, a change point or a peak that moves";
    return d;
  }
  if (d.ratio_low >= lo_band && d.ratio_high <= hi_band) {
    d.outcome = Outcome::kAgrees;
    d.text = "agrees within " + band + ": " + interval;
    return d;
  }
  d.outcome = Outcome::kInconclusive;
  // The samples that would decide: the interval's half-width (~ 1/sqrt(n)) small enough to fit
  // in the band around R (agreement) or to exclude 1 (disagreement).
  const double room = large ? std::abs(std::log(d.ratio)) : std::min(std::log(hi_band / d.ratio), std::log(d.ratio / lo_band));
  d.text = "inconclusive: " + interval + ": " + uncertainty;
  if (room > 0)
    d.text += Format("; about %.2g samples would tell ", static_cast<double>(m.n) * (half / room) * (half / room)) +
              band;
  return d;
}

/// The verdict's sentence without a curvature estimate (one verdict, 5 %, delta 5 %).
inline std::string Verdict(const FirstOrder& f, const Moments& m, const VerdictOptions& options = VerdictOptions()) {
  return Decide(f, m, Curvature(), options).text;
}

}  // namespace mechgen::study
