/**
 * \file study/rows.h
 * A study's outputs from its packed results (Study::Width() doubles per sample: the status
 * code, the metrics, the envelope's path; study/run.h): the CSV rows of a chunk of samples,
 * made by the thread that ran the chunk and written in sample order by one writer, and the
 * statistics of each metric over the ok samples (n, mean, sigma, quantiles, histogram) from
 * the metric's values in sample order: the same bytes whatever the threads or ranks that ran
 * the samples, with or without the rows (rows: none), and whatever the threads that compute
 * them (fixed blocks' sums added in block order, counts, exact order statistics).
 *
 * The CSV's columns are one column table (SampleColumns: table/columns.h, a column's name, unit,
 * meaning and cell together): io/csv.h's WriteCsvHeader writes its head, AppendRows its rows;
 * so are the statistics' (SummaryColumns, HistogramColumns), the tolerance analysis'
 * (ToleranceColumns) and the envelope's (EnvelopeColumns), each row's cells by AppendRow.
 * Numbers are written as printf's "%.17g" (they round-trip), by std::to_chars with the
 * general format and precision 17, which the standard defines as printf's conversion (the
 * same characters; ~4 times faster here: 60 ns against 260 ns a number); NaN as "nan".
 */
#pragma once

#include <algorithm>
#include <charconv>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <string>
#include <thread>
#include <vector>

#include "mechgen/study/shards.h"
#include "mechgen/study/tolerance.h"
#include "mechgen/table/columns.h"

namespace mechgen::study {

/// x as "%.17g" at out (at least 32 chars of room); NaN as "nan". Returns the end.
inline char* FormatG17(double x, char* out) {
  if (std::isnan(x)) {
    out[0] = 'n', out[1] = 'a', out[2] = 'n';
    return out + 3;
  }
  return std::to_chars(out, out + 32, x, std::chars_format::general, 17).ptr;
}

inline std::string G17(double x) {
  char buffer[40];
  return std::string(buffer, FormatG17(x, buffer));
}

/// One row of the study's CSV: a sample's index, its parameters' values and its packed result
/// (Study::Pack's layout: the status code, then the metrics).
struct SampleRow {
  uint64_t index = 0;
  const double* values = nullptr;
  const double* result = nullptr;
};

/// What one of the study's metrics is: its name, unit and meaning (Study::Unit, Description).
struct MetricColumn {
  std::string name, unit, description;
};

/**
 * \brief The study's CSV columns: sample, each varied parameter (`parameters`, in the study's
 *        order), each metric, status. A number column's cell is "%.17g" of its value
 *        (AppendRows), the status the text of its code.
 */
inline table::Columns<SampleRow> SampleColumns(const std::vector<std::string>& parameters,
                                               const std::vector<MetricColumn>& metrics) {
  table::Columns<SampleRow> columns;
  table::Builder<SampleRow> add(&columns);
  add.Number("sample", "1", "the sample's index, 0-based, in the study's order",
             [](const SampleRow& r) { return static_cast<double>(r.index); });  // (exact: <= kMaxSamples)
  for (size_t k = 0; k < parameters.size(); ++k)
    add.Number(parameters[k], "model units", "the model's parameter " + parameters[k],
               [k](const SampleRow& r) { return r.values[k]; });
  for (size_t k = 0; k < metrics.size(); ++k)
    add.Number(metrics[k].name, metrics[k].unit, metrics[k].description,
               [k](const SampleRow& r) { return r.result[1 + k]; });
  add.Text("status",
           "ok, rows_failed (some rows did not converge), not_assembled, cycle_failed (flywheel, engine), "
           "simulation_failed (simulate: the run ended before t_end)",
           [](const SampleRow& r) { return std::string(StatusOfCode(r.result[0])); });
  return columns;
}

/**
 * \brief Appends the cells of `row` in `columns` to *text, comma-separated, and the line's end:
 *        a number column's value as "%.17g" (NaN: "nan"), a text column's text as it is.
 */
template <class Row>
void AppendRow(const table::Columns<Row>& columns, const Row& row, std::string* text) {
  char buffer[48];
  buffer[0] = ',';
  for (size_t c = 0; c < columns.size(); ++c) {
    const table::Column<Row>& column = columns[c];
    if (column.text) {
      if (c > 0) text->push_back(',');
      text->append(column.text(row));
    } else {
      text->append(buffer + (c == 0 ? 1 : 0), FormatG17(column.value(row), buffer + 1));
    }
  }
  text->push_back('\n');
}

/**
 * \brief Appends the CSV rows of samples first .. first + n - 1 to *text, the cells of
 *        `columns` (SampleColumns): per sample i (from 0 here) its row, the values
 *        values[i * parameters ..] and the packed result packed[i * width ..].
 */
inline void AppendRows(const table::Columns<SampleRow>& columns,
                       uint64_t first,
                       uint64_t n,
                       const double* values,
                       size_t parameters,
                       const double* packed,
                       uint64_t width,
                       std::string* text) {
  for (uint64_t i = 0; i < n; ++i) AppendRow(columns, SampleRow{first + i, values + i * parameters, packed + i * width}, text);
}

/// The quantiles of ColumnStatistics, as probabilities.
inline const std::vector<double>& SummaryQuantiles() {
  static const std::vector<double> p = {0.01, 0.05, 0.25, 0.5, 0.75, 0.95, 0.99};
  return p;
}

/// The statistics of one metric over the samples (its finite values).
struct ColumnStatistics {
  Moments moments;  ///< n, mean, sigma (n - 1) and their intervals: MomentsOf
  double min = NAN, max = NAN;
  /// SummaryQuantiles()'s p-quantile: the ceil(p n)-th smallest value (nearest rank; exact).
  std::vector<double> quantiles;
  /// `bins` equal bins from min to max (the last includes max): the count in each; bin b
  /// takes v with min(bins - 1, floor((v - min) / width)) == b, width = (max - min) / bins
  /// (0: every value in bin 0).
  std::vector<uint64_t> histogram;
  double bin_width = NAN;
};

/**
 * \brief The statistics of the finite values of x (a non-finite value is left out) on
 *        `threads` threads, the same bits for any number: the moments are MomentsOf's (sums
 *        of fixed blocks added in block order), min, max and the histogram's counts do not
 *        depend on an order, and each quantile is an exact order statistic found by counting
 *        the values in 65536 equal buckets from min to max (a monotone map: the k-th smallest
 *        is in the bucket where the counts pass k), then selecting within that bucket.
 */
inline ColumnStatistics StatisticsOf(const std::vector<double>& x,
                                     int bins,
                                     int threads = 1,
                                     const Moments* moments = nullptr) {
  ColumnStatistics s;
  const uint64_t n_all = x.size(), blocks = (n_all + kMomentBlock - 1) / kMomentBlock;
  threads = std::max(threads, 1);
  s.moments = moments != nullptr ? *moments : MomentsOf(x, threads);  // (the caller's MomentsOf(x))
  s.quantiles.assign(SummaryQuantiles().size(), NAN);
  s.histogram.assign(static_cast<size_t>(std::max(bins, 1)), 0);
  const uint64_t n = static_cast<uint64_t>(std::max<long long>(s.moments.n, 0));
  if (n == 0) return s;
  // min and max (of the finite values: MomentsOf counted them).
  std::vector<double> lo(threads, INFINITY), hi(threads, -INFINITY);
  ForEachBlock(blocks, threads, [&](uint64_t b, int t) {
    for (uint64_t i = b * kMomentBlock; i < std::min(n_all, (b + 1) * kMomentBlock); ++i)
      if (std::isfinite(x[i])) lo[t] = std::min(lo[t], x[i]), hi[t] = std::max(hi[t], x[i]);
  });
  s.min = *std::min_element(lo.begin(), lo.end());
  s.max = *std::max_element(hi.begin(), hi.end());
  // The histogram and the buckets: counts per thread, added (integers: any order).
  const size_t nbins = s.histogram.size();
  s.bin_width = (s.max - s.min) / static_cast<double>(nbins);
  constexpr uint64_t kBuckets = 65536;
  const double scale = s.max > s.min ? static_cast<double>(kBuckets) / (s.max - s.min) : 0;
  auto bucket_of = [&](double v) {
    const double f = std::floor((v - s.min) * scale);
    return f <= 0 ? uint64_t(0) : static_cast<uint64_t>(std::min(f, static_cast<double>(kBuckets - 1)));
  };
  auto bin_of = [&](double v) {
    if (!(s.bin_width > 0)) return size_t(0);
    const double f = std::floor((v - s.min) / s.bin_width);
    return f <= 0 ? size_t(0) : static_cast<size_t>(std::min(f, static_cast<double>(nbins - 1)));
  };
  std::vector<std::vector<uint64_t>> bucket_count(threads, std::vector<uint64_t>(kBuckets, 0)),
      bin_count(threads, std::vector<uint64_t>(nbins, 0));
  ForEachBlock(blocks, threads, [&](uint64_t b, int t) {
    for (uint64_t i = b * kMomentBlock; i < std::min(n_all, (b + 1) * kMomentBlock); ++i)
      if (std::isfinite(x[i])) ++bucket_count[t][bucket_of(x[i])], ++bin_count[t][bin_of(x[i])];
  });
  std::vector<uint64_t> buckets(kBuckets, 0);
  for (int t = 0; t < threads; ++t) {
    for (uint64_t k = 0; k < kBuckets; ++k) buckets[k] += bucket_count[t][k];
    for (size_t k = 0; k < nbins; ++k) s.histogram[k] += bin_count[t][k];
  }
  // Each quantile's rank, its bucket and its place there.
  const size_t nq = SummaryQuantiles().size();
  std::vector<uint64_t> rank(nq), bucket(nq), before(nq);
  for (size_t q = 0; q < nq; ++q) {
    rank[q] =
        std::clamp<uint64_t>(static_cast<uint64_t>(std::ceil(SummaryQuantiles()[q] * static_cast<double>(n))), 1, n);
    uint64_t below = 0, k = 0;
    while (below + buckets[k] < rank[q]) below += buckets[k++];
    bucket[q] = k, before[q] = below;
  }
  // The values of those buckets (any order: only their order statistics are read).
  std::vector<std::vector<double>> found(threads);
  ForEachBlock(blocks, threads, [&](uint64_t b, int t) {
    for (uint64_t i = b * kMomentBlock; i < std::min(n_all, (b + 1) * kMomentBlock); ++i)
      if (std::isfinite(x[i])) {
        const uint64_t k = bucket_of(x[i]);
        if (std::find(bucket.begin(), bucket.end(), k) != bucket.end()) found[t].push_back(x[i]);
      }
  });
  std::vector<double> in;
  for (const std::vector<double>& f : found) in.insert(in.end(), f.begin(), f.end());
  for (size_t q = 0; q < nq; ++q) {
    std::vector<double> v;
    for (double value : in)
      if (bucket_of(value) == bucket[q]) v.push_back(value);
    const auto at = v.begin() + static_cast<std::ptrdiff_t>(rank[q] - before[q] - 1);
    std::nth_element(v.begin(), at, v.end());
    s.quantiles[q] = *at;
  }
  return s;
}

/// One row of the summary CSV: a metric and its statistics over the ok samples.
struct SummaryRow {
  std::string metric, unit;
  const ColumnStatistics* statistics = nullptr;
};

/// The summary CSV's columns: metric, unit, then n, mean, sigma, min, the SummaryQuantiles()'
/// (p01 .. p99) and max, each a number in the metric's unit (n: a count).
inline table::Columns<SummaryRow> SummaryColumns() {
  table::Columns<SummaryRow> columns;
  table::Builder<SummaryRow> add(&columns);
  add.Text("metric", "the metric (the study's CSV's column)", [](const SummaryRow& r) { return r.metric; });
  add.Text("unit", "the metric's unit, of every number of the row but n", [](const SummaryRow& r) { return r.unit; });
  add.Number("n", "1", "the finite values of the ok samples",
             [](const SummaryRow& r) { return static_cast<double>(r.statistics->moments.n); });
  add.Number("mean", "the metric's", "their mean (two passes in sample order)",
             [](const SummaryRow& r) { return r.statistics->moments.mean; });
  add.Number("sigma", "the metric's", "their standard deviation (n - 1)",
             [](const SummaryRow& r) { return r.statistics->moments.sigma; });
  add.Number("min", "the metric's", "the smallest", [](const SummaryRow& r) { return r.statistics->min; });
  for (size_t q = 0; q < SummaryQuantiles().size(); ++q) {
    char name[16];
    std::snprintf(name, sizeof name, "p%02d", static_cast<int>(std::lround(100 * SummaryQuantiles()[q])));
    add.Number(name, "the metric's", "the p-quantile: the ceil(p n)-th smallest value (exact)",
               [q](const SummaryRow& r) { return r.statistics->quantiles[q]; });
  }
  add.Number("max", "the metric's", "the largest", [](const SummaryRow& r) { return r.statistics->max; });
  return columns;
}

/// One row of the histogram CSV: a bin of a metric.
struct HistogramRow {
  std::string metric;
  uint64_t bin = 0, count = 0;
  double low = NAN, high = NAN;
};

/// The histogram CSV's columns: metric, bin, low, high, count.
inline table::Columns<HistogramRow> HistogramColumns() {
  table::Columns<HistogramRow> columns;
  table::Builder<HistogramRow> add(&columns);
  add.Text("metric", "the metric (the study's CSV's column)", [](const HistogramRow& r) { return r.metric; });
  add.Number("bin", "1", "the bin's index, from the metric's min",
             [](const HistogramRow& r) { return static_cast<double>(r.bin); });
  add.Number("low", "the metric's", "the bin's lower end (low <= v)", [](const HistogramRow& r) { return r.low; });
  add.Number("high", "the metric's", "its upper end (v < high; the last bin includes max)",
             [](const HistogramRow& r) { return r.high; });
  add.Number("count", "1", "the finite values of the ok samples in the bin",
             [](const HistogramRow& r) { return static_cast<double>(r.count); });
  return columns;
}

/// One row of the tolerance CSV: a metric, its value at the nominal, its first order, the
/// Monte-Carlo's figures over the ok samples, the curvature, the decision and the verdict's text.
struct ToleranceRow {
  std::string metric, unit;
  double nominal = NAN;
  const FirstOrder* first = nullptr;
  const Moments* moments = nullptr;
  const Curvature* curvature = nullptr;
  const Decision* decision = nullptr;
  std::string verdict;
};

/// The tolerance CSV's columns: metric, unit, nominal, the first order (fo_sigma, fo_worst,
/// clearance), the Monte-Carlo's (mc_n, mc_mean and sigma with their 95 % intervals, mc_sigma_se,
/// mc_kurtosis), the ratio fo_sigma / mc_sigma with its interval, quadratic_share,
/// linear_fit_sigma, decision and the verdict (quoted: it holds commas).
inline table::Columns<ToleranceRow> ToleranceColumns() {
  using R = ToleranceRow;
  table::Columns<R> columns;
  table::Builder<R> add(&columns);
  add.Text("metric", "the metric (the study's CSV's column)", [](const R& r) { return r.metric; });
  add.Text("unit", "the metric's unit, of the numbers of the row but mc_n, mc_kurtosis, the ratios and shares",
           [](const R& r) { return r.unit; });
  add.Number("nominal", "the metric's", "the metric at the nominal design", [](const R& r) { return r.nominal; });
  add.Number("fo_sigma", "the metric's", "first-order root-sum-square sqrt(sum (dm/dp sigma_p)^2)",
             [](const R& r) { return r.first->rss; });
  add.Number("fo_worst", "the metric's", "first-order worst case sum |dm/dp| t_p (t: the tolerance)",
             [](const R& r) { return r.first->worst; });
  add.Number("clearance", "the metric's", "sum |dm/dp| c over the joint clearances (worst direction); nan: no figure",
             [](const R& r) { return r.first->complete ? r.first->clearance : NAN; });
  add.Number("mc_n", "1", "the ok samples with a finite value",
             [](const R& r) { return static_cast<double>(r.moments->n); });  // (exact: <= kMaxSamples)
  add.Number("mc_mean", "the metric's", "their mean", [](const R& r) { return r.moments->mean; });
  add.Number("mc_mean_low", "the metric's", "its 95 % interval's lower end", [](const R& r) { return r.moments->mean_low; });
  add.Number("mc_mean_high", "the metric's", "its upper end", [](const R& r) { return r.moments->mean_high; });
  add.Number("mc_sigma", "the metric's", "their standard deviation (n - 1)", [](const R& r) { return r.moments->sigma; });
  add.Number("mc_sigma_low", "the metric's", "its 95 % interval's lower end",
             [](const R& r) { return r.moments->sigma_low; });
  add.Number("mc_sigma_high", "the metric's", "its upper end", [](const R& r) { return r.moments->sigma_high; });
  add.Number("mc_sigma_se", "the metric's", "the standard error of mc_sigma from the sample kurtosis",
             [](const R& r) { return r.moments->sigma_se; });
  add.Number("mc_kurtosis", "1", "the sample kurtosis m4 / sigma^4", [](const R& r) { return r.moments->kurtosis; });
  add.Number("ratio", "1", "fo_sigma / mc_sigma", [](const R& r) { return r.decision->ratio; });
  add.Number("ratio_low", "1", "its corrected interval's lower end", [](const R& r) { return r.decision->ratio_low; });
  add.Number("ratio_high", "1", "its upper end", [](const R& r) { return r.decision->ratio_high; });
  add.Number("quadratic_share", "1",
             "the share of the variance that the quadratic terms in the standardized parameters explain beyond the "
             "linear ones",
             [](const R& r) { return r.curvature->share; });
  add.Number("linear_fit_sigma", "the metric's", "the sigma of a linear fit to the samples",
             [](const R& r) { return r.curvature->linear_sigma; });
  add.Text("decision", "agrees, DISAGREES, inconclusive or none (no figure)",
           [](const R& r) { return std::string(OutcomeName(r.decision->outcome)); });
  add.Text("verdict", "the verdict in words, in double quotes",
           [](const R& r) { return "\"" + r.verdict + "\""; });
  return columns;
}

/// One row of the envelope CSV: a row of the motion, the input there, the point's nominal
/// place and each axis' first order and Monte-Carlo figures.
struct EnvelopeRow {
  uint64_t row = 0;
  double input = NAN, x = NAN, y = NAN;
  const FirstOrder *first_x = nullptr, *first_y = nullptr;
  const Moments *moments_x = nullptr, *moments_y = nullptr;
};

/// The envelope CSV's columns: row, the input (`input`: the model's first input's name), the
/// point's nominal x and y, the first-order sigma and worst case of x and y, the Monte-Carlo's
/// n and sigma of x and y with their 95 % intervals.
inline table::Columns<EnvelopeRow> EnvelopeColumns(const std::string& input) {
  using R = EnvelopeRow;
  table::Columns<R> columns;
  table::Builder<R> add(&columns);
  add.Number("row", "1", "the row of the motion, 0-based", [](const R& r) { return static_cast<double>(r.row); });
  add.Number(input, "rad or model length", "the input there", [](const R& r) { return r.input; });
  add.Number("x_nominal", "model length", "the point's x at the nominal design", [](const R& r) { return r.x; });
  add.Number("y_nominal", "model length", "its y", [](const R& r) { return r.y; });
  add.Number("fo_sigma_x", "model length", "first-order sigma of x from the generated dr_P/dp",
             [](const R& r) { return r.first_x->rss; });
  add.Number("fo_sigma_y", "model length", "of y", [](const R& r) { return r.first_y->rss; });
  add.Number("fo_worst_x", "model length", "first-order worst case of x", [](const R& r) { return r.first_x->worst; });
  add.Number("fo_worst_y", "model length", "of y", [](const R& r) { return r.first_y->worst; });
  add.Number("mc_n", "1", "the ok samples with a finite x",
             [](const R& r) { return static_cast<double>(r.moments_x->n); });  // (exact: <= kMaxSamples)
  add.Number("mc_sigma_x", "model length", "the Monte-Carlo's sigma of x over the ok samples",
             [](const R& r) { return r.moments_x->sigma; });
  add.Number("mc_sigma_x_low", "model length", "its 95 % interval's lower end",
             [](const R& r) { return r.moments_x->sigma_low; });
  add.Number("mc_sigma_x_high", "model length", "its upper end", [](const R& r) { return r.moments_x->sigma_high; });
  add.Number("mc_sigma_y", "model length", "the Monte-Carlo's sigma of y", [](const R& r) { return r.moments_y->sigma; });
  add.Number("mc_sigma_y_low", "model length", "its 95 % interval's lower end",
             [](const R& r) { return r.moments_y->sigma_low; });
  add.Number("mc_sigma_y_high", "model length", "its upper end", [](const R& r) { return r.moments_y->sigma_high; });
  return columns;
}

}  // namespace mechgen::study
