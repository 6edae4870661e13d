// The symbolic kinematics of a model, in Paul's notation: the coordinates (inputs q and
// dependent variables phi), every link's frame through the spanning tree, the loop
// closure equations Phi(q, phi; p) = 0 with their Jacobians Phi_phi and Phi_q, and the
// positions of the requested points and of every link point (the scene).
#pragma once

#include <string>
#include <vector>

#include "analysis/topology.h"
#include "joints/cam_profile.h"
#include "joints/joint_kind.h"
#include "model/model.h"

namespace mechgen {

struct Coordinate {
  std::string name;  ///< theta_<link> for an angle; s_<joint>, psi_<joint>, u_<joint> for a joint's own
  std::string what;  ///< a sentence for the generated header
  bool is_angle = true;
  GiNaC::symbol symbol;
};

/// Where a row of Phi comes from: its joint, the loop that joint closes (-1: a tree
/// joint's row, e.g. rolling's no slip) and which of the joint's equations it is.
struct RowSource {
  int joint = -1;  ///< -1 for a driving constraint (then `input` is set)
  int loop = -1;
  RowComponent component = RowComponent::kX;
  int input = -1;  ///< a driving constraint x_P(phi) - q = 0: its input (index into q)
  /// "loop 1, joint C, x" / "joint R, no slip" / "input x_dist1_C, drive of dist1.C, x":
  /// the text headers and the report print.
  std::string Text(const Model& m) const;
};

/// A tree joint's placement: joint `joint` places link `child` on link `parent` (the
/// reactions of tree joints will come from here, issue 14).
struct Placement {
  int joint = -1;
  int parent = -1;
  int child = -1;
};

/// A model's cams, derived and checked at the parameters' defaults (the validation stage
/// builds them once; DeriveKinematics takes them over).
struct CamAnalysis {
  std::vector<CamLaw> laws;              ///< per law cam joint, in file order
  std::vector<CamGeometry> geometry;     ///< per law cam joint
  std::vector<std::string> summary;      ///< pressure angle and curvature over a turn
  std::vector<CamContour> contours;      ///< per contour cam joint, in file order
};

/// The coordinates of a model in file order: one angle per rotation group but the
/// ground's, then the joints' own (s, psi, u); and which group or joint each belongs to.
struct CoordinateTable {
  std::vector<Coordinate> all;
  std::vector<int> of_group;  ///< per rotation group: index into all, -1 for the ground's
  std::vector<int> of_joint;  ///< per joint: index into all, -1 if it has none
};

/// The coordinate (index into table.all) that input `in` makes a generalized coordinate:
/// a ground pivot's or rolling link's group angle, a slide, a link's group angle; -1 for a
/// point's x or y, which is no coordinate of the linkage (DeriveKinematics adds it to q with
/// its driving constraint).
int InputCoordinate(const Model& m, const Topology& t, const CoordinateTable& table, const Input& in);

/// A point input's coordinate name: x_<link>_<point> or y_<link>_<point>.
std::string PointInputName(const Model& m, const Input& in);

/// Creates the coordinates' symbols. GiNaC orders terms by the symbols' serial numbers, so
/// the generated text depends on the order in which symbols are created: build this
/// table once per model, before the cams (as DeriveKinematics always did).
CoordinateTable BuildCoordinates(const Model& m, const Topology& t);

struct Kinematics {
  std::vector<Coordinate> q, phi;
  std::vector<Frame> frames;            ///< per link
  std::vector<Placement> placements;    ///< per tree joint, in the order the frames are built
  std::vector<GiNaC::ex> Phi;           ///< closure equations: the cut joints' rows, loop by loop, then rolling tree joints' no
                                        ///< slip, then the driving constraints x_P(phi) - q of point inputs
  std::vector<RowSource> Phi_rows;      ///< per row: where it comes from (structured)
  std::vector<std::string> Phi_source;  ///< per row: Phi_rows[i].Text(m) (kept for the emitters and the report)
  std::vector<int> Phi_group;           ///< rows with equal group: x and y of one vector closure
  GiNaC::matrix Phi_phi, Phi_q;         ///< dPhi/dphi (nc x nphi), dPhi/dq (nc x nq)
  std::vector<Vec2> points;             ///< requested points of interest
  std::vector<std::string> point_names;
  std::vector<Vec2> scene;              ///< every point of every link
  std::vector<std::string> scene_names;
  std::vector<int> scene_link;
  std::vector<double> assembly_q, assembly_phi;
  std::vector<double> q_min, q_max;
  std::vector<CamLaw> cam_laws;              ///< per cam joint, in file order
  std::vector<CamGeometry> cam_geometry;     ///< per cam joint
  std::vector<std::string> cam_summary;      ///< pressure angle and curvature over a turn
  std::vector<CamContour> cam_contours;      ///< per contour cam joint, in file order

  int nq() const { return static_cast<int>(q.size()); }
  int nphi() const { return static_cast<int>(phi.size()); }
  int nc() const { return static_cast<int>(Phi.size()); }
};

/// \param coordinates, cams  from the validation stage (Validate()); if null, they are
/// built (and the cams checked) here.
Kinematics DeriveKinematics(const Model& m, const Topology& t, const CoordinateTable* coordinates = nullptr,
                            const CamAnalysis* cams = nullptr);

}  // namespace mechgen
