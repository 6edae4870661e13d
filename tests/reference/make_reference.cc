// make_reference: high-precision kinematic references for a model, by a path independent
// of the emitted code.
//
// It reads the model with the generator's own front end (LoadModel, BuildTopology,
// DeriveKinematics: the loop-closure equations Phi(q, phi; p) and the requested points as
// GiNaC expressions) and then does everything else itself, in CLN floating point at
// GiNaC::Digits = 50:
//   positions  damped Newton on Phi = 0 from the model's assembly guess, then continuation
//              to each requested q in sub-steps of at most 1 deg (predictor phi + K dq,
//              Newton to |dphi| < 1e-45, step halved when Newton fails or the branch
//              sign(det Phi_phi) changes);
//   K          Phi_phi K = -Phi_q, solved by Gaussian elimination with partial pivoting;
//   L          Phi_phi L(:, j + nq k) = -gamma(j, k), gamma_i(j, k) = sum_ab
//              d2 Phi_i / dx_a dx_b V_aj V_bk with x = (q, phi), V = [I; K];
//   points     r_P, K_P = dr_P/dx V, L_P = sum_ab d2 r_P/dx_a dx_b V_aj V_bk + dr_P/dphi L.
// Jacobians and Hessians are differentiated here from Phi (GiNaC::diff), not taken from the
// generator's derivation, and nothing of the emitted double code is evaluated.
// Parameters and q are the exact binary values of the doubles the generated code sees
// (converted to rationals), so the reference is the exact answer to the double-precision
// problem, not to its decimal spelling.
//
// Usage: make_reference MODEL.yaml OUT.csv [--steps N] [--cluster DEG] [--follow-change-points yes]
//   one input:  N + 1 equally spaced values over the model's input range (N for a full
//               turn, whose last value would repeat the first); --cluster DEG adds
//               DEG -+ 10^(-k/4) rad, k = 8..40, sorted in (to resolve a near-singular spot);
//   two inputs: an (N + 1) x (N + 1) grid, row by row in a serpentine (continuation) order.
//   --follow-change-points yes: the continuation passes a change point (det Phi_phi changing
//               sign on one smooth curve: a parallelogram folded flat) on the curve it is on,
//               instead of failing there; the number of crossings is printed on stderr.
#include <ginac/ginac.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <iostream>
#include <sstream>
#include <string>
#include <vector>

#include "analysis/kinematics.h"
#include "analysis/topology.h"
#include "model/model.h"

namespace {

using GiNaC::ex;
using GiNaC::numeric;

// A long-float numeric vector / matrix (row-major).
using Vector = std::vector<numeric>;
struct Matrix {
  int rows = 0, cols = 0;
  std::vector<numeric> a;
  Matrix(int r = 0, int c = 0) : rows(r), cols(c), a(static_cast<size_t>(r * c), numeric(0)) {}
  numeric& operator()(int i, int j) { return a[static_cast<size_t>(i * cols + j)]; }
  const numeric& operator()(int i, int j) const { return a[static_cast<size_t>(i * cols + j)]; }
};

// The exact value of a double as a rational m * 2^e.
numeric ExactRational(double x) {
  if (x == 0) return numeric(0);
  int e = 0;
  const double m = std::frexp(x, &e);  // x = m 2^e, 0.5 <= |m| < 1
  const long mantissa = static_cast<long>(std::ldexp(m, 53));
  return numeric(mantissa) * numeric(2).power(numeric(e - 53));
}

numeric ToFloat(const ex& e) {
  const ex v = e.evalf();
  if (!GiNaC::is_a<numeric>(v)) {
    std::ostringstream os;
    os << "make_reference: expression did not evaluate to a number: " << v;
    throw std::runtime_error(os.str());
  }
  return GiNaC::ex_to<numeric>(v);
}

numeric Abs(const numeric& x) { return GiNaC::abs(x); }

// Solves A X = B (A n x n, B n x m) by Gaussian elimination with partial pivoting.
// Returns false when a pivot is exactly zero.
bool Solve(Matrix A, Matrix B, Matrix* X) {
  const int n = A.rows, m = B.cols;
  for (int c = 0; c < n; ++c) {
    int p = c;
    for (int r = c + 1; r < n; ++r)
      if (Abs(A(r, c)) > Abs(A(p, c))) p = r;
    if (A(p, c).is_zero()) return false;
    if (p != c) {
      for (int j = 0; j < n; ++j) std::swap(A(p, j), A(c, j));
      for (int j = 0; j < m; ++j) std::swap(B(p, j), B(c, j));
    }
    for (int r = c + 1; r < n; ++r) {
      const numeric f = A(r, c) / A(c, c);
      if (f.is_zero()) continue;
      for (int j = c; j < n; ++j) A(r, j) = A(r, j) - f * A(c, j);
      for (int j = 0; j < m; ++j) B(r, j) = B(r, j) - f * B(c, j);
    }
  }
  *X = Matrix(n, m);
  for (int j = 0; j < m; ++j) {
    for (int r = n - 1; r >= 0; --r) {
      numeric s = B(r, j);
      for (int k = r + 1; k < n; ++k) s = s - A(r, k) * (*X)(k, j);
      (*X)(r, j) = s / A(r, r);
    }
  }
  return true;
}

numeric Determinant(Matrix A) {
  const int n = A.rows;
  numeric det(1);
  for (int c = 0; c < n; ++c) {
    int p = c;
    for (int r = c + 1; r < n; ++r)
      if (Abs(A(r, c)) > Abs(A(p, c))) p = r;
    if (A(p, c).is_zero()) return numeric(0);
    if (p != c) {
      for (int j = 0; j < n; ++j) std::swap(A(p, j), A(c, j));
      det = -det;
    }
    det = det * A(c, c);
    for (int r = c + 1; r < n; ++r) {
      const numeric f = A(r, c) / A(c, c);
      for (int j = c; j < n; ++j) A(r, j) = A(r, j) - f * A(c, j);
    }
  }
  return det;
}

numeric Norm1(const Matrix& A) {
  numeric best(0);
  for (int j = 0; j < A.cols; ++j) {
    numeric s(0);
    for (int i = 0; i < A.rows; ++i) s = s + Abs(A(i, j));
    if (s > best) best = s;
  }
  return best;
}

int Sign(const numeric& x) { return x.is_zero() ? 0 : (x.is_positive() ? 1 : -1); }

// The model with parameters substituted, its derivatives, and a numeric evaluator.
class Reference {
 public:
  explicit Reference(const std::string& path) : model_(mechgen::LoadModel(path)) {
    const mechgen::Topology topology = mechgen::BuildTopology(model_);
    kin_ = mechgen::DeriveKinematics(model_, topology);
    nq_ = kin_.nq();
    nphi_ = kin_.nphi();
    nc_ = kin_.nc();
    np_ = static_cast<int>(kin_.points.size());
    if (nc_ != nphi_) throw std::runtime_error("make_reference: Phi is not square");
    for (const mechgen::Parameter& p : model_.params) params_[p.symbol] = ExactRational(p.value);
    for (const auto& c : kin_.q) x_.push_back(c.symbol);
    for (const auto& c : kin_.phi) x_.push_back(c.symbol);
    const int nx = nq_ + nphi_;
    // Residual rows then point coordinates: f = (Phi_0..Phi_{nc-1}, x_P0, y_P0, ...).
    for (const ex& e : kin_.Phi) f_.push_back(e.subs(params_));
    for (const auto& r : kin_.points) {
      f_.push_back(r[0].subs(params_));
      f_.push_back(r[1].subs(params_));
    }
    df_.assign(f_.size(), std::vector<ex>(static_cast<size_t>(nx)));
    d2f_.assign(f_.size(), std::vector<ex>(static_cast<size_t>(nx * nx)));
    for (size_t i = 0; i < f_.size(); ++i) {
      for (int a = 0; a < nx; ++a) {
        df_[i][static_cast<size_t>(a)] = f_[i].diff(GiNaC::ex_to<GiNaC::symbol>(x_[a]));
        for (int b = 0; b < nx; ++b)
          d2f_[i][static_cast<size_t>(a * nx + b)] =
              df_[i][static_cast<size_t>(a)].diff(GiNaC::ex_to<GiNaC::symbol>(x_[b]));
      }
    }
    length_scale_ = LengthScale();
  }

  const mechgen::Model& model() const { return model_; }
  const mechgen::Kinematics& kin() const { return kin_; }
  int nq() const { return nq_; }
  int nphi() const { return nphi_; }
  int np() const { return np_; }

  // The largest distance between two points of one link, with the default parameters.
  double LengthScale() const {
    double best = 0;
    for (const mechgen::Link& link : model_.links) {
      for (size_t i = 0; i < link.points.size(); ++i)
        for (size_t j = i + 1; j < link.points.size(); ++j) {
          const double dx = ToFloat((link.points[i].x - link.points[j].x).subs(params_)).to_double();
          const double dy = ToFloat((link.points[i].y - link.points[j].y).subs(params_)).to_double();
          best = std::max(best, std::hypot(dx, dy));
        }
    }
    return best;
  }

  GiNaC::exmap Point(const Vector& q, const Vector& phi) const {
    GiNaC::exmap m;
    for (int j = 0; j < nq_; ++j) m[x_[j]] = q[static_cast<size_t>(j)];
    for (int i = 0; i < nphi_; ++i) m[x_[nq_ + i]] = phi[static_cast<size_t>(i)];
    return m;
  }

  // Phi and Phi_phi at (q, phi).
  void EvalPhi(const Vector& q, const Vector& phi, Vector* Phi, Matrix* Phi_phi) const {
    const GiNaC::exmap m = Point(q, phi);
    Phi->assign(static_cast<size_t>(nc_), numeric(0));
    *Phi_phi = Matrix(nc_, nphi_);
    for (int i = 0; i < nc_; ++i) {
      (*Phi)[static_cast<size_t>(i)] = ToFloat(f_[static_cast<size_t>(i)].subs(m));
      for (int k = 0; k < nphi_; ++k)
        (*Phi_phi)(i, k) = ToFloat(df_[static_cast<size_t>(i)][static_cast<size_t>(nq_ + k)].subs(m));
    }
  }

  // Newton at fixed q; true when |dphi|_inf < 10^-(Digits - 5) within 60 iterations and
  // the residual never grew by more than 10x (a step that jumps branches or diverges).
  bool Newton(const Vector& q, Vector* phi, bool damped) const {
    const numeric tol = numeric(10).power(numeric(-(static_cast<long>(GiNaC::Digits) - 5)));
    Vector Phi;
    Matrix A;
    EvalPhi(q, *phi, &Phi, &A);
    numeric norm = InfNorm(Phi);
    for (int it = 0; it < 60; ++it) {
      Matrix B(nc_, 1), dphi;
      for (int i = 0; i < nc_; ++i) B(i, 0) = -Phi[static_cast<size_t>(i)];
      if (!Solve(A, B, &dphi)) return false;
      numeric step_norm(0);
      for (int i = 0; i < nphi_; ++i) step_norm = std::max(step_norm, Abs(dphi(i, 0)));
      numeric t(1);
      Vector trial;
      numeric trial_norm;
      for (int halvings = 0;; ++halvings) {
        trial = *phi;
        for (int i = 0; i < nphi_; ++i)
          trial[static_cast<size_t>(i)] = trial[static_cast<size_t>(i)] + t * dphi(i, 0);
        Vector P;
        Matrix Ap;
        EvalPhi(q, trial, &P, &Ap);
        trial_norm = InfNorm(P);
        if (!damped || trial_norm < norm || halvings == 30 || step_norm < tol) {
          Phi = P;
          A = Ap;
          break;
        }
        t = t / 2;
      }
      if (!damped && trial_norm > norm * 10 && norm > tol) return false;
      *phi = trial;
      norm = trial_norm;
      if (step_norm < tol) return true;
    }
    return false;
  }

  static numeric InfNorm(const Vector& v) {
    numeric n(0);
    for (const numeric& x : v) n = std::max(n, Abs(x));
    return n;
  }

  struct Result {
    Matrix Phi_phi, K, L, r_P, K_P, L_P;
    numeric cond, det;
  };

  // K alone (Phi_phi K = -Phi_q), for the continuation's predictor: the Hessians and points of
  // Coefficients are not needed there and cost most of its time.
  bool Tangent(const Vector& q, const Vector& phi, Matrix* K) const {
    const GiNaC::exmap m = Point(q, phi);
    Matrix Phi_phi(nc_, nphi_), Phi_q(nc_, nq_);
    for (int i = 0; i < nc_; ++i) {
      for (int k = 0; k < nphi_; ++k)
        Phi_phi(i, k) = ToFloat(df_[static_cast<size_t>(i)][static_cast<size_t>(nq_ + k)].subs(m));
      for (int j = 0; j < nq_; ++j) Phi_q(i, j) = -ToFloat(df_[static_cast<size_t>(i)][static_cast<size_t>(j)].subs(m));
    }
    return Solve(Phi_phi, Phi_q, K);
  }

  // Everything at a closed configuration.
  bool Coefficients(const Vector& q, const Vector& phi, Result* r) const {
    const GiNaC::exmap m = Point(q, phi);
    const int nx = nq_ + nphi_;
    const int nf = static_cast<int>(f_.size());
    Matrix J(nf, nx);  // df/dx
    for (int i = 0; i < nf; ++i)
      for (int a = 0; a < nx; ++a)
        J(i, a) = ToFloat(df_[static_cast<size_t>(i)][static_cast<size_t>(a)].subs(m));
    r->Phi_phi = Matrix(nc_, nphi_);
    Matrix Phi_q(nc_, nq_);
    for (int i = 0; i < nc_; ++i) {
      for (int k = 0; k < nphi_; ++k) r->Phi_phi(i, k) = J(i, nq_ + k);
      for (int j = 0; j < nq_; ++j) Phi_q(i, j) = -J(i, j);
    }
    if (!Solve(r->Phi_phi, Phi_q, &r->K)) return false;
    Matrix identity(nc_, nc_), inverse;
    for (int i = 0; i < nc_; ++i) identity(i, i) = 1;
    if (!Solve(r->Phi_phi, identity, &inverse)) return false;
    r->cond = Norm1(r->Phi_phi) * Norm1(inverse);
    r->det = Determinant(r->Phi_phi);
    // V = [I; K] (nx x nq).
    Matrix V(nx, nq_);
    for (int j = 0; j < nq_; ++j) {
      V(j, j) = 1;
      for (int i = 0; i < nphi_; ++i) V(nq_ + i, j) = r->K(i, j);
    }
    // gamma(f_i)(j, k) = sum_ab d2f_i/dx_a dx_b V_aj V_bk for every row of f.
    Matrix gamma(nf, nq_ * nq_);
    for (int i = 0; i < nf; ++i) {
      Matrix H(nx, nx);
      for (int a = 0; a < nx; ++a)
        for (int b = 0; b < nx; ++b)
          H(a, b) = ToFloat(d2f_[static_cast<size_t>(i)][static_cast<size_t>(a * nx + b)].subs(m));
      for (int j = 0; j < nq_; ++j)
        for (int k = 0; k < nq_; ++k) {
          numeric s(0);
          for (int a = 0; a < nx; ++a)
            for (int b = 0; b < nx; ++b) s = s + H(a, b) * V(a, j) * V(b, k);
          gamma(i, j + nq_ * k) = s;
        }
    }
    Matrix rhs(nc_, nq_ * nq_);
    for (int i = 0; i < nc_; ++i)
      for (int c = 0; c < nq_ * nq_; ++c) rhs(i, c) = -gamma(i, c);
    if (!Solve(r->Phi_phi, rhs, &r->L)) return false;
    r->r_P = Matrix(2 * np_, 1);
    r->K_P = Matrix(2 * np_, nq_);
    r->L_P = Matrix(2 * np_, nq_ * nq_);
    for (int row = 0; row < 2 * np_; ++row) {
      const int i = nc_ + row;
      r->r_P(row, 0) = ToFloat(f_[static_cast<size_t>(i)].subs(m));
      for (int j = 0; j < nq_; ++j) {
        numeric s(0);
        for (int a = 0; a < nx; ++a) s = s + J(i, a) * V(a, j);
        r->K_P(row, j) = s;
      }
      for (int c = 0; c < nq_ * nq_; ++c) {
        numeric s = gamma(i, c);
        for (int b = 0; b < nphi_; ++b) s = s + J(i, nq_ + b) * r->L(b, c);
        r->L_P(row, c) = s;
      }
    }
    return true;
  }

  // Continuation from (q0, *phi) to q1 on the branch `*branch`; adaptive sub-steps. With
  // `follow`, a sub-step whose converged point is on the predictor's tangent (Newton's
  // correction below a tenth of the step in q: O(h^2) on the same smooth curve, O(h) on the
  // other curve of a change point) may change the sign of det Phi_phi: the motion passes a
  // change point on its smooth branch, which becomes *branch; *crossings counts them.
  bool Continue(const Vector& q0, const Vector& q1, int* branch, Vector* phi, bool follow = false,
                int* crossings = nullptr) const {
    const numeric one(1);
    numeric t(0), h(1);
    // Sub-steps of at most 1 deg in an angle, and in a length (a slide) its arc at the
    // mechanism's size: 1 deg times the longest link.
    double max_dq = 0;
    for (int j = 0; j < nq_; ++j) {
      const double dq = std::fabs((q1[static_cast<size_t>(j)] - q0[static_cast<size_t>(j)]).to_double());
      max_dq = std::max(max_dq, kin_.q[static_cast<size_t>(j)].is_angle ? dq : dq / length_scale_);
    }
    const double max_step = M_PI / 180;  // 1 deg
    if (max_dq > max_step) h = numeric(1) / numeric(static_cast<long>(std::ceil(max_dq / max_step)));
    Vector q = q0;
    int failures = 0;
    while (t < one) {
      if (t + h > one) h = one - t;
      Vector qn(static_cast<size_t>(nq_));
      for (int j = 0; j < nq_; ++j) {
        const size_t s = static_cast<size_t>(j);
        qn[s] = q0[s] + (t + h) * (q1[s] - q0[s]);
        if (t + h == one) qn[s] = q1[s];
      }
      Matrix K;
      if (!Tangent(q, *phi, &K)) return false;
      Vector guess = *phi;
      for (int i = 0; i < nphi_; ++i)
        for (int j = 0; j < nq_; ++j)
          guess[static_cast<size_t>(i)] =
              guess[static_cast<size_t>(i)] + K(i, j) * (qn[static_cast<size_t>(j)] - q[static_cast<size_t>(j)]);
      const Vector predictor = guess;
      bool ok = Newton(qn, &guess, false);
      int sign = *branch;
      if (ok) {
        Vector Phi;
        Matrix A;
        EvalPhi(qn, guess, &Phi, &A);
        sign = Sign(Determinant(A));
        if (sign != *branch && follow) {
          numeric correction(0), dq(0);
          for (int i = 0; i < nphi_; ++i)
            correction = std::max(correction, Abs(guess[static_cast<size_t>(i)] - predictor[static_cast<size_t>(i)]));
          for (int j = 0; j < nq_; ++j)
            dq = std::max(dq, Abs(qn[static_cast<size_t>(j)] - q[static_cast<size_t>(j)]));
          ok = sign != 0 && correction < dq / 10;
        } else {
          ok = sign == *branch;
        }
      }
      if (!ok) {
        if (++failures > 40) return false;
        h = h / 2;
        continue;
      }
      if (sign != *branch && crossings != nullptr) ++*crossings;
      *branch = sign;
      *phi = guess;
      q = qn;
      t = t + h;
    }
    return true;
  }

 private:
  mechgen::Model model_;
  mechgen::Kinematics kin_;
  int nq_ = 0, nphi_ = 0, nc_ = 0, np_ = 0;
  double length_scale_ = 1;  // LengthScale(), once
  GiNaC::exmap params_;
  std::vector<ex> x_;                   // (q, phi) symbols
  std::vector<ex> f_;                   // Phi rows, then point coordinates
  std::vector<std::vector<ex>> df_;     // df_i/dx_a
  std::vector<std::vector<ex>> d2f_;    // d2f_i/dx_a dx_b (a * nx + b)
};

std::string Format(const numeric& x) {
  // CLN prints a long float with all its digits ("0.327...", "3.27...E-7"); strtod reads it.
  std::ostringstream os;
  os << ToFloat(x);
  return os.str();
}

std::string FormatDouble(double x) {
  char buf[64];
  std::snprintf(buf, sizeof(buf), "%.17g", x);
  return buf;
}

}  // namespace

int main(int argc, char** argv) {
  if (argc < 3) {
    std::cerr << "usage: make_reference MODEL.yaml OUT.csv [--steps N]\n";
    return 2;
  }
  const std::string model_path = argv[1], out_path = argv[2];
  int steps = -1;
  double cluster = std::nan("");
  bool follow = false;
  int crossings = 0;
  for (int i = 3; i + 1 < argc; i += 2) {
    if (std::string(argv[i]) == "--steps") steps = std::atoi(argv[i + 1]);
    if (std::string(argv[i]) == "--cluster") cluster = std::atof(argv[i + 1]) * M_PI / 180;
    if (std::string(argv[i]) == "--follow-change-points") follow = std::string(argv[i + 1]) == "yes";
  }
  GiNaC::Digits = 50;
  try {
    const Reference ref(model_path);
    const mechgen::Kinematics& kin = ref.kin();
    const int nq = ref.nq(), nphi = ref.nphi(), np = ref.np();
    if (nq > 2) throw std::runtime_error("make_reference: more than two inputs");
    if (steps < 0) steps = nq == 1 ? 720 : 8;

    // The requested inputs, as doubles (what the generated code will be given).
    std::vector<std::vector<double>> qs;
    if (nq == 1) {
      const double lo = kin.q_min[0], hi = kin.q_max[0];
      const bool full_turn = kin.q[0].is_angle && std::fabs(hi - lo - 2 * M_PI) < 1e-12;
      const int n = full_turn ? steps : steps + 1;
      std::vector<double> v;
      for (int k = 0; k < n; ++k) v.push_back(lo + (hi - lo) * k / steps);
      // --cluster X: also X -+ 10^(-k/4) rad, k = 8..40, to resolve a near-singular spot.
      if (std::isfinite(cluster)) {
        for (int k = 8; k <= 40; ++k) {
          v.push_back(cluster - std::pow(10.0, -k / 4.0));
          v.push_back(cluster + std::pow(10.0, -k / 4.0));
        }
        std::sort(v.begin(), v.end());
        v.erase(std::unique(v.begin(), v.end()), v.end());
      }
      for (double x : v) qs.push_back({x});
    } else {
      for (int a = 0; a <= steps; ++a)
        for (int bb = 0; bb <= steps; ++bb) {
          const int b = a % 2 == 0 ? bb : steps - bb;  // serpentine
          qs.push_back({kin.q_min[0] + (kin.q_max[0] - kin.q_min[0]) * a / steps,
                        kin.q_min[1] + (kin.q_max[1] - kin.q_min[1]) * b / steps});
        }
    }

    // Assembly: damped Newton from the model's guess, on the guess's branch.
    Vector q(static_cast<size_t>(nq)), phi(static_cast<size_t>(nphi));
    for (int j = 0; j < nq; ++j) q[static_cast<size_t>(j)] = ExactRational(kin.assembly_q[static_cast<size_t>(j)]);
    for (int i = 0; i < nphi; ++i) phi[static_cast<size_t>(i)] = ToFloat(ExactRational(kin.assembly_phi[static_cast<size_t>(i)]));
    Vector Phi;
    Matrix A;
    ref.EvalPhi(q, phi, &Phi, &A);
    int branch = Sign(Determinant(A));
    if (!ref.Newton(q, &phi, true)) throw std::runtime_error("make_reference: assembly failed");
    ref.EvalPhi(q, phi, &Phi, &A);
    if (Sign(Determinant(A)) != branch)
      throw std::runtime_error("make_reference: assembly landed on the other branch");

    std::ofstream out(out_path);
    if (!out) throw std::runtime_error("make_reference: cannot write " + out_path);
    const auto& m = ref.model();
    out << "# mechgen high-precision reference: tests/reference/make_reference.cc, GiNaC/CLN at "
        << GiNaC::Digits << " digits\n";
    out << "# model: " << m.name << "\n";
    out << "# regenerate: cmake --build <build> --target reference_data\n";
    out << "# nq=" << nq << " nphi=" << nphi << " npoints=" << np << "\n";
    out << "# length_scale=" << FormatDouble(ref.LengthScale())
        << " (largest distance between two points of one link)\n";
    out << "# q:";
    for (const auto& c : kin.q) out << ' ' << c.name << (c.is_angle ? "[angle]" : "[length]");
    out << "\n# phi:";
    for (const auto& c : kin.phi) out << ' ' << c.name << (c.is_angle ? "[angle]" : "[length]");
    out << "\n# points:";
    for (const auto& p : kin.point_names) out << ' ' << p;
    out << "\n# branch=" << branch << " (sign det Phi_phi)\n";
    out << "# columns: q_j (exact doubles, %.17g), phi_i, K_i_j, L_i_j_k = dK_ij/dq_k, "
           "rP_a_m (a: 0 x, 1 y), KP_r_j, LP_r_j_k (r = 2m + a), cond1 = |Phi_phi|_1 "
           "|Phi_phi^-1|_1\n";
    std::vector<std::string> cols;
    for (int j = 0; j < nq; ++j) cols.push_back("q_" + std::to_string(j));
    for (int i = 0; i < nphi; ++i) cols.push_back("phi_" + std::to_string(i));
    for (int i = 0; i < nphi; ++i)
      for (int j = 0; j < nq; ++j) cols.push_back("K_" + std::to_string(i) + "_" + std::to_string(j));
    // L(i, j + nq k): j runs fastest, as in the generated layout.
    for (int i = 0; i < nphi; ++i)
      for (int k = 0; k < nq; ++k)
        for (int j = 0; j < nq; ++j)
          cols.push_back("L_" + std::to_string(i) + "_" + std::to_string(j) + "_" + std::to_string(k));
    for (int pm = 0; pm < np; ++pm)
      for (int a = 0; a < 2; ++a) cols.push_back("rP_" + std::to_string(a) + "_" + std::to_string(pm));
    for (int r = 0; r < 2 * np; ++r)
      for (int j = 0; j < nq; ++j) cols.push_back("KP_" + std::to_string(r) + "_" + std::to_string(j));
    for (int r = 0; r < 2 * np; ++r)
      for (int k = 0; k < nq; ++k)
        for (int j = 0; j < nq; ++j)
          cols.push_back("LP_" + std::to_string(r) + "_" + std::to_string(j) + "_" + std::to_string(k));
    cols.push_back("cond1");
    for (size_t c = 0; c < cols.size(); ++c) out << (c ? "," : "") << cols[c];
    out << "\n";

    for (const std::vector<double>& qd : qs) {
      Vector q1(static_cast<size_t>(nq));
      for (int j = 0; j < nq; ++j) q1[static_cast<size_t>(j)] = ExactRational(qd[static_cast<size_t>(j)]);
      if (!ref.Continue(q, q1, &branch, &phi, follow, &crossings))
        throw std::runtime_error("make_reference: continuation failed at q = " + FormatDouble(qd[0]));
      q = q1;
      Reference::Result r;
      if (!ref.Coefficients(q, phi, &r)) throw std::runtime_error("make_reference: singular Phi_phi");
      std::vector<std::string> row;
      for (int j = 0; j < nq; ++j) row.push_back(FormatDouble(qd[static_cast<size_t>(j)]));
      for (int i = 0; i < nphi; ++i) row.push_back(Format(phi[static_cast<size_t>(i)]));
      for (int i = 0; i < nphi; ++i)
        for (int j = 0; j < nq; ++j) row.push_back(Format(r.K(i, j)));
      for (int i = 0; i < nphi; ++i)
        for (int c = 0; c < nq * nq; ++c) row.push_back(Format(r.L(i, c)));
      for (int pm = 0; pm < np; ++pm)
        for (int a = 0; a < 2; ++a) row.push_back(Format(r.r_P(2 * pm + a, 0)));
      for (int rr = 0; rr < 2 * np; ++rr)
        for (int j = 0; j < nq; ++j) row.push_back(Format(r.K_P(rr, j)));
      for (int rr = 0; rr < 2 * np; ++rr)
        for (int c = 0; c < nq * nq; ++c) row.push_back(Format(r.L_P(rr, c)));
      row.push_back(FormatDouble(r.cond.to_double()));
      for (size_t c = 0; c < row.size(); ++c) out << (c ? "," : "") << row[c];
      out << "\n";
    }
    std::cerr << "make_reference: " << m.name << ": " << qs.size() << " configurations -> "
              << out_path;
    if (follow) std::cerr << " (" << crossings << " change point(s) passed)";
    std::cerr << "\n";
  } catch (const mechgen::ModelError& e) {
    std::cerr << e.file() << ":" << e.mark().line << ":" << e.mark().column
              << ": error: " << e.message() << "\n";
    return 1;
  } catch (const std::exception& e) {
    std::cerr << e.what() << "\n";
    return 1;
  }
  return 0;
}
