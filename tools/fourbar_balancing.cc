// fourbar_balancing: the shaking force and moment, the driving torque and the bearing loads of
// models/fourbar_balanced.yaml over one crank revolution at constant speed, with the
// counterweights (balance = 1) and without them (balance = 0), as two CSV files and a summary
// of the peaks (Paul 7.3: balancing trades shaking force against driving torque and reactions).
//
//   fourbar_balancing [--omega W] [--steps N] OUT_DIR
//
// writes OUT_DIR/fourbar_balancing_balanced.csv and OUT_DIR/fourbar_balancing_unbalanced.csv
// (both or neither: each is written to a temporary file first; io/csv.h: numbers that round-trip,
// after '#' lines that name the tool, the model, the signs and each column's unit), columns:
//   theta_deg            crank angle (deg)
//   F_x, F_y, F_mag      shaking force, what the moving links exert on the frame (N): -sum m a_G
//   M                    shaking moment about the crank pivot O2 (N m, CCW +); it includes the
//                        reaction of the driving torque on the frame
//   drive                driving torque on the crank (N m, CCW +; kinetostatics, no load)
//   O2_x, O2_y, O2_mag   bearing load of the crank on the frame at O2 (N)
//   O4_x, O4_y, O4_mag   bearing load of the rocker on the frame at O4 (N)
//   A_mag, B_mag         pin forces at the crank pin A and the coupler-rocker pin B (N)
//   r_C_x, r_C_y         the moving links' centre of mass (m)
// and prints, per case, the peaks of |F|, |M|, |drive| and the bearing loads, and the
// counterweights (mass, radius, mass x radius, angle from the link's axis) read from the
// scene's CW2 and CW4 points. Exit status 0, or 2 with a message on a bad argument, 1 if a
// position does not solve or a file cannot be written.
#include <Eigen/Core>
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <sstream>
#include <string>
#include <vector>

#include "fourbar_balanced.h"
#include "mechgen/io/csv.h"
#include "mechgen/table/columns.h"

namespace {

using M = mech::fourbar_balanced::Model;
using Params = M::ParamsT<double>;

int Index(const char* const* names, int n, const char* name) {
  for (int i = 0; i < n; ++i)
    if (std::strcmp(names[i], name) == 0) return i;
  std::fprintf(stderr, "fourbar_balancing: the model has no '%s'\n", name);
  std::exit(1);
}

// One row of a CSV: the values at one crank angle.
struct Row {
  double theta_deg, F_x, F_y, F_mag, M, drive, O2_x, O2_y, O2_mag, O4_x, O4_y, O4_mag, A_mag, B_mag, r_C_x, r_C_y;
};

// The columns of both CSVs (table/columns.h; the file comment lists them).
mechgen::table::Columns<Row> Columns() {
  mechgen::table::Columns<Row> columns;
  mechgen::table::Builder<Row> add(&columns);
  add.Number("theta_deg", "deg", "crank angle", [](const Row& r) { return r.theta_deg; });
  add.Number("F_x", "N", "shaking force on the frame, -sum m a_G, x", [](const Row& r) { return r.F_x; });
  add.Number("F_y", "N", "shaking force on the frame, -sum m a_G, y", [](const Row& r) { return r.F_y; });
  add.Number("F_mag", "N", "|shaking force|", [](const Row& r) { return r.F_mag; });
  add.Number("M", "N m", "shaking moment on the frame about O2, CCW + (with the driving torque's reaction)",
             [](const Row& r) { return r.M; });
  add.Number("drive", "N m", "driving torque on the crank, CCW + (kinetostatics, no load)",
             [](const Row& r) { return r.drive; });
  add.Number("O2_x", "N", "bearing load of the crank on the frame at O2, x", [](const Row& r) { return r.O2_x; });
  add.Number("O2_y", "N", "bearing load of the crank on the frame at O2, y", [](const Row& r) { return r.O2_y; });
  add.Number("O2_mag", "N", "|bearing load at O2|", [](const Row& r) { return r.O2_mag; });
  add.Number("O4_x", "N", "bearing load of the rocker on the frame at O4, x", [](const Row& r) { return r.O4_x; });
  add.Number("O4_y", "N", "bearing load of the rocker on the frame at O4, y", [](const Row& r) { return r.O4_y; });
  add.Number("O4_mag", "N", "|bearing load at O4|", [](const Row& r) { return r.O4_mag; });
  add.Number("A_mag", "N", "|pin force at the crank pin A|", [](const Row& r) { return r.A_mag; });
  add.Number("B_mag", "N", "|pin force at the coupler-rocker pin B|", [](const Row& r) { return r.B_mag; });
  add.Number("r_C_x", "m", "centre of mass of the moving links, x", [](const Row& r) { return r.r_C_x; });
  add.Number("r_C_y", "m", "centre of mass of the moving links, y", [](const Row& r) { return r.r_C_y; });
  return columns;
}

struct Peaks {
  double F = 0, M = 0, drive = 0, O2 = 0, O4 = 0, A = 0, B = 0;
};

// One revolution at omega of the case `name` into `path` (via path.tmp); false on a failure
// (message printed).
bool Revolution(const Params& p, const char* name, double omega, int steps, const std::string& path,
                Peaks* peaks) {
  const std::string tmp = path + ".tmp";
  std::FILE* f = std::fopen(tmp.c_str(), "w");
  if (f == nullptr) {
    std::fprintf(stderr, "fourbar_balancing: cannot write %s\n", tmp.c_str());
    return false;
  }
  std::vector<Row> rows;
  const int O2 = Index(M::kReactionNames.data(), M::kNumReactions, "F_O2_x");
  const int O4 = Index(M::kReactionNames.data(), M::kNumReactions, "F_O4_x");
  const int A = Index(M::kReactionNames.data(), M::kNumReactions, "F_A_x");
  const int B = Index(M::kReactionNames.data(), M::kNumReactions, "F_B_x");
  Eigen::Matrix<double, M::kNphi, 1> phi;
  for (int k = 0; k < M::kNphi; ++k) phi(k) = M::kAssemblyPhi[k];
  for (int i = 0; i <= steps; ++i) {
    Eigen::Matrix<double, 1, 1> q, qd, qdd;
    q(0) = 2 * M_PI * i / steps;
    qd(0) = omega;
    qdd(0) = 0;
    const auto report = M::Solve(p, q, &phi);
    if (report.status != mech::fourbar_balanced::SolveStatus::kConverged) {
      std::fprintf(stderr, "fourbar_balancing: no position at theta_crank = %g deg\n", q(0) * 180 / M_PI);
      std::fclose(f);
      std::remove(tmp.c_str());
      return false;
    }
    M::CoefficientsT<double> c;
    M::Coeffs(p, q, phi, &c);
    M::ShakingT<double> s;
    M::Shaking(p, q, phi, qd, qdd, c, &s);
    M::StaticsT<double> st;
    M::Kinetostatics(p, q, phi, qd, qdd, 0.0, c, &st);
    // R is the force of the joint's first link on its second: at O2 and O4 the ground's on the
    // crank and the rocker, so the frame carries -R there.
    const Eigen::Vector2d o2(-st.R(O2), -st.R(O2 + 1)), o4(-st.R(O4), -st.R(O4 + 1));
    const double a = std::hypot(st.R(A), st.R(A + 1)), b = std::hypot(st.R(B), st.R(B + 1));
    rows.push_back({q(0) * 180 / M_PI, s.F(0), s.F(1), s.F.norm(), s.M, st.drive(0), o2.x(), o2.y(), o2.norm(),
                    o4.x(), o4.y(), o4.norm(), a, b, s.r_C(0), s.r_C(1)});
    peaks->F = std::max(peaks->F, s.F.norm());
    peaks->M = std::max(peaks->M, std::abs(s.M));
    peaks->drive = std::max(peaks->drive, std::abs(st.drive(0)));
    peaks->O2 = std::max(peaks->O2, o2.norm());
    peaks->O4 = std::max(peaks->O4, o4.norm());
    peaks->A = std::max(peaks->A, a);
    peaks->B = std::max(peaks->B, b);
  }
  std::ostringstream csv;
  mechgen::WriteCsv(Columns(), rows, csv,
                    mechgen::Described(mechgen::CsvAbout(
                        "fourbar_balancing", M::kName,
                        std::string(name) + " (balance = " + (std::strcmp(name, "balanced") == 0 ? "1" : "0") +
                            "), one crank revolution at constant speed",
                        "F and M: what the moving links exert on the frame; drive: the torque on the crank, CCW +; "
                        "O2, O4: the load of the crank and the rocker on the frame; fixed frame x, y")));
  const std::string text = csv.str();
  if (std::fputs(text.c_str(), f) < 0 || std::fclose(f) != 0) {
    std::fprintf(stderr, "fourbar_balancing: cannot write %s\n", tmp.c_str());
    std::remove(tmp.c_str());
    return false;
  }
  return true;
}

// A counterweight point's radius and angle from its link's axis, from the scene at q = 0.
void Counterweight(const Params& p, const char* point, const char* pivot, const char* tip, double mass) {
  Eigen::Matrix<double, 1, 1> q(0.0);
  Eigen::Matrix<double, M::kNphi, 1> phi;
  for (int k = 0; k < M::kNphi; ++k) phi(k) = M::kAssemblyPhi[k];
  M::Solve(p, q, &phi);
  Eigen::Matrix<double, 2, M::kNumScenePoints> scene;
  M::Scene(p, q, phi, &scene);
  const Eigen::Vector2d o = scene.col(Index(M::kScenePointNames.data(), M::kNumScenePoints, pivot));
  const Eigen::Vector2d axis = scene.col(Index(M::kScenePointNames.data(), M::kNumScenePoints, tip)) - o;
  const Eigen::Vector2d r = scene.col(Index(M::kScenePointNames.data(), M::kNumScenePoints, point)) - o;
  const double angle = std::atan2(axis.x() * r.y() - axis.y() * r.x(), axis.dot(r));
  std::printf("  %s: mass %.4g kg at radius %.4g m (mass x radius %.4g kg m), %.2f deg from the link's axis\n",
              point, mass, r.norm(), mass * r.norm(), angle * 180 / M_PI);
}

}  // namespace

int main(int argc, char** argv) {
  double omega = 100;
  int steps = 360;
  std::string dir;
  for (int i = 1; i < argc; ++i) {
    const std::string arg = argv[i];
    char* end = nullptr;
    if ((arg == "--omega" || arg == "--steps") && i + 1 < argc) {
      const double v = std::strtod(argv[++i], &end);
      if (*end != '\0' || !std::isfinite(v) || v <= 0 || (arg == "--steps" && (v != std::floor(v) || v > 1e6))) {
        std::fprintf(stderr, "fourbar_balancing: %s takes a positive %s, not '%s'\n", arg.c_str(),
                     arg == "--steps" ? "whole number up to 1e6" : "number (rad/s)", argv[i]);
        return 2;
      }
      if (arg == "--omega")
        omega = v;
      else
        steps = static_cast<int>(v);
    } else if (arg.rfind("--", 0) == 0 || !dir.empty()) {
      std::fprintf(stderr, "usage: fourbar_balancing [--omega W (rad/s, default 100)] [--steps N (default 360)] OUT_DIR\n");
      return 2;
    } else {
      dir = arg;
    }
  }
  if (dir.empty()) {
    std::fprintf(stderr, "usage: fourbar_balancing [--omega W (rad/s, default 100)] [--steps N (default 360)] OUT_DIR\n");
    return 2;
  }
  Params balanced;
  Params unbalanced;
  *unbalanced.Find("balance") = 0;
  const char* names[2] = {"balanced", "unbalanced"};
  const Params* params[2] = {&balanced, &unbalanced};
  Peaks peaks[2];
  std::string paths[2];
  for (int k = 0; k < 2; ++k) {
    paths[k] = dir + "/fourbar_balancing_" + names[k] + ".csv";
    if (!Revolution(*params[k], names[k], omega, steps, paths[k], &peaks[k])) {
      if (k == 1) std::remove((paths[0] + ".tmp").c_str());
      return 1;
    }
  }
  for (int k = 0; k < 2; ++k)
    if (std::rename((paths[k] + ".tmp").c_str(), paths[k].c_str()) != 0) {
      std::fprintf(stderr, "fourbar_balancing: cannot write %s\n", paths[k].c_str());
      return 1;
    }
  std::printf("fourbar_balanced at %g rad/s (%g rpm), %d steps; counterweights (balance = 1):\n", omega,
              omega * 30 / M_PI, steps);
  Counterweight(balanced, "crank.CW2", "crank.O2", "crank.A", balanced.mc2);
  Counterweight(balanced, "rocker.CW4", "rocker.O4", "rocker.B", balanced.mc4);
  std::printf("%-11s %12s %12s %12s %12s %12s %12s %12s\n", "peak", "|F| N", "|M| N m", "|drive| N m", "O2 N",
              "O4 N", "A N", "B N");
  for (int k = 0; k < 2; ++k)
    std::printf("%-11s %12.4g %12.4g %12.4g %12.4g %12.4g %12.4g %12.4g\n", names[k], peaks[k].F, peaks[k].M,
                peaks[k].drive, peaks[k].O2, peaks[k].O4, peaks[k].A, peaks[k].B);
  std::printf("wrote %s and %s\n", paths[0].c_str(), paths[1].c_str());
  return 0;
}
