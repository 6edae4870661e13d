// The statics sweep (statics/sweep.h) and its output (statics/columns.h: CSV and table;
// statics/svg.h) on the hand-written statics models, against closed forms written here:
// the slider-crank's crank torque by virtual work T0 = F ds/dq, the rod force |P| =
// F / cos(beta) at every pin, the friction circle T = T0 +- mu r |P|, self-locking where
// a |sin(q - beta)| <= mu r, and the mechanical advantage of the slider by virtual work
// (|T0| MA = F); at a dead point the rows say `singular` and print no force; the column
// names are unique.
#include <cmath>
#include <regex>
#include <set>
#include <sstream>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "handwritten_statics_pendulum.h"
#include "handwritten_statics_slider_crank.h"
#include "mechgen/position/solver.h"
#include "mechgen/statics/columns.h"
#include "mechgen/statics/svg.h"
#include "mechgen/statics/sweep.h"

namespace mechgen::statics {
namespace {

using M = mech::handwritten_statics_slider_crank::Model;
using Params = ModelTypes<M>::Params;
using VecQ = ModelTypes<M>::VecQ;

std::vector<std::string> Split(const std::string& line) {
  std::vector<std::string> cells;
  std::string cell;
  std::stringstream in(line);
  while (std::getline(in, cell, ',')) cells.push_back(cell);
  if (!line.empty() && line.back() == ',') cells.push_back("");
  return cells;
}

// The CSV as a header and rows of cells.
template <class Model>
std::vector<std::vector<std::string>> Csv(const std::vector<StaticsRecord<Model>>& records) {
  std::ostringstream out;
  WriteStaticsCsv(records, out);
  std::istringstream in(out.str());
  std::vector<std::vector<std::string>> table;
  std::string line;
  while (std::getline(in, line)) table.push_back(Split(line));
  return table;
}

int Column(const std::vector<std::string>& header, const std::string& name) {
  for (size_t i = 0; i < header.size(); ++i)
    if (header[i] == name) return static_cast<int>(i);
  ADD_FAILURE() << "no column " << name;
  return 0;
}

template <class Model>
void ExpectUniqueColumns() {
  const std::vector<std::string> names = StaticsCsvColumns<Model>();
  const std::set<std::string> unique(names.begin(), names.end());
  EXPECT_EQ(unique.size(), names.size());
  for (const std::string& name : names) {
    EXPECT_FALSE(name.empty());
    EXPECT_EQ(name.find(','), std::string::npos) << name;
  }
}

TEST(StaticsSweep, ColumnNamesAreUniqueAndNamedFromTheModel) {
  ExpectUniqueColumns<M>();
  ExpectUniqueColumns<mech::handwritten_statics_pendulum::Model>();
  const std::vector<std::string> expected = {
      "theta_crank", "theta_rod", "s_slide", "drive_theta_crank", "drive_theta_crank_plus",
      "drive_theta_crank_minus", "efficiency_theta_crank_fwd", "efficiency_theta_crank_back",
      "self_locking_theta_crank", "F_O_x", "F_O_y", "F_B_x", "F_B_y", "F_C_x", "F_C_y",
      "N_slide", "T_slide", "M_slide", "F_O_mag", "F_B_mag", "F_C_mag", "F_slide_mag",
      "F_O_mag_plus", "F_O_mag_minus", "F_B_mag_plus", "F_B_mag_minus", "F_C_mag_plus",
      "F_C_mag_minus", "F_slide_mag_plus", "F_slide_mag_minus", "stiffness",
      "mechanical_advantage", "status", "cond", "evaluations"};
  EXPECT_EQ(StaticsCsvColumns<M>(), expected);
  const std::vector<std::string> pendulum = {
      "theta_pendulum", "x_P", "y_P", "drive_theta_pendulum", "F_O_x", "F_O_y", "F_O_mag",
      "V", "stiffness", "status", "cond", "evaluations"};
  EXPECT_EQ(StaticsCsvColumns<mech::handwritten_statics_pendulum::Model>(), pendulum);
}

// The force diagram of the hand-written slider-crank's sweep (statics/svg.h): every arrow of
// the pins O and B is the rod force P = F b / sqrt(b^2 - a^2 sin^2 q) (the closed form, at
// the snapshot's q read from its group) long at the drawing's force scale, to within the
// 0.01 px rounding of its end points; the scale bar is its force at that scale; each
// snapshot is labelled with its input angle, each arrow with its magnitude.
void ExpectForceDiagram(const std::string& text, const Params& p) {
  const std::regex scale_re("<g id=\"reactions\" data-force-scale=\"([^\"]+)\">");
  std::smatch m;
  ASSERT_TRUE(std::regex_search(text, m, scale_re));
  const double pixels_per_newton = std::stod(m[1]);
  ASSERT_GT(pixels_per_newton, 0.0);
  // The bar: from x = 8 to 8 + force * scale.
  const std::regex bar_re(
      "<g id=\"force_scale\" data-force=\"([^\"]+)\"><line x1=\"8\" y1=\"54\" x2=\"([^\"]+)\"");
  ASSERT_TRUE(std::regex_search(text, m, bar_re));
  const double bar = std::stod(m[1]);
  EXPECT_NEAR(std::stod(m[2]) - 8, bar * pixels_per_newton, 0.006);
  EXPECT_NE(text.find(" N (force scale: "), std::string::npos);
  // Snapshots and their arrows.
  const std::regex group_re("<g class=\"snapshot\" data-q=\"([^\"]+)\">\n([\\s\\S]*?)</g>");
  const std::regex line_re(
      "<line x1=\"([^\"]+)\" y1=\"([^\"]+)\" x2=\"([^\"]+)\" y2=\"([^\"]+)\"[^>]*><title>F_([A-Z]+) = ");
  int groups = 0, checked = 0;
  for (auto g = std::sregex_iterator(text.begin(), text.end(), group_re);
       g != std::sregex_iterator(); ++g, ++groups) {
    const double q = std::stod((*g)[1]);
    const std::string body = (*g)[2];
    const double sq = p.a * std::sin(q);
    const double P = p.F * p.b / std::sqrt(p.b * p.b - sq * sq);
    char label[64];
    std::snprintf(label, sizeof(label), "theta_crank = %.4g deg", q * 180 / M_PI);
    EXPECT_NE(body.find(label), std::string::npos) << label;
    int magnitudes = 0;
    for (size_t at = body.find("class=\"magnitude\""); at != std::string::npos;
         at = body.find("class=\"magnitude\"", at + 1))
      ++magnitudes;
    EXPECT_EQ(magnitudes, 3) << body;  // O, B, C
    for (auto l = std::sregex_iterator(body.begin(), body.end(), line_re);
         l != std::sregex_iterator(); ++l) {
      const std::string joint = (*l)[5];
      if (joint != "O" && joint != "B") continue;
      const double length = std::hypot(std::stod((*l)[3]) - std::stod((*l)[1]),
                                        std::stod((*l)[4]) - std::stod((*l)[2]));
      EXPECT_NEAR(length, pixels_per_newton * P, 0.015) << "F_" << joint << " at q = " << q;
      char magnitude[64];
      std::snprintf(magnitude, sizeof(magnitude), "F_%s %.4g N", joint.c_str(), P);
      EXPECT_NE(body.find(magnitude), std::string::npos) << magnitude;
      ++checked;
    }
  }
  EXPECT_EQ(groups, 4);
  EXPECT_EQ(checked, 8);
}

TEST(StaticsSweep, SliderCrankFullTurnAgainstClosedForms) {
  const Params p;
  const double mu_r = p.mu_O * p.r_O;
  position::PositionSolver<M> solver(position::Options(), p);
  ASSERT_EQ(solver.AssembleDefault(nullptr), position::Status::kConverged);
  std::vector<StaticsRecord<M>> records;
  ASSERT_EQ(StaticsSweep(Options(), &solver, VecQ::Constant(0.0), VecQ::Constant(2 * M_PI), 360,
                         &records),
            0);
  const auto table = Csv(records);
  ASSERT_EQ(table.size(), records.size() + 1);
  const auto& header = table[0];
  const int drive = Column(header, "drive_theta_crank");
  const int plus = Column(header, "drive_theta_crank_plus");
  const int minus = Column(header, "drive_theta_crank_minus");
  const int eff_fwd = Column(header, "efficiency_theta_crank_fwd");
  const int locked = Column(header, "self_locking_theta_crank");
  const int F_O = Column(header, "F_O_mag"), F_B = Column(header, "F_B_mag");
  const int F_C_plus = Column(header, "F_C_mag_plus");
  const int ma = Column(header, "mechanical_advantage");
  const int status = Column(header, "status");
  int locked_rows = 0;
  for (size_t i = 0; i < records.size(); ++i) {
    const auto& row = table[i + 1];
    ASSERT_EQ(row.size(), header.size());
    const double q = records[i].kinematics.q(0);
    EXPECT_EQ(row[status], "converged");
    // Closed forms (zero offset): sin(beta) = -a sin q / b.
    const double sq = p.a * std::sin(q), root = std::sqrt(p.b * p.b - sq * sq);
    const double ds = -sq - sq * p.a * std::cos(q) / root;  // ds/dq
    const double T0 = p.F * ds;                             // virtual work
    const double P = p.F * p.b / root;                      // F / cos(beta)
    const double lever = sq * (root / p.b + p.a / p.b * std::cos(q));  // a sin(q - beta)
    const double sign = T0 < 0 ? -1 : 1;
    EXPECT_NEAR(std::stod(row[drive]), T0, 1e-8 * p.F);
    // stiffness = -dQ/dq = dT0/dq (Model::Stiffness, once per row): a central difference.
    const double h = 1e-5;
    auto T0_at = [&](double x) {
      const double sx = p.a * std::sin(x);
      return p.F * (-sx - sx * p.a * std::cos(x) / std::sqrt(p.b * p.b - sx * sx));
    };
    EXPECT_NEAR(std::stod(row[Column(header, "stiffness")]), (T0_at(q + h) - T0_at(q - h)) / (2 * h),
                1e-5 * p.F);
    // The input running in +q: the bearing's friction torque mu_r P opposes it, whatever the
    // sign of T0 (continuous through T0 = 0); in -q the same torque the other way.
    EXPECT_NEAR(std::stod(row[plus]), T0 + mu_r * P, 1e-8 * p.F);
    EXPECT_NEAR(std::stod(row[minus]), T0 - mu_r * P, 1e-8 * p.F);
    // Forward (the motion along sign T0, the actuator driving): T0 / (T0 + sign mu_r P).
    EXPECT_NEAR(std::stod(row[eff_fwd]), T0 / (T0 + sign * mu_r * P), 1e-9);
    EXPECT_NEAR(std::stod(row[F_O]), P, 1e-8 * p.F);
    EXPECT_NEAR(std::stod(row[F_B]), P, 1e-8 * p.F);
    EXPECT_NEAR(std::stod(row[F_C_plus]), P, 1e-8 * p.F);  // the rod force ignores O's friction
    if (std::abs(std::abs(lever) - mu_r) > 1e-9) {
      EXPECT_EQ(row[locked], std::abs(lever) <= mu_r ? "1" : "0") << "q = " << q;
    }
    locked_rows += row[locked] == "1";
    // Mechanical advantage of the slider: |T0| MA = F (virtual work, no friction); inf at
    // the dead centres (q = 0, pi, 2 pi: ds/dq = 0).
    if (std::abs(ds) > 1e-12) {
      EXPECT_NEAR(std::abs(T0) * std::stod(row[ma]), p.F, 1e-7 * p.F) << "q = " << q;
    }
  }
  EXPECT_GT(locked_rows, 10);

  std::ostringstream printed;
  PrintStaticsTable(records, 8, printed);
  EXPECT_NE(printed.str().find("drive_theta_crank_plus"), std::string::npos) << printed.str();
  EXPECT_NE(printed.str().find("converged"), std::string::npos);

  std::ostringstream svg;
  SvgOptions options;
  options.snapshots = 4;
  options.animate = false;
  WriteStaticsSvg(solver.params(), records, options, svg);
  const std::string text = svg.str();
  size_t arrows = 0;
  for (size_t at = text.find("marker-end=\"url(#reaction_head)\""); at != std::string::npos;
       at = text.find("marker-end=\"url(#reaction_head)\"", at + 1))
    ++arrows;
  EXPECT_EQ(arrows, 4u * 3u);  // joints O, B and C at each of 4 snapshots
  EXPECT_NE(text.find("<title>F_B = ("), std::string::npos);
  EXPECT_EQ(text.rfind("</svg>\n"), text.size() - 7);
  ExpectForceDiagram(text, p);
}

// a = b: the position sweep stops next to the dead point at q = 90 deg; that row says
// `singular` and no force cell holds a number.
TEST(StaticsSweep, DeadPointRowsAreSingularAndEmpty) {
  Params p;
  p.a = p.b = 0.2;
  position::PositionSolver<M> solver(position::Options(), p);
  const ModelTypes<M>::VecPhi guess(-1.0, 2 * p.a * std::cos(1.0));  // beta = -q at q = 1 rad
  ASSERT_EQ(solver.Assemble(VecQ::Constant(1.0), guess, 0, nullptr), position::Status::kConverged);
  std::vector<StaticsRecord<M>> records;
  const int failures = StaticsSweep(Options(), &solver, VecQ::Constant(1.0),
                                    VecQ::Constant(M_PI / 2 + 0.2), 40, &records);
  EXPECT_GT(failures, 0);
  const auto table = Csv(records);
  const auto& header = table[0];
  const int status = Column(header, "status");
  int singular = 0, not_run = 0;
  for (size_t i = 0; i < records.size(); ++i) {
    const auto& row = table[i + 1];
    ASSERT_EQ(row.size(), header.size()) << i;
    if (row[status] == "converged") {
      for (size_t c = 0; c < header.size(); ++c) EXPECT_FALSE(row[c].empty()) << header[c];
      // Nothing huge is printed: P = F / cos(beta) stays below F cond.
      EXPECT_LT(std::abs(std::stod(row[Column(header, "F_O_mag")])), 1e6 * p.F);
      continue;
    }
    singular += row[status] == "singular";
    not_run += row[status] == "not_run";
    for (const char* name : {"drive_theta_crank", "drive_theta_crank_plus", "F_O_x", "F_O_mag",
                             "F_C_mag_minus", "stiffness", "mechanical_advantage"})
      EXPECT_TRUE(row[Column(header, name)].empty()) << name << " = " << row[Column(header, name)];
  }
  EXPECT_EQ(singular, 1);
  EXPECT_GT(not_run, 0);
}

TEST(StaticsSweep, PendulumPotentialAndReactions) {
  using P = mech::handwritten_statics_pendulum::Model;
  const ModelTypes<P>::Params p;
  position::PositionSolver<P> solver(position::Options(), p);
  ASSERT_EQ(solver.AssembleDefault(nullptr), position::Status::kConverged);
  std::vector<StaticsRecord<P>> records;
  ASSERT_EQ(StaticsSweep(Options(), &solver, ModelTypes<P>::VecQ::Constant(-M_PI),
                         ModelTypes<P>::VecQ::Constant(M_PI), 72, &records),
            0);
  const auto table = Csv(records);
  const int V = Column(table[0], "V"), F = Column(table[0], "F_O_mag");
  for (size_t i = 0; i < records.size(); ++i) {
    const double q = records[i].kinematics.q(0);
    EXPECT_NEAR(std::stod(table[i + 1][V]),
                p.m * p.g * p.lc * std::sin(q) + 0.5 * p.k * q * q, 1e-9);
    EXPECT_NEAR(std::stod(table[i + 1][F]), p.m * p.g, 1e-9);
  }
}

}  // namespace
}  // namespace mechgen::statics
