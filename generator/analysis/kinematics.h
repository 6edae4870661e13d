// The symbolic kinematics of a model, in Paul's notation: the coordinates (inputs q and
// dependent variables phi), every link's frame through the spanning tree, the loop
// closure equations Phi(q, phi; p) = 0 with their Jacobians Phi_phi and Phi_q, and the
// positions of the requested points and of every link point (the scene).
#pragma once

#include <string>
#include <vector>

#include "cam.h"
#include "joints.h"
#include "model.h"
#include "topology.h"

namespace mechgen {

struct Coordinate {
  std::string name;  ///< theta_<link> for an angle, s_<joint> for a displacement
  std::string what;  ///< a sentence for the generated header
  bool is_angle = true;
  GiNaC::symbol symbol;
};

struct Kinematics {
  std::vector<Coordinate> q, phi;
  std::vector<Frame> frames;            ///< per link
  std::vector<GiNaC::ex> Phi;           ///< closure equations, 2 per loop
  std::vector<std::string> Phi_source;  ///< which joint and projection each row comes from
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

Kinematics DeriveKinematics(const Model& m, const Topology& t);

}  // namespace mechgen
