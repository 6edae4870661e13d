/**
 * \file reference_data.h
 * Reads the high-precision references written by make_reference (data/<model>.csv) and
 * measures how far a double-precision result is from them. Used by reference_test.cc and by
 * bench/accuracy. Header-only; depends on the standard library and Eigen.
 *
 * Error measures (dimensionless, so that one tolerance fits every model):
 *  - positions: |d phi_i| for an angle (radians: a link of length l moves its far end by
 *    l |d phi_i| <= l_max |d phi_i|), |d phi_i| / l_max for a displacement and |d r_P| / l_max
 *    for a point, l_max = length_scale (the largest distance between two points of a link);
 *  - K, K_P: each entry scaled the same way (a row of a length divided by l_max, a column of
 *    a length input multiplied by l_max), then max |dK| / max(1, max |K|): absolute where the
 *    coefficients are O(1), relative where they are large (near a singular position);
 *  - L, L_P: likewise, with both input columns j and k scaled.
 */
#pragma once

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

#include <Eigen/Core>

namespace mechgen::reference {

/// One configuration of a reference file, rounded to double.
struct Row {
  std::vector<double> q, phi, K, L, rP, KP, LP;
  double cond = 0;  ///< cond_1(Phi_phi) at 50 digits
};

struct Data {
  std::string model;
  int nq = 0, nphi = 0, np = 0;
  double length_scale = 1;
  std::vector<bool> q_is_angle, phi_is_angle;
  std::vector<Row> rows;

  // Accessors in the generated code's layouts.
  static double K(const Row& r, int nq, int i, int j) { return r.K[i * nq + j]; }

  /// Reads data/<model>.csv; false with *error set when it is missing or malformed.
  bool Load(const std::string& path, std::string* error) {
    std::ifstream in(path);
    if (!in) {
      *error = "cannot open " + path + " (regenerate: cmake --build <build> --target reference_data)";
      return false;
    }
    std::string line;
    bool have_header = false;
    while (std::getline(in, line)) {
      if (line.empty()) continue;
      if (line[0] == '#') {
        std::istringstream s(line.substr(1));
        std::string key;
        s >> key;
        if (key == "model:") s >> model;
        if (key.rfind("nq=", 0) == 0) {
          std::sscanf(line.c_str(), "# nq=%d nphi=%d npoints=%d", &nq, &nphi, &np);
        }
        if (key.rfind("length_scale=", 0) == 0) length_scale = std::atof(key.c_str() + 13);
        if (key == "q:" || key == "phi:") {
          std::string name;
          while (s >> name) {
            const bool angle = name.find("[angle]") != std::string::npos;
            (key == "q:" ? q_is_angle : phi_is_angle).push_back(angle);
          }
        }
        continue;
      }
      if (!have_header) {  // the column names
        have_header = true;
        continue;
      }
      std::vector<double> v;
      std::istringstream s(line);
      std::string cell;
      while (std::getline(s, cell, ',')) v.push_back(std::strtod(cell.c_str(), nullptr));
      const size_t nq2 = static_cast<size_t>(nq * nq);
      const size_t want = static_cast<size_t>(nq + nphi) + static_cast<size_t>(nphi) * (nq + nq2) +
                          static_cast<size_t>(2 * np) * (1 + nq + nq2) + 1;
      if (v.size() != want) {
        *error = path + ": a row has " + std::to_string(v.size()) + " cells, expected " +
                 std::to_string(want);
        return false;
      }
      Row r;
      size_t at = 0;
      auto take = [&](size_t n, std::vector<double>* out) {
        out->assign(v.begin() + static_cast<long>(at), v.begin() + static_cast<long>(at + n));
        at += n;
      };
      take(static_cast<size_t>(nq), &r.q);
      take(static_cast<size_t>(nphi), &r.phi);
      take(static_cast<size_t>(nphi * nq), &r.K);
      take(static_cast<size_t>(nphi) * nq2, &r.L);
      take(static_cast<size_t>(2 * np), &r.rP);
      take(static_cast<size_t>(2 * np * nq), &r.KP);
      take(static_cast<size_t>(2 * np) * nq2, &r.LP);
      r.cond = v[at];
      rows.push_back(std::move(r));
    }
    if (nq <= 0 || nphi <= 0 || rows.empty() || static_cast<int>(q_is_angle.size()) != nq ||
        static_cast<int>(phi_is_angle.size()) != nphi) {
      *error = path + ": incomplete header or no rows";
      return false;
    }
    return true;
  }

  /// Scale of row i of phi (1 for an angle, 1/l_max for a length) and column j of q.
  double PhiScale(int i) const { return phi_is_angle[static_cast<size_t>(i)] ? 1 : 1 / length_scale; }
  double QScale(int j) const { return q_is_angle[static_cast<size_t>(j)] ? 1 : length_scale; }

  /// Position error of phi (kNphi) against row r.
  template <class V>
  double PhiError(const Row& r, const V& phi) const {
    double e = 0;
    for (int i = 0; i < nphi; ++i) e = std::max(e, std::fabs(phi(i) - r.phi[static_cast<size_t>(i)]) * PhiScale(i));
    return std::isnan(e) ? INFINITY : e;
  }
  /// Position error of r_P (2 x np, column per point) against row r.
  template <class M>
  double PointError(const Row& r, const M& rP) const {
    double e = 0;
    for (int m = 0; m < np; ++m)
      for (int a = 0; a < 2; ++a)
        e = std::max(e, std::fabs(rP(a, m) - r.rP[static_cast<size_t>(2 * m + a)]) / length_scale);
    return std::isnan(e) ? INFINITY : e;
  }
  /// Error of K (nphi x nq).
  template <class M>
  double KError(const Row& r, const M& K) const {
    double e = 0, scale = 1;
    for (int i = 0; i < nphi; ++i)
      for (int j = 0; j < nq; ++j) {
        const double s = PhiScale(i) * QScale(j);
        const double ref = r.K[static_cast<size_t>(i * nq + j)];
        e = std::max(e, std::fabs(K(i, j) - ref) * s);
        scale = std::max(scale, std::fabs(ref) * s);
      }
    return std::isnan(e) ? INFINITY : e / scale;
  }
  /// Error of L (nphi x nq^2, L(i, j + nq k)).
  template <class M>
  double LError(const Row& r, const M& L) const {
    double e = 0, scale = 1;
    for (int i = 0; i < nphi; ++i)
      for (int k = 0; k < nq; ++k)
        for (int j = 0; j < nq; ++j) {
          const int c = j + nq * k;
          const double s = PhiScale(i) * QScale(j) * QScale(k);
          const double ref = r.L[static_cast<size_t>(i * nq * nq + c)];
          e = std::max(e, std::fabs(L(i, c) - ref) * s);
          scale = std::max(scale, std::fabs(ref) * s);
        }
    return std::isnan(e) ? INFINITY : e / scale;
  }
  /// Error of K_P (2 np x nq).
  template <class M>
  double KPError(const Row& r, const M& KP) const {
    double e = 0, scale = 1;
    for (int row = 0; row < 2 * np; ++row)
      for (int j = 0; j < nq; ++j) {
        const double s = QScale(j) / length_scale;
        const double ref = r.KP[static_cast<size_t>(row * nq + j)];
        e = std::max(e, std::fabs(KP(row, j) - ref) * s);
        scale = std::max(scale, std::fabs(ref) * s);
      }
    return std::isnan(e) ? INFINITY : e / scale;
  }
  /// Error of L_P (2 np x nq^2).
  template <class M>
  double LPError(const Row& r, const M& LP) const {
    double e = 0, scale = 1;
    for (int row = 0; row < 2 * np; ++row)
      for (int k = 0; k < nq; ++k)
        for (int j = 0; j < nq; ++j) {
          const int c = j + nq * k;
          const double s = QScale(j) * QScale(k) / length_scale;
          const double ref = r.LP[static_cast<size_t>(row * nq * nq + c)];
          e = std::max(e, std::fabs(LP(row, c) - ref) * s);
          scale = std::max(scale, std::fabs(ref) * s);
        }
    return std::isnan(e) ? INFINITY : e / scale;
  }
};

}  // namespace mechgen::reference
