/**
 * \file machines/balancing/engine_balance.h
 * Primary and secondary shaking forces and moments of multi-cylinder reciprocating engines
 * (Paul ch. 7: shaking forces and moments of single- and multi-cylinder engines), analytic, by
 * the two-mass approximation; and the classical balance table.
 *
 * Frame. The crankshaft is the z axis and turns at constant ω through the crank angle θ,
 * counter-clockwise seen from +z. The x axis is the reference direction (for an in-line
 * engine, the cylinder axis, "up"); y is x turned by +90° about z. Cylinder j has
 *   α_j  the angle of its crank throw (crank pin) from x at θ = 0 (rad),
 *   β_j  the direction of its axis from x, from the crank towards the head (rad): 0 for every
 *        cylinder of an in-line engine, ±V/2 for the two banks of a V, ±90° for a boxer,
 *   z_j  its axial position (in units of a, e.g. the cylinder spacing).
 * Its crank angle from top dead centre is ψ_j = θ + α_j − β_j.
 *
 * Two-mass approximation. The reciprocating mass m (piston, wrist pin, the rod's share at the
 * small end), the same for every cylinder, has, with λ = r/l (crank radius over rod length)
 * and to first order in λ, the acceleration −r ω² (cos ψ + λ cos 2ψ) along the axis; the
 * force it exerts on the frame (the shaking force, −m a) is
 *     primary    m r ω² cos ψ_j u_j,        secondary  m r ω² λ cos 2ψ_j u_j,
 * with u_j = e^{iβ_j} the axis (complex numbers x + i y in the plane normal to the shaft).
 * A rotating mass m_rot per cylinder at the crank pin (the rod's big end and its share of the
 * pin, without counterweights) adds the centrifugal m_rot r ω² e^{i(θ + α_j)} to the primary.
 * With cos ψ = ½(e^{iψ} + e^{−iψ}) each order n is the sum of a forward and a backward
 * rotating vector,
 *     X_n(θ) = f_n e^{inθ} + b_n e^{−inθ},
 *     primary force:    f_1 = Σ_j (½ + ρ) e^{iα_j},   b_1 = ½ Σ_j e^{i(2β_j − α_j)}   (ρ = m_rot/m)
 *     secondary force:  f_2 = ½ Σ_j e^{i(2α_j − β_j)},  b_2 = ½ Σ_j e^{i(3β_j − 2α_j)}
 * in units of m r ω² (primary) and m r ω² λ (secondary). X_n traces an ellipse: |X| runs
 * between ||f| − |b|| and |f| + |b| over a turn; |b| = 0 is a vector of constant length turning
 * with the crank (balanced by a counterweight on the crank for n = 1), |f| = |b| a force on a
 * fixed line (an in-line engine's free forces). The shaking moment of order n about the point
 * z = 0 of the axis is Σ_j z_j ẑ × F_j, i.e. i Σ_j z_j F_j as a complex number (M_x + i M_y):
 * the same sums with e^{...} replaced by i z_j e^{...}, in units of m r ω² a and m r ω² λ a.
 * The moment of an order is a couple (the same about any point) when the force of that order
 * vanishes; the presets place z = 0 at the middle of the engine.
 *
 * The presets of EngineLayouts(): single, in-line twins (360° and 180° cranks), in-line
 * three, four (flat crank 0-180-180-0), five (firing order 1-2-4-5-3, four-stroke: a
 * cylinder's throw is minus half its firing angle, 0-216-144-72-288) and six, 60° V6 with a 120° crank and common crank
 * pins, 90° V8 with the cross-plane crank 0-90-270-180, flat-four boxer (opposed pistons on throws 180° apart) and the
 * 90° V-twin with a common crank pin. The two cylinders on one pin of a V are given the same z (the rod offset
 * neglected, as in the textbooks).
 *
 * Allocation-free except PrintBalanceTable(), BalanceRows() and BalanceColumns(); nothing throws.
 */
#pragma once

#include <array>
#include <cmath>
#include <complex>
#include <cstdio>
#include <initializer_list>
#include <ostream>
#include <string>
#include <vector>

#include "mechgen/core/constants.h"
#include "mechgen/io/csv.h"
#include "mechgen/table/columns.h"

namespace mechgen::balancing {

/// One cylinder: crank throw angle α, axis angle β (rad), axial position z (units of a).
struct Cylinder {
  double throw_angle = 0;
  double bank_angle = 0;
  double z = 0;
};

constexpr int kMaxCylinders = 16;

/// An engine's cylinders on one crankshaft (count <= kMaxCylinders).
struct EngineLayout {
  const char* name = "";
  const char* description = "";
  int count = 0;
  std::array<Cylinder, kMaxCylinders> cylinders{};
};

/// One order of a shaking force or moment: X(θ) = forward e^{inθ} + backward e^{−inθ}.
struct OrderVector {
  int n = 1;
  std::complex<double> forward, backward;
  /// X at crank angle θ (complex x + i y).
  std::complex<double> At(double theta) const {
    return forward * std::polar(1.0, n * theta) + backward * std::polar(1.0, -n * theta);
  }
  /// max |X| over a turn: the ellipse's semi-major axis.
  double Max() const { return std::abs(forward) + std::abs(backward); }
  /// min |X| over a turn: the semi-minor axis.
  double Min() const { return std::abs(std::abs(forward) - std::abs(backward)); }
  /// The cos nθ and sin nθ coefficients of its x and y components:
  /// x = ax cos nθ + bx sin nθ, y = ay cos nθ + by sin nθ.
  double ax() const { return forward.real() + backward.real(); }
  double bx() const { return -forward.imag() + backward.imag(); }
  double ay() const { return forward.imag() + backward.imag(); }
  double by() const { return forward.real() - backward.real(); }
};

/// The primary ([0], order 1) and secondary ([1], order 2) shaking force and moment.
struct EngineBalance {
  OrderVector force[2];   ///< units m r ω² (primary), m r ω² λ (secondary)
  OrderVector moment[2];  ///< units m r ω² a, m r ω² λ a
};

/// The analytic balance of a layout; rotating_ratio = m_rot/m (0: reciprocating masses only).
inline EngineBalance AnalyzeBalance(const EngineLayout& e, double rotating_ratio = 0) {
  using C = std::complex<double>;
  const C i(0, 1);
  EngineBalance b;
  b.force[0].n = b.moment[0].n = 1;
  b.force[1].n = b.moment[1].n = 2;
  for (int j = 0; j < e.count; ++j) {
    const double a = e.cylinders[j].throw_angle, be = e.cylinders[j].bank_angle;
    const double z = e.cylinders[j].z;
    const C f1 = (0.5 + rotating_ratio) * std::polar(1.0, a);
    const C b1 = 0.5 * std::polar(1.0, 2 * be - a);
    const C f2 = 0.5 * std::polar(1.0, 2 * a - be);
    const C b2 = 0.5 * std::polar(1.0, 3 * be - 2 * a);
    b.force[0].forward += f1;
    b.force[0].backward += b1;
    b.force[1].forward += f2;
    b.force[1].backward += b2;
    b.moment[0].forward += i * z * f1;
    b.moment[0].backward += i * z * b1;
    b.moment[1].forward += i * z * f2;
    b.moment[1].backward += i * z * b2;
  }
  return b;
}

/// A mass on the crankshaft, turning with it: m_cw r_cw (in units of m r) at the angle `angle` from x at θ = 0
/// (so at θ + angle at crank angle θ), at the axial position z.
struct Counterweight {
  double mr = 0;
  double angle = 0;
  double z = 0;
};

/// The crank counterweights that cancel the forward (turning with the crank) parts of the primary force and moment.
struct PrimaryCounterweights {
  Counterweight force;      ///< at z = 0: its centrifugal force is −f_1 (and its moment about z = 0 is zero)
  Counterweight couple[2];  ///< equal and opposite at z = ±half_span: no force, moment −f of the primary moment
};

/**
 * \brief Counterweights for the primary's forward parts. A counterweight w e^{iφ} at z turning with the crank adds
 * w e^{iφ} to the forward primary force and i z w e^{iφ} to the forward primary moment (centrifugal force
 * m_cw r_cw ω² on the frame), so one at z = 0 with w e^{iφ} = −f_1 cancels the forward force, and a pair
 * ±w e^{iφ} at z = ±c with 2 i c w e^{iφ} = −f_M, i.e. w e^{iφ} = i f_M/(2c), cancels the forward moment. The
 * backward parts (the cos 2β_j − α_j terms) turn against the crank and stay: a counter-rotating balance shaft would
 * be needed. A V8 with the cross-plane crank and a 90° V-twin on one pin have no backward primary: their primary
 * couple and force are fully balanced this way; a single keeps ½ m r ω² turning backwards.
 * \param[in] b          the balance (AnalyzeBalance())
 * \param[in] half_span  c > 0: the couple's counterweights at z = ±c (units of a)
 */
inline PrimaryCounterweights BalancePrimaryForward(const EngineBalance& b, double half_span) {
  PrimaryCounterweights p;
  const std::complex<double> force = -b.force[0].forward;
  p.force = {std::abs(force), std::abs(force) > 0 ? std::arg(force) : 0.0, 0.0};
  const std::complex<double> w = std::complex<double>(0, 1) * b.moment[0].forward / (2 * half_span);
  const double angle = std::abs(w) > 0 ? std::arg(w) : 0.0;
  p.couple[0] = {std::abs(w), angle, half_span};
  p.couple[1] = {std::abs(w), std::abs(w) > 0 ? std::arg(-w) : 0.0, -half_span};
  return p;
}

/// How an order vector moves over a turn (for the table).
enum class OrderKind {
  kBalanced,  ///< max |X| <= tolerance
  kRotating,  ///< |b| <= tolerance: constant length, turning with the crank (n = 1: a
              ///< counterweight balances it) — or against it for |f| <= tolerance
  kLine,      ///< ||f| − |b|| <= tolerance: on a fixed line (a free force or couple)
  kEllipse,   ///< otherwise
};

inline OrderKind Classify(const OrderVector& v, double tolerance = 1e-9) {
  if (v.Max() <= tolerance) return OrderKind::kBalanced;
  if (std::abs(v.backward) <= tolerance || std::abs(v.forward) <= tolerance) return OrderKind::kRotating;
  if (v.Min() <= tolerance) return OrderKind::kLine;
  return OrderKind::kEllipse;
}

inline const char* ToString(OrderKind k) {
  switch (k) {
    case OrderKind::kBalanced:
      return "balanced";
    case OrderKind::kRotating:
      return "rotating";
    case OrderKind::kLine:
      return "line";
    case OrderKind::kEllipse:
      return "ellipse";
  }
  return "unknown";
}

namespace internal {
// The line without its trailing blanks (the last column is padded), newline kept.
inline std::string TrimRight(const char* line) {
  std::string s(line);
  const bool newline = !s.empty() && s.back() == '\n';
  s.erase(s.find_last_not_of(" \n") + 1);
  return newline ? s + '\n' : s;
}
inline EngineLayout Make(const char* name, const char* description, std::initializer_list<Cylinder> cylinders) {
  EngineLayout e;
  e.name = name;
  e.description = description;
  for (const Cylinder& c : cylinders) {
    Cylinder d = c;
    d.throw_angle = FromDegrees(d.throw_angle);
    d.bank_angle = FromDegrees(d.bank_angle);
    e.cylinders[e.count++] = d;
  }
  return e;
}
}  // namespace internal

constexpr int kNumLayouts = 13;

/// The preset layouts (angles given here in degrees, stored in rad; z in cylinder spacings,
/// centred on 0). The cylinders are numbered as in tools/make_engine.py, whose presets carry
/// the same names, throws and banks (tests/engine/layout_names_test.py); v6_60_common is
/// here only (a textbook case with uneven firing, not an engine the maker builds).
inline std::array<EngineLayout, kNumLayouts> EngineLayouts() {
  using internal::Make;
  return {
      Make("single", "single cylinder", {{0, 0, 0}}),
      Make("inline2_180", "in-line twin, 180 deg crank", {{0, 0, -0.5}, {180, 0, 0.5}}),
      Make("inline2_360", "in-line twin, 360 deg crank", {{0, 0, -0.5}, {0, 0, 0.5}}),
      Make("inline3", "in-line three, 0-120-240", {{0, 0, -1}, {120, 0, 0}, {240, 0, 1}}),
      Make("inline4", "in-line four, flat crank 0-180-180-0",
           {{0, 0, -1.5}, {180, 0, -0.5}, {180, 0, 0.5}, {0, 0, 1.5}}),
      Make("inline5", "in-line five, firing 1-2-4-5-3: throws 0-216-144-72-288",
           {{0, 0, -2}, {216, 0, -1}, {144, 0, 0}, {72, 0, 1}, {288, 0, 2}}),
      Make("inline6", "in-line six, 0-240-120-120-240-0, firing 1-5-3-6-2-4",
           {{0, 0, -2.5}, {240, 0, -1.5}, {120, 0, -0.5}, {120, 0, 0.5}, {240, 0, 1.5}, {0, 0, 2.5}}),
      // The six pins along the shaft in throw order 30-90-150-210-270-330, half a spacing apart.
      Make("v6_60", "60 deg V6, six split pins 60 deg apart (even firing); cylinders 1-3 on the +30 deg bank",
           {{30, 30, -1.25}, {150, 30, -0.25}, {270, 30, 0.75}, {210, -30, 0.25}, {330, -30, 1.25},
            {90, -30, -0.75}}),
      Make("v6_60_common", "60 deg V6, 120 deg crank, common pins",
           {{0, 30, -1}, {0, -30, -1}, {120, 30, 0}, {120, -30, 0}, {240, 30, 1}, {240, -30, 1}}),
      Make("v8_crossplane", "90 deg V8, cross-plane crank 0-90-270-180; cylinders i and i + 4 on pin i",
           {{0, 45, -1.5},
            {90, 45, -0.5},
            {270, 45, 0.5},
            {180, 45, 1.5},
            {0, -45, -1.5},
            {90, -45, -0.5},
            {270, -45, 0.5},
            {180, -45, 1.5}}),
      Make("vtwin90", "90 deg V-twin, common crank pin", {{0, 45, 0}, {0, -45, 0}}),
      Make("boxer4", "flat-four boxer, throws 0-180-180-0, opposed cylinders along the x axis",
           {{0, 0, -1.5}, {180, 180, -0.5}, {180, 0, 0.5}, {0, 180, 1.5}}),
      Make("radial5", "five-cylinder radial, one crank pin, banks 72 deg apart",
           {{0, 0, 0}, {0, 72, 0}, {0, 144, 0}, {0, 216, 0}, {0, 288, 0}}),
  };
}

/// The preset named `name`, or nullptr.
inline const EngineLayout* FindLayout(const std::array<EngineLayout, kNumLayouts>& all, const std::string& name) {
  for (const EngineLayout& e : all)
    if (name == e.name) return &e;
  return nullptr;
}

/// One row of the layout listing (`mechgen_balance layouts`): one cylinder of a layout.
struct LayoutCylinderRow {
  const EngineLayout* layout = nullptr;
  int cylinder = 0;  ///< 1-based, the numbering of tools/make_engine.py
};

/// The rows of the listing: every cylinder of every layout in `layouts`, in order.
template <class Range>
std::vector<LayoutCylinderRow> LayoutCylinderRows(const Range& layouts) {
  std::vector<LayoutCylinderRow> rows;
  for (const EngineLayout& e : layouts)
    for (int i = 0; i < e.count; ++i) rows.push_back({&e, i + 1});
  return rows;
}

/// The columns of the listing: the geometry of each cylinder, angles in degrees.
inline table::Columns<LayoutCylinderRow> LayoutCylinderColumns() {
  table::Columns<LayoutCylinderRow> columns;
  table::Builder<LayoutCylinderRow> add(&columns);
  auto cylinder = [](const LayoutCylinderRow& r) -> const Cylinder& { return r.layout->cylinders[r.cylinder - 1]; };
  add.Text("layout", "the layout's name (tools/make_engine.py --preset takes the same names)",
           [](const LayoutCylinderRow& r) { return std::string(r.layout->name); });
  add.Text("cylinder", "the cylinder's number, from 1",
           [](const LayoutCylinderRow& r) { return std::to_string(r.cylinder); });
  add.Number("throw_deg", "deg", "the crank pin's throw angle gamma from the crank's reference line, CCW +",
             [cylinder](const LayoutCylinderRow& r) { return ToDegrees(cylinder(r).throw_angle); });
  add.Number("bank_deg", "deg", "the cylinder axis's bank angle beta from the x axis, CCW +",
             [cylinder](const LayoutCylinderRow& r) { return ToDegrees(cylinder(r).bank_angle); });
  add.Number("z", "cylinder spacings", "the cylinder's axial position along the crankshaft, centred on 0",
             [cylinder](const LayoutCylinderRow& r) { return cylinder(r).z; });
  add.Text("description", "what the layout is", [](const LayoutCylinderRow& r) { return std::string(r.layout->description); });
  return columns;
}

/// One row of the balance table: a layout and its balance.
struct BalanceRow {
  const char* name = "";
  int count = 0;
  EngineBalance balance;
};

/// The balance table's rows for `layouts` (rotating_ratio as in AnalyzeBalance()).
template <class Range>
std::vector<BalanceRow> BalanceRows(const Range& layouts, double rotating_ratio = 0) {
  std::vector<BalanceRow> rows;
  for (const EngineLayout& e : layouts) rows.push_back({e.name, e.count, AnalyzeBalance(e, rotating_ratio)});
  return rows;
}

/// The sign convention of the balance table's CSV (its first comment line, io/csv.h).
inline constexpr const char* kBalanceSigns =
    "the shaking force and moment of the reciprocating (and rotating) masses on the frame, "
    "moments about the engine's middle; magnitudes, so no sign";

/**
 * \brief The balance table's CSV columns (table/columns.h): layout, cylinders, then per
 * quantity (primary and secondary force and moment) its largest and smallest magnitude over a
 * turn and how it moves (balanced, rotating, line, ellipse). Below the classification's
 * tolerance a figure is 0 (not 1e-16); a line's minimum is 0.
 */
inline table::Columns<BalanceRow> BalanceColumns() {
  table::Columns<BalanceRow> columns;
  table::Builder<BalanceRow> add(&columns);
  add.Text("layout", "the layout's name", [](const BalanceRow& r) { return std::string(r.name); });
  add.Text("cylinders", "its number of cylinders", [](const BalanceRow& r) { return std::to_string(r.count); });
  struct Quantity {
    const char* name;
    const char* unit;
    const char* what;
    bool moment;
    int order;
  };
  for (const Quantity& q : {Quantity{"primary_force", "m r w^2", "primary shaking force", false, 0},
                            Quantity{"secondary_force", "m r w^2 (r/l)", "secondary shaking force", false, 1},
                            Quantity{"primary_moment", "m r w^2 a", "primary shaking moment", true, 0},
                            Quantity{"secondary_moment", "m r w^2 (r/l) a", "secondary shaking moment", true, 1}}) {
    auto vector = [q](const BalanceRow& r) -> const OrderVector& {
      return q.moment ? r.balance.moment[q.order] : r.balance.force[q.order];
    };
    add.Number(std::string(q.name) + "_max", q.unit, std::string("largest |") + q.what + "| over a turn",
               [vector](const BalanceRow& r) {
                 const OrderVector& v = vector(r);
                 return Classify(v) == OrderKind::kBalanced ? 0.0 : v.Max();
               });
    add.Number(std::string(q.name) + "_min", q.unit, std::string("smallest |") + q.what + "| over a turn",
               [vector](const BalanceRow& r) {
                 const OrderVector& v = vector(r);
                 const OrderKind k = Classify(v);
                 return k == OrderKind::kBalanced || k == OrderKind::kLine ? 0.0 : v.Min();
               });
    add.Text(std::string(q.name) + "_kind", "how it moves: balanced, rotating, line or ellipse",
             [vector](const BalanceRow& r) { return std::string(ToString(Classify(vector(r)))); });
  }
  return columns;
}

/**
 * \brief Prints the balance table of the layouts: one row per layout; per order, the largest
 * magnitude over a turn of the force and of the moment about the engine's middle, "0" where
 * balanced, with how it moves (rotating / line / ellipse min). Forces in m r ω² (primary) and
 * m r ω² (r/l) (secondary), moments times a. csv: BalanceColumns() through the one CSV writer
 * (io/csv.h; `options` may describe the columns).
 */
template <class Range>
void PrintBalanceTable(const Range& layouts, std::ostream& out, bool csv = false, double rotating_ratio = 0,
                       const CsvOptions& options = CsvOptions()) {
  if (csv) {
    WriteCsv(BalanceColumns(), BalanceRows(layouts, rotating_ratio), out, options);
    return;
  }
  auto cell = [](const OrderVector& v) -> std::string {
    const OrderKind k = Classify(v);
    char buffer[64];
    if (k == OrderKind::kBalanced) return "0";
    if (k == OrderKind::kEllipse)
      std::snprintf(buffer, sizeof(buffer), "%.3f ellipse(min %.3f)", v.Max(), v.Min());
    else
      std::snprintf(buffer, sizeof(buffer), "%.3f %s", v.Max(), ToString(k));
    return buffer;
  };
  out << "Shaking forces and moments, two-mass approximation (max over a turn; forces in m r w^2\n"
         "(primary) and m r w^2 (r/l) (secondary), moments about the engine's middle times the\n"
         "cylinder spacing a; reciprocating masses only"
      << (rotating_ratio != 0 ? ", plus rotating mass ratio " + std::to_string(rotating_ratio) : std::string())
      << ")\n";
  char line[256];
  std::snprintf(line, sizeof(line), "%-14s %3s  %-24s %-24s %-24s %-24s\n", "layout", "cyl", "primary force",
                "secondary force", "primary moment", "secondary moment");
  out << internal::TrimRight(line);
  for (const EngineLayout& e : layouts) {
    const EngineBalance b = AnalyzeBalance(e, rotating_ratio);
    const OrderVector* v[4] = {&b.force[0], &b.force[1], &b.moment[0], &b.moment[1]};
    std::snprintf(line, sizeof(line), "%-14s %3d  %-24s %-24s %-24s %-24s\n", e.name, e.count, cell(*v[0]).c_str(),
                  cell(*v[1]).c_str(), cell(*v[2]).c_str(), cell(*v[3]).c_str());
    out << internal::TrimRight(line);
  }
}

}  // namespace mechgen::balancing
