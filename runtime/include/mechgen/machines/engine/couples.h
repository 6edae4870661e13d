/**
 * \file machines/engine/couples.h
 * The rocking couples of an engine model of tools/make_engine.py: the moments, about axes across
 * the crankshaft, of the shaking forces of cylinders at different axial positions (Paul ch. 7).
 *
 * The engine models are planar: the crank plane is x-y and the crankshaft is the z axis (x, y, z
 * right-handed). Every cylinder j is superposed in that plane, but on a real crankshaft it sits at
 * its axial position z_j (the model's parameter "z_j", m). The generated shaking force
 * (`shaking` quantity: Model::Shaking) has per-link columns F_link.col(l) = −m_l a_Gl, the force
 * link l exerts on the frame through its inertia; its sum F is the shaking force. Giving each link
 * an axial position z_l, the shaking forces acting at (x, y, z_l) have about the point
 * (0, 0, z_ref) of the crankshaft axis the moment
 *     M = Σ_l (z_l − z_ref) ẑ × F_l,   i.e.   M_x = −Σ_l (z_l − z_ref) F_y,l,   M_y = Σ_l (z_l − z_ref) F_x,l
 * (N m): the rocking couple the moving parts exert on the frame (same sign convention as F: what
 * the engine block feels, what its mounts must resist). The in-plane moment M_z is the generated
 * Shaking::M and is not repeated here. As a complex number M_x + i M_y = i Σ_l (z_l − z_ref) F_l
 * (F_l = F_x + i F_y): the convention of mechgen/machines/balancing/engine_balance.h's moments.
 *
 * Reference point. The couple depends on z_ref unless the total force F is zero:
 *     M(z_ref') = M(z_ref) + (z_ref − z_ref') ẑ × F,
 * i.e. M_x' = M_x − (z_ref − z_ref') F_y and M_y' = M_y + (z_ref − z_ref') F_x (ShiftReference()).
 * The default reference is the mean of the z_j (the middle of the cylinders).
 *
 * Axial positions of the links (LinkAxialPositions()): the links named rod_j and piston_j act at
 * z_j (the rod's big end and the wrist pin are taken in the cylinder's plane: no rod offset);
 * every other link (the ground, the crank) gets the crank's axial position, by default the mean
 * of the z_j. Assumption: in these models the crank's centre of mass is on the axis O, so its
 * F_link is zero and its z does not matter; a crank with an off-axis centre of mass (an
 * unbalanced crank) would need its own z, which the caller sets (crank_z). A model without the
 * z_j parameters is refused (AxialStatus::kNoAxialPositions), never silently put at z = 0.
 *
 * Header-only, C++17, Eigen fixed-size (bounded for a model view); no allocation, nothing throws.
 */
#pragma once

#include <Eigen/Core>
#include <cmath>
#include <cstddef>
#include <cstdio>
#include <cstring>
#include <type_traits>

#include "mechgen/core/model_calls.h"
#include "mechgen/core/model_view.h"

namespace mechgen::engine {

/// Why LinkAxialPositions() failed (kOk: it did not).
enum class AxialStatus {
  kOk = 0,
  kNoAxialPositions,  ///< the model has no parameter z_1: not a tools/make_engine.py engine
  kMissingCylinder,   ///< a link rod_j or piston_j has no parameter z_j
};

inline const char* ToString(AxialStatus s) {
  switch (s) {
    case AxialStatus::kOk:
      return "ok";
    case AxialStatus::kNoAxialPositions:
      return "the model has no axial positions z_1.. (not an engine model of tools/make_engine.py)";
    case AxialStatus::kMissingCylinder:
      return "a link rod_j or piston_j has no axial position z_j";
  }
  return "unknown";
}

/// The axial position of every link of a model (indexed like Model::kLinkNames); NumLinks
/// Eigen::Dynamic: the links of a model reached through its view (bounded by ModelView::kMaxLinks).
template <int NumLinks>
struct LinkAxial {
  static constexpr int kMaxLinks = NumLinks == Eigen::Dynamic ? ModelView::kMaxLinks : NumLinks;
  using VecZ = Eigen::Matrix<double, NumLinks, 1, 0, kMaxLinks, 1>;
  AxialStatus status = AxialStatus::kNoAxialPositions;
  int cylinders = 0;             ///< n: the parameters z_1..z_n found
  double z_mean = 0;             ///< mean of z_1..z_n (m): the default reference point
  double z_crank = 0;            ///< the axial position given to the links other than rod_j, piston_j (m)
  int bad_link = -1;             ///< kMissingCylinder: the link without a z_j
  VecZ z = VecZ::Zero(NumLinks == Eigen::Dynamic ? 0 : NumLinks);  ///< z_l (m)
  bool ok() const { return status == AxialStatus::kOk; }
};

namespace internal {
/// j if name is prefix followed by a positive decimal number j (no sign, no trailing text), else 0.
inline int CylinderOf(const char* name, const char* prefix) {
  const std::size_t n = std::strlen(prefix);
  if (std::strncmp(name, prefix, n) != 0) return 0;
  const char* s = name + n;
  if (*s < '1' || *s > '9') return 0;
  int j = 0;
  for (; *s; ++s) {
    if (*s < '0' || *s > '9' || j > 100000) return 0;
    j = 10 * j + (*s - '0');
  }
  return j;
}
/// The links of M: M::kNumLinks and M::kLinkNames where M declares them (a generated model, or
/// one in its shape), else the model's view through ModelCalls<M> (ViewModel: at run time).
template <class M, class = void>
struct LinksOf {
  static constexpr int kCount = Eigen::Dynamic;
  static int Count(const M& m) { return ModelCalls<M>::NumLinks(m); }
  static const char* Name(const M& m, int l) { return ModelCalls<M>::LinkName(m, l); }
  template <class P>
  static auto* Find(const M& m, P& p, const char* name) { return ModelCalls<M>::FindParameter(m, &p, name); }
};
template <class M>
struct LinksOf<M, std::void_t<decltype(M::kNumLinks), decltype(M::kLinkNames)>> {
  static constexpr int kCount = M::kNumLinks;
  static constexpr int Count(const M&) { return M::kNumLinks; }
  static const char* Name(const M&, int l) { return M::kLinkNames[static_cast<std::size_t>(l)]; }
  template <class P>
  static auto* Find(const M&, P& p, const char* name) { return p.Find(name); }
};
}  // namespace internal

/**
 * \brief The axial position of each link of an engine model (see the file comment).
 * \tparam M        the generated Model (kNumLinks, kLinkNames), or a ViewModel (its view's links)
 * \param[in] model the model (a generated Model's empty tag)
 * \param[in] p     the model's parameters (only read; non-const because Params::Find is)
 * \param[in] crank_z  the axial position of the links other than rod_j and piston_j (the crank,
 *                  the ground), m; nullptr: the mean of the z_j
 * \return status kOk with z filled, or the reason (z then all zero and not to be used)
 */
template <class M, class P>
LinkAxial<internal::LinksOf<M>::kCount> LinkAxialPositions(const M& model, P& p, const double* crank_z = nullptr) {
  using Links = internal::LinksOf<M>;
  LinkAxial<Links::kCount> out;
  const int num_links = Links::Count(model);
  out.z.setZero(num_links);
  char name[32];
  double sum = 0;
  for (int j = 1;; ++j) {
    std::snprintf(name, sizeof(name), "z_%d", j);
    const auto* z = Links::Find(model, p, name);
    if (z == nullptr) break;
    sum += static_cast<double>(*z);
    out.cylinders = j;
  }
  if (out.cylinders == 0) {
    out.status = AxialStatus::kNoAxialPositions;
    return out;
  }
  out.z_mean = sum / out.cylinders;
  out.z_crank = crank_z != nullptr ? *crank_z : out.z_mean;
  for (int l = 0; l < num_links; ++l) {
    const char* link = Links::Name(model, l);
    int j = internal::CylinderOf(link, "rod_");
    if (j == 0) j = internal::CylinderOf(link, "piston_");
    if (j == 0) {
      out.z(l) = out.z_crank;
      continue;
    }
    std::snprintf(name, sizeof(name), "z_%d", j);
    const auto* z = Links::Find(model, p, name);
    if (z == nullptr) {
      out.status = AxialStatus::kMissingCylinder;
      out.bad_link = l;
      out.z.setZero();
      return out;
    }
    out.z(l) = static_cast<double>(*z);
  }
  out.status = AxialStatus::kOk;
  return out;
}
/// The same for a generated Model M (an empty tag).
template <class M, class P>
LinkAxial<M::kNumLinks> LinkAxialPositions(P& p, const double* crank_z = nullptr) {
  return LinkAxialPositions<M, P>(M(), p, crank_z);
}

/**
 * \brief The rocking couple (M_x, M_y) of the per-link shaking forces about the point (0, 0, z_ref)
 * of the crankshaft axis: M_x = −Σ_l (z_l − z_ref) F_y,l, M_y = Σ_l (z_l − z_ref) F_x,l (N m), the
 * moment the moving parts exert on the frame (F_link.col(l) = −m_l a_Gl, Shaking::F_link).
 * \param[in] F_link  2 x L: the per-link shaking forces (N)
 * \param[in] z       L: the links' axial positions (m), e.g. LinkAxialPositions().z
 * \param[in] z_ref   the reference point on the axis (m)
 */
template <class DerivedF, class DerivedZ>
Eigen::Matrix<typename DerivedF::Scalar, 2, 1> RockingCouple(const Eigen::MatrixBase<DerivedF>& F_link,
                                                             const Eigen::MatrixBase<DerivedZ>& z, double z_ref) {
  using S = typename DerivedF::Scalar;
  Eigen::Matrix<S, 2, 1> m(S(0), S(0));
  for (Eigen::Index l = 0; l < F_link.cols(); ++l) {
    const S arm = S(z(l) - z_ref);
    m(0) -= arm * F_link(1, l);
    m(1) += arm * F_link(0, l);
  }
  return m;
}

/// The rocking couple of a generated Shaking result (sh.F_link) about the mean of the z_j.
template <class ShakingT, int NumLinks>
auto RockingCouple(const ShakingT& sh, const LinkAxial<NumLinks>& axial) {
  return RockingCouple(sh.F_link, axial.z, axial.z_mean);
}

/**
 * \brief The couple about z_ref_new from the couple M about z_ref and the total shaking force F
 * (2-vector, N): M' = M + (z_ref − z_ref_new) ẑ × F.
 */
template <class DerivedM, class DerivedF>
Eigen::Matrix<typename DerivedM::Scalar, 2, 1> ShiftReference(const Eigen::MatrixBase<DerivedM>& M,
                                                              const Eigen::MatrixBase<DerivedF>& F, double z_ref,
                                                              double z_ref_new) {
  using S = typename DerivedM::Scalar;
  const S d = S(z_ref - z_ref_new);
  return Eigen::Matrix<S, 2, 1>(M(0) - d * F(1), M(1) + d * F(0));
}

/**
 * \brief The largest magnitude over a turn of one order n of a couple vector, from the cosine and
 * sine coefficients of its components: M_x = ax cos nθ + bx sin nθ, M_y = ay cos nθ + by sin nθ
 * (e.g. the Harmonic a, b of mechgen/machines/engine/harmonics.h for M_x and M_y). As M_x + i M_y =
 * f e^{inθ} + b e^{−inθ} with f = ½(ax + by + i(ay − bx)), b = ½(ax − by + i(ay + bx)), the tip
 * traces an ellipse with semi-axes |f| + |b| (returned) and ||f| − |b||; |b| = 0: a couple of
 * constant size turning with the crank (mechgen/machines/balancing/engine_balance.h's OrderVector::Max()).
 */
inline double CoupleOrderAmplitude(double ax, double bx, double ay, double by) {
  return 0.5 * (std::hypot(ax + by, ay - bx) + std::hypot(ax - by, ay + bx));
}

}  // namespace mechgen::engine
