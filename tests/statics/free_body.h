// A numeric Newton–Euler free-body solver for a planar mechanism at one configuration:
// the independent oracle of the generated statics (issue 14) and the benchmark's
// baseline (4). It knows nothing of the generator: a mechanism is links, points with world
// positions, joints and loads; each moving link gives three equations (sum Fx, sum Fy, sum M
// about the world origin = 0), the unknowns are the joints' reaction components and the
// inputs' actuator, and one dense LU solves them.
//
// Conventions (those of the statics contract, written here once):
//   Revolute J [a, b] at point P:  unknowns F_J = (Fx, Fy), the force of link a on link b at
//     P, fixed frame; link a gets -F_J. A driven revolute adds the unknown tau_J, the torque of
//     a on b (CCW +); a gets -tau_J. A known friction torque f_J (of a on b) adds likewise.
//   Prismatic J (guide g, slider s) at the slider point P, line angle alpha (absolute):
//     u = (cos alpha, sin alpha), n = (-sin alpha, cos alpha). Unknowns N_J (along n) and M_J
//     (moment of g on s about P, CCW +); the force on s is N n + T u at P, g gets the opposite
//     (at P, -M). T = the actuator force (an unknown, if J is driven) + the known friction
//     force f_J along +u.
//   Loads: forces at points (fixed frame), torques on links, weights (m g at the centre of
//   mass), linear springs between two points: tension S = F0 + k (l - L0) pulls the points
//   together.
//   Friction (SolveWithFriction): f_J = -gain_J * normal_J * sign_J, with normal_J = |F_J|
//   (revolute; gain = mu r) or |N_J| (prismatic; gain = mu), sign_J the sign of the relative
//   motion (omega_b - omega_a, or ds/dt), iterated to a fixed point.
//
// Usage: build once (Add* return ids), then per configuration Set* the positions (and any
// load values) and Solve(); nothing reallocates after the first Solve() of a given size.
#pragma once

#include <cmath>
#include <string>
#include <vector>

#include <Eigen/Dense>

namespace mechtest::fb {

using Vec2 = Eigen::Vector2d;

inline double Cross(const Vec2& r, const Vec2& f) { return r.x() * f.y() - r.y() * f.x(); }

class FreeBodySystem {
 public:
  // ---- description -------------------------------------------------------------------
  /// A link; `ground` links give no equations. Returns its id.
  int AddLink(const std::string& name, bool ground = false) {
    links_.push_back({name, ground, -1});
    dirty_ = true;
    return static_cast<int>(links_.size()) - 1;
  }
  /// A point with its world position (a joint's location, a load's point, a centre of mass).
  int AddPoint(const Vec2& r = Vec2::Zero()) {
    points_.push_back(r);
    return static_cast<int>(points_.size()) - 1;
  }
  void SetPoint(int point, const Vec2& r) { points_[point] = r; }
  const Vec2& point(int id) const { return points_[point_index(id)]; }

  /// Revolute joint of links a and b at `point`; `driven`: an actuator torque (of a on b).
  int AddRevolute(const std::string& name, int link_a, int link_b, int point, bool driven = false) {
    Joint j;
    j.name = name;
    j.prismatic = false;
    j.a = link_a;
    j.b = link_b;
    j.point = point;
    j.driven = driven;
    joints_.push_back(j);
    dirty_ = true;
    return static_cast<int>(joints_.size()) - 1;
  }
  /// Prismatic joint: guide link, slider link, the slider point, the line's absolute angle.
  int AddPrismatic(const std::string& name, int guide, int slider, int point, double angle,
                   bool driven = false) {
    Joint j;
    j.name = name;
    j.prismatic = true;
    j.a = guide;
    j.b = slider;
    j.point = point;
    j.angle = angle;
    j.driven = driven;
    joints_.push_back(j);
    dirty_ = true;
    return static_cast<int>(joints_.size()) - 1;
  }
  void SetPrismaticAngle(int joint, double angle) { joints_[joint].angle = angle; }
  /// Known friction at a joint: torque of a on b (revolute) or force along +u on the slider.
  void SetFriction(int joint, double f) { joints_[joint].friction = f; }
  double friction(int joint) const { return joints_[joint].friction; }

  /// A force with fixed-frame components at a point of a link.
  int AddForce(int link, int point, const Vec2& force = Vec2::Zero()) {
    forces_.push_back({link, point, force});
    return static_cast<int>(forces_.size()) - 1;
  }
  void SetForce(int id, const Vec2& force) { forces_[id].force = force; }
  /// A torque on a link (CCW +).
  int AddTorque(int link, double torque = 0) {
    torques_.push_back({link, torque});
    return static_cast<int>(torques_.size()) - 1;
  }
  void SetTorque(int id, double torque) { torques_[id].torque = torque; }
  /// The weight m * gravity at the centre of mass `point` of `link`.
  int AddWeight(int link, int point, double mass, const Vec2& gravity) {
    return AddForce(link, point, mass * gravity);
  }
  /// A linear spring between point i of link_i and point j of link_j.
  int AddSpring(int link_i, int point_i, int link_j, int point_j, double stiffness,
                double free_length, double preload = 0) {
    springs_.push_back({link_i, point_i, link_j, point_j, stiffness, free_length, preload});
    return static_cast<int>(springs_.size()) - 1;
  }
  /// Spring length and tension S = F0 + k (l - L0) at the current positions.
  double SpringLength(int id) const {
    const Spring& s = springs_[id];
    return (points_[s.point_j] - points_[s.point_i]).norm();
  }
  double SpringTension(int id) const {
    const Spring& s = springs_[id];
    return s.preload + s.stiffness * (SpringLength(id) - s.free_length);
  }
  /// Potential energy of the springs, F0 (l - L0) + k (l - L0)^2 / 2 each.
  double SpringEnergy() const {
    double v = 0;
    for (size_t i = 0; i < springs_.size(); ++i) {
      const double e = SpringLength(static_cast<int>(i)) - springs_[i].free_length;
      v += springs_[i].preload * e + 0.5 * springs_[i].stiffness * e * e;
    }
    return v;
  }

  // ---- sizes and unknowns ------------------------------------------------------------
  int num_equations() {
    Layout();
    return num_eq_;
  }
  int num_unknowns() {
    Layout();
    return num_unk_;
  }
  /// Index of the first unknown of a joint: revolute (Fx, Fy[, tau]), prismatic (N, M[, T_act]).
  int unknown_index(int joint) {
    Layout();
    return joints_[joint].first_unknown;
  }

  // ---- assembly ----------------------------------------------------------------------
  /// A x = rhs: rows 3 e + (0: Fx, 1: Fy, 2: M about the origin) of the e-th moving link;
  /// rhs = minus the known loads (forces, torques, weights, springs, friction).
  void Assemble(Eigen::MatrixXd* A, Eigen::VectorXd* rhs) {
    Layout();
    if (A->rows() != num_eq_ || A->cols() != num_unk_) A->resize(num_eq_, num_unk_);
    if (rhs->size() != num_eq_) rhs->resize(num_eq_);
    A->setZero();
    rhs->setZero();
    // A known force F at r on link l: rhs -= (Fx, Fy, r x F).
    auto known_force = [&](int link, const Vec2& r, const Vec2& f) {
      const int e = links_[link].equation;
      if (e < 0) return;
      (*rhs)(3 * e) -= f.x();
      (*rhs)(3 * e + 1) -= f.y();
      (*rhs)(3 * e + 2) -= Cross(r, f);
    };
    auto known_torque = [&](int link, double t) {
      const int e = links_[link].equation;
      if (e >= 0) (*rhs)(3 * e + 2) -= t;
    };
    // Unknown force column `col` (unit components d) at r, with sign on link l.
    auto unknown_force = [&](int link, int col, const Vec2& r, const Vec2& d, double sign) {
      const int e = links_[link].equation;
      if (e < 0) return;
      (*A)(3 * e, col) += sign * d.x();
      (*A)(3 * e + 1, col) += sign * d.y();
      (*A)(3 * e + 2, col) += sign * Cross(r, d);
    };
    auto unknown_torque = [&](int link, int col, double sign) {
      const int e = links_[link].equation;
      if (e >= 0) (*A)(3 * e + 2, col) += sign;
    };
    for (const Joint& j : joints_) {
      const Vec2& r = points_[j.point];
      const int c = j.first_unknown;
      if (!j.prismatic) {
        const Vec2 ex(1, 0), ey(0, 1);
        unknown_force(j.b, c, r, ex, +1);
        unknown_force(j.a, c, r, ex, -1);
        unknown_force(j.b, c + 1, r, ey, +1);
        unknown_force(j.a, c + 1, r, ey, -1);
        if (j.driven) {
          unknown_torque(j.b, c + 2, +1);
          unknown_torque(j.a, c + 2, -1);
        }
        known_torque(j.b, j.friction);
        known_torque(j.a, -j.friction);
      } else {
        const Vec2 u(std::cos(j.angle), std::sin(j.angle));
        const Vec2 n(-u.y(), u.x());
        unknown_force(j.b, c, r, n, +1);
        unknown_force(j.a, c, r, n, -1);
        unknown_torque(j.b, c + 1, +1);
        unknown_torque(j.a, c + 1, -1);
        if (j.driven) {
          unknown_force(j.b, c + 2, r, u, +1);
          unknown_force(j.a, c + 2, r, u, -1);
        }
        known_force(j.b, r, j.friction * u);
        known_force(j.a, r, -j.friction * u);
      }
    }
    for (const Force& f : forces_) known_force(f.link, points_[f.point], f.force);
    for (const Torque& t : torques_) known_torque(t.link, t.torque);
    for (const Spring& s : springs_) {
      const Vec2 d = points_[s.point_j] - points_[s.point_i];
      const double l = d.norm();
      const double tension = s.preload + s.stiffness * (l - s.free_length);
      const Vec2 on_i = tension * d / l;  // pulls i towards j
      known_force(s.link_i, points_[s.point_i], on_i);
      known_force(s.link_j, points_[s.point_j], -on_i);
    }
  }

  /// Solves the assembled system with a dense LU (square systems: partial pivoting; any
  /// other shape: full-pivoting LU, least squares sense). Returns false if the matrix is
  /// singular to working precision (a dead point: reactions unbounded) or not square.
  bool Solve(Eigen::VectorXd* x) {
    Assemble(&A_, &rhs_);
    if (num_eq_ != num_unk_) return false;
    lu_.compute(A_);
    *x = lu_.solve(rhs_);
    // Partial pivoting does not report singularity: check the pivots.
    const auto& lu = lu_.matrixLU();
    double max_pivot = 0, min_pivot = INFINITY;
    for (int i = 0; i < num_eq_; ++i) {
      max_pivot = std::max(max_pivot, std::abs(lu(i, i)));
      min_pivot = std::min(min_pivot, std::abs(lu(i, i)));
    }
    return min_pivot > 1e-12 * max_pivot && x->allFinite();
  }

  /// The residual A x - rhs of given unknowns (e.g. the generated reactions and drive): the
  /// sum of forces and moments on each moving link, 3 per link.
  Eigen::VectorXd Residual(const Eigen::VectorXd& x) {
    Assemble(&A_, &rhs_);
    return A_ * x - rhs_;
  }

  // ---- Coulomb friction --------------------------------------------------------------
  struct FrictionSpec {
    int joint;
    double gain;  ///< mu * pin radius (revolute) or mu (prismatic)
    double sign;  ///< sign of the relative motion: omega_b - omega_a, or ds/dt
  };
  /// Iterates f_J = -gain_J normal_J sign_J (normal from the previous solve, starting with
  /// no friction) until the friction loads change by less than `tol`. Returns false if a
  /// solve fails or the iteration does not settle in `max_iterations`.
  bool SolveWithFriction(const std::vector<FrictionSpec>& specs, Eigen::VectorXd* x,
                         int max_iterations = 200, double tol = 1e-13) {
    for (const auto& s : specs) SetFriction(s.joint, 0);
    for (int it = 0; it < max_iterations; ++it) {
      if (!Solve(x)) return false;
      double change = 0, scale = 1;
      for (const auto& s : specs) {
        const double f = -s.gain * Normal(s.joint, *x) * s.sign;
        change = std::max(change, std::abs(f - friction(s.joint)));
        scale = std::max(scale, std::abs(f));
        SetFriction(s.joint, f);
      }
      if (change <= tol * scale) return Solve(x);
    }
    return false;
  }
  /// |F_J| (revolute) or |N_J| (prismatic) in a solution.
  double Normal(int joint, const Eigen::VectorXd& x) {
    const int c = unknown_index(joint);
    if (joints_[joint].prismatic) return std::abs(x(c));
    return std::hypot(x(c), x(c + 1));
  }

  // ---- reading a solution ------------------------------------------------------------
  Vec2 RevoluteForce(int joint, const Eigen::VectorXd& x) {
    const int c = unknown_index(joint);
    return {x(c), x(c + 1)};
  }
  /// Actuator torque (revolute) or actuator force (prismatic) of a driven joint.
  double Drive(int joint, const Eigen::VectorXd& x) {
    const int c = unknown_index(joint);
    return x(c + 2);
  }
  double PrismaticN(int joint, const Eigen::VectorXd& x) { return x(unknown_index(joint)); }
  double PrismaticM(int joint, const Eigen::VectorXd& x) { return x(unknown_index(joint) + 1); }
  /// T_J = the actuator's force (if driven) + the known friction force.
  double PrismaticT(int joint, const Eigen::VectorXd& x) {
    const Joint& j = joints_[joint];
    return (j.driven ? x(unknown_index(joint) + 2) : 0.0) + j.friction;
  }

 private:
  struct Link {
    std::string name;
    bool ground;
    int equation;  // index among the moving links, -1 for ground
  };
  struct Joint {
    std::string name;
    bool prismatic = false;
    int a = -1, b = -1, point = -1;
    double angle = 0;
    bool driven = false;
    double friction = 0;
    int first_unknown = -1;
  };
  struct Force {
    int link, point;
    Vec2 force;
  };
  struct Torque {
    int link;
    double torque;
  };
  struct Spring {
    int link_i, point_i, link_j, point_j;
    double stiffness, free_length, preload;
  };

  int point_index(int id) const { return id; }
  void Layout() {
    if (!dirty_ && num_eq_ >= 0) return;
    int e = 0;
    for (Link& l : links_) l.equation = l.ground ? -1 : e++;
    num_eq_ = 3 * e;
    int c = 0;
    for (Joint& j : joints_) {
      j.first_unknown = c;
      c += 2 + (j.driven ? 1 : 0);
    }
    num_unk_ = c;
    dirty_ = false;
  }

  std::vector<Link> links_;
  std::vector<Vec2> points_;
  std::vector<Joint> joints_;
  std::vector<Force> forces_;
  std::vector<Torque> torques_;
  std::vector<Spring> springs_;
  bool dirty_ = true;
  int num_eq_ = -1, num_unk_ = -1;
  Eigen::MatrixXd A_;
  Eigen::VectorXd rhs_;
  Eigen::PartialPivLU<Eigen::MatrixXd> lu_;
};

}  // namespace mechtest::fb
