// The validation stage. See validate.h.
#include "analysis/validate.h"

#include <algorithm>
#include <cmath>
#include <cstdio>

#include "joints/joint_kind.h"

namespace mechgen {
namespace {

double Num(const GiNaC::ex& e, const GiNaC::exmap& values) {
  const GiNaC::ex v = e.subs(values).evalf();
  if (!GiNaC::is_a<GiNaC::numeric>(v)) return std::nan("");
  return GiNaC::ex_to<GiNaC::numeric>(v).to_double();
}

std::string Deg(double rad) {
  char buf[32];
  std::snprintf(buf, sizeof buf, "%.1f deg", rad * 180 / M_PI);
  return buf;
}

std::string G(double v) {
  char buf[32];
  std::snprintf(buf, sizeof buf, "%.4g", v);
  return buf;
}

}  // namespace

void CheckZeroLengthLinks(const Model& m) {
  const GiNaC::exmap defaults = m.Defaults();
  // Links whose angle a higher pair uses (its two links, its carrier): not only their pins.
  std::vector<bool> other_use(m.links.size(), false);
  for (const Joint& j : m.joints) {
    if (j.IsLowerPair() && j.type() != JointType::kRoll) continue;
    other_use[j.link_a] = other_use[j.link_b] = true;
    if (j.type() == JointType::kGear && j.Data<GearData>().carrier >= 0) other_use[j.Data<GearData>().carrier] = true;
    if (j.type() == JointType::kRack && j.Data<RackData>().carrier >= 0) other_use[j.Data<RackData>().carrier] = true;
    if (j.type() == JointType::kCam && j.Data<CamData>().carrier >= 0) other_use[j.Data<CamData>().carrier] = true;
  }
  double scale = 1;
  for (const Link& l : m.links)
    for (const LinkPoint& p : l.points) scale = std::max({scale, std::abs(Num(p.x, defaults)), std::abs(Num(p.y, defaults))});
  for (size_t li = 0; li < m.links.size(); ++li) {
    if (static_cast<int>(li) == m.ground || other_use[li]) continue;
    std::vector<int> pins;
    bool only_revolute = true;
    for (size_t k = 0; k < m.joints.size(); ++k) {
      if (!m.joints[k].Joins(static_cast<int>(li))) continue;
      only_revolute &= m.joints[k].type() == JointType::kRevolute;
      pins.push_back(static_cast<int>(k));
    }
    if (!only_revolute || pins.size() < 2) continue;
    const Link& link = m.links[li];
    const LinkPoint& first = link.points[m.joints[pins[0]].End(static_cast<int>(li)).point];
    const double x0 = Num(first.x, defaults), y0 = Num(first.y, defaults);
    double spread = 0;
    for (int k : pins) {
      const LinkPoint& p = link.points[m.joints[k].End(static_cast<int>(li)).point];
      spread = std::max(spread, std::hypot(Num(p.x, defaults) - x0, Num(p.y, defaults) - y0));
    }
    if (!(spread <= 1e-12 * scale)) continue;  // (NaN cannot come here: expressions are checked finite)
    std::string names, driven;
    for (int k : pins) names += (names.empty() ? "" : ", ") + m.joints[k].name;
    for (const Input& in : m.inputs)
      for (int k : pins)
        if (in.joint == k) driven = m.joints[k].name;
    const LinkPoint& last = link.points[m.joints[pins.back()].End(static_cast<int>(li)).point];
    m.Fail(last.mark, "link '" + link.name + "' has zero length: its joints " + names + " are all at one point (" +
                          G(x0) + ", " + G(y0) + ") at the parameters' defaults, so " +
                          (driven.empty() ? "its angle is in no equation (Phi_phi is singular everywhere)"
                                          : "turning it by input '" + driven + "' moves nothing (K = 0)") +
                          "; give its joints distinct points");
  }
}

void CheckZeroRadii(const Model& m) {
  // Gears and rolling joints check their radii themselves (joints/<kind>.cc); a rack's
  // pinion with a zero pitch radius would not drive its rack.
  const GiNaC::exmap defaults = m.Defaults();
  for (const Joint& j : m.joints)
    if (j.type() == JointType::kRack && Num(j.Data<RackData>().radius, defaults) == 0)
      m.Fail(j.mark, "rack '" + j.name + "': the pinion's pitch radius is 0 at the parameters' defaults, so " +
                         "turning the pinion would not move the rack; give it a non-zero radius");
}

void CheckCamLaw(const Model& m, const Joint& j) {
  const CamData& cd = j.Data<CamData>();
  GiNaC::ex turn_ex = 0, rises = 0, returns = 0;
  for (const CamSegment& s : cd.law) {
    turn_ex += s.duration;
    if (s.kind == CamSegment::Kind::kRise) rises += s.lift;
    if (s.kind == CamSegment::Kind::kReturn) returns += s.lift;
  }
  const GiNaC::exmap defaults = m.Defaults();
  const double turn = Num(turn_ex, defaults);
  if (std::abs(turn - 2 * M_PI) > 1e-9)
    m.Fail(cd.law_mark, "the law of cam '" + j.name + "' spans " + Deg(turn) +
                            " of cam angle, not 360 deg; make the segments' angles add up to one turn");
  const double up = Num(rises, defaults), down = Num(returns, defaults);
  if (std::abs(up - down) > 1e-9 * std::max(1.0, std::abs(up)))
    m.Fail(cd.law_mark, "the law of cam '" + j.name + "' does not close the cycle: its rises add up to " + G(up) +
                            " and its returns to " + G(down) + "; the follower must return to its start");
}

CamAnalysis AnalyzeCams(const Model& m) {
  CamAnalysis c;
  for (const Joint& j : m.joints) {
    if (j.type() != JointType::kCam) continue;
    if (j.Data<CamData>().contour != CamData::Contour::kNone) {
      c.contours.push_back(BuildCamContour(m, j));
      continue;
    }
    CheckCamLaw(m, j);
    c.laws.push_back(BuildCamLaw(m, j));
    c.geometry.push_back(DeriveCamGeometry(m, j));
    c.summary.push_back(CheckCam(m, j, c.laws.back(), c.geometry.back()));
  }
  return c;
}

void CheckTopology(const Model& m, const Topology& t) {
  if (t.inconsistent_slider >= 0) {
    const Joint& j = m.joints[t.inconsistent_slider];
    m.Fail(j.mark, "prismatic joint '" + j.name + "' fixes the angle between '" + m.links[j.link_a].name + "' and '" +
                       m.links[j.link_b].name + "' differently from other sliders; check relative_angle");
  }
  for (int l : t.unconnected)
    m.Fail(m.links[l].mark, "link '" + m.links[l].name +
                                "' is not connected to the ground through revolute, prismatic or rolling " +
                                "joints (gears and cams cannot place a link); add a pivot or remove the link");
  const int declared = static_cast<int>(m.inputs.size());
  if (t.loop_mobility <= 0)
    m.Fail(m.inputs_mark, "the mechanism cannot move: mobility " + std::to_string(t.loop_mobility) +
                              " (Grübler–Kutzbach " + t.grubler_text + "); it is a structure" +
                              (t.loop_mobility < 0 ? " and over-constrained" : "") + ". Remove a joint or add a link");
  if (declared != t.loop_mobility) {
    std::string detail = "Grübler–Kutzbach " + t.grubler_text + ", loop criterion " + t.loop_text;
    m.Fail(m.inputs_mark, std::to_string(declared) + " input(s) declared but the mechanism has " +
                              std::to_string(t.loop_mobility) + " degree(s) of freedom (" + detail +
                              "); declare exactly " + std::to_string(t.loop_mobility) +
                              " input(s): driven joints, link angles (angle: <link>) or point coordinates (point: "
                              "<link.point>, coordinate: x|y)");
  }
  // Each input must drive its own variable.
  std::vector<int> driven_group(t.num_groups(), -1);  // index into m.inputs
  auto input_name = [&](int i) {
    const Input& in = m.inputs[i];
    return in.kind == Input::Kind::kAngle ? "angle " + m.links[in.link].name : m.joints[in.joint].name;
  };
  for (size_t i = 0; i < m.inputs.size(); ++i) {
    const Input& in = m.inputs[i];
    int moving;
    if (in.kind == Input::Kind::kAngle) {
      moving = in.link;
      if (t.group[moving] == t.ground_group)
        m.Fail(in.mark, "input angle of '" + m.links[moving].name + "' cannot change: the link slides on the ground "
                        "and keeps its angle; drive a slide or another link's angle");
    } else if (in.kind == Input::Kind::kJoint) {
      const Joint& j = m.joints[in.joint];
      if (j.type() != JointType::kRevolute && j.type() != JointType::kRoll) continue;
      moving = j.link_a == m.ground ? j.link_b : j.link_a;
      if (t.group[moving] == t.ground_group)
        m.Fail(in.mark, "input joint '" + j.name + "' cannot turn: link '" + m.links[moving].name +
                            "' also slides on the ground and keeps its angle");
    } else {
      continue;
    }
    const int g = t.group[moving];
    if (driven_group[g] >= 0)
      m.Fail(in.mark, "inputs '" + input_name(driven_group[g]) + "' and '" + input_name(static_cast<int>(i)) +
                          "' drive the same angle; drive independent coordinates");
    driven_group[g] = static_cast<int>(i);
  }
}

void CheckCsvColumnNames(const Model& m, const Topology& t, const CoordinateTable& table) {
  // The sweep's CSV (runtime/include/mechgen/sweep/columns.h) derives its column names from
  // the coordinates: q, phi, <c>_dot, <c>_ddot, singular_<phi>, K_<phi>_<q>,
  // L_<phi>_<q>_<q'> (q <= q' in input order); the rest (points "link.P.x", mu_<joint>,
  // status, cond, ...) cannot meet them (a dot, or no coordinate prefix). Two equal names
  // would make a CSV reader silently pick one.
  const size_t n = table.all.size();
  std::vector<bool> driven(n, false);
  std::vector<std::string> q;  // the inputs' names (a point's x or y is none of table.all)
  for (const Input& in : m.inputs) {
    const int c = InputCoordinate(m, t, table, in);
    if (c < 0) {
      q.push_back(PointInputName(m, in));
      continue;
    }
    if (driven[c]) continue;
    driven[c] = true;
    q.push_back(table.all[c].name);
  }
  // Where a coordinate comes from: the link its angle is named after, or its joint.
  auto owner = [&](size_t c, SourceMark* mark) {
    for (int g = 0; g < t.num_groups(); ++g)
      if (table.of_group[g] == static_cast<int>(c) && t.rep[g] >= 0) {
        *mark = m.links[t.rep[g]].mark;
        return "link '" + m.links[t.rep[g]].name + "'";
      }
    for (size_t j = 0; j < m.joints.size(); ++j)
      if (table.of_joint[j] == static_cast<int>(c)) {
        *mark = m.joints[j].mark;
        return "joint '" + m.joints[j].name + "'";
      }
    *mark = m.inputs_mark;
    return "coordinate '" + table.all[c].name + "'";
  };
  struct Column {
    std::string name, what;
    size_t coordinate;
  };
  std::vector<Column> columns;
  for (size_t c = 0; c < n; ++c) {
    const std::string& name = table.all[c].name;
    columns.push_back({name, "the coordinate " + name, c});
    columns.push_back({name + "_dot", "the velocity of " + name, c});
    columns.push_back({name + "_ddot", "the acceleration of " + name, c});
    if (driven[c]) continue;
    columns.push_back({"singular_" + name, "the singular direction's " + name, c});
    for (size_t a = 0; a < q.size(); ++a) {
      const std::string& qa = q[a];
      columns.push_back({"K_" + name + "_" + qa, "K of " + name + " by " + qa, c});
      for (size_t b = a; b < q.size(); ++b)
        columns.push_back({"L_" + name + "_" + qa + "_" + q[b], "L of " + name + " by " + qa + ", " + q[b], c});
    }
  }
  std::vector<size_t> order(columns.size());
  for (size_t i = 0; i < order.size(); ++i) order[i] = i;
  std::stable_sort(order.begin(), order.end(),
                   [&](size_t x, size_t y) { return columns[x].name < columns[y].name; });
  for (size_t i = 1; i < order.size(); ++i) {
    const Column& x = columns[order[i - 1]];
    const Column& y = columns[order[i]];
    if (x.name != y.name) continue;
    // Blame the coordinate with the longer name (the one that reads like a derived column,
    // e.g. the link 'rocker_dot' next to 'rocker').
    const size_t c = table.all[x.coordinate].name.size() >= table.all[y.coordinate].name.size() ? x.coordinate
                                                                                                 : y.coordinate;
    SourceMark mark;
    const std::string who = owner(c, &mark);
    m.Fail(mark, "the sweep's CSV would have two columns named '" + x.name + "' (" + x.what + " and " + y.what +
                     "); rename " + who + " so that its coordinate " + table.all[c].name +
                     " does not read like another coordinate's column");
  }
}

Analysis Validate(const Model& m) {
  Analysis a;
  for (const Joint& j : m.joints) KindOf(j).Check(m, j);
  a.topology = BuildTopology(m);
  CheckTopology(m, a.topology);
  CheckZeroLengthLinks(m);
  CheckZeroRadii(m);
  a.four_bars = ClassifyFourBars(m, a.topology);
  for (const FourBarLoop& f : a.four_bars) CheckFourBarRange(m, f);
  a.coordinates = BuildCoordinates(m, a.topology);
  a.cams = AnalyzeCams(m);
  auto check_guess = [&](const GuessValue& g, const std::string& where) {
    bool known = false;
    std::vector<std::string> names;
    for (const Coordinate& c : a.coordinates.all) names.push_back(c.name);
    for (const Input& in : m.inputs)
      if (in.IsPoint()) names.push_back(PointInputName(m, in));
    for (const std::string& name : names) known |= name == g.coordinate;
    if (!known) {
      std::string list;
      for (const std::string& name : names) list += (list.empty() ? "" : ", ") + name;
      m.Fail(g.mark, where + ": unknown coordinate '" + g.coordinate + "'; the coordinates are: " + list);
    }
  };
  for (const GuessValue& g : m.guess) check_guess(g, "assembly");
  for (const NamedMode& mode : m.assembly_modes)
    for (const GuessValue& g : mode.guess) check_guess(g, "assembly mode '" + mode.name + "'");
  CheckCsvColumnNames(m, a.topology, a.coordinates);
  return a;
}

}  // namespace mechgen
