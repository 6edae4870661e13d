/**
 * \file statics/svg.h
 * An SVG force diagram of a statics sweep: the drawing of io/svg.h (the mechanism at a few
 * configurations, the point paths, the ground pivots) with, at those snapshot configurations
 * (SvgOptions::overlay), the reaction vectors at the pins (red) and the applied loads,
 * springs and link weights (blue).
 *
 * Each red arrow is the frictionless reaction F_J = (F_J_x, F_J_y) of a revolute joint J, the
 * force of the joint's first link on its second (the contract's convention), drawn from the
 * pin: at the scene point whose name is J (e.g. "crank.B" for joint B); joints without such
 * a point and the reactions of prismatic, gear and cam joints (whose direction the runtime
 * does not know) are not drawn. Each arrow has its magnitude written at its tip ("F_B 1000 N")
 * and says who acts on whom in its tooltip ("F_B = (..) N: force of crank on rod").
 *
 * A model generated with a scene, statics and loads, springs or weights has Model::AppliedLoads
 * (EvalAppliedLoads: each load's and spring's points and force or torque, Model::
 * kAppliedLoadNames, kAppliedLoadKind, kAppliedLoadUnits). Its loads are drawn in blue: a
 * force load as an arrow from its point of application (class "load"), at the same force
 * scale as the reactions; a torque load as a curved arrow round its link's pivot
 * (class "torque": counter-clockwise as drawn for a positive torque, its size not to scale); a
 * linear spring as a zig-zag between its ends (class "spring") labelled with its tension
 * (+ pulling the ends together); a torsional spring as a dashed curved arrow at its joint
 * (class "torsion", the torque on the joint's second link). Each has its name and magnitude
 * with its unit as a label and its values in its tooltip, and data-at (its point, model
 * units; a spring data-b its other end) and data-value (N or N m). Under gravity the weight
 * m g of each moving link with mass (its point masses included; kind 4, named "W_<link>") is
 * drawn as a force load is, from the link's centre of mass (class "weight", labelled
 * "W_crank 19.6 N"), at the same force scale.
 *
 * Each snapshot's arrows are one group <g class="snapshot" data-q="..."> (the inputs, model
 * units) with a label of its inputs ("theta_crank = 90 deg") at the last point of a moving
 * link; `--snapshots 1` draws one configuration per picture. Labels never overlap, within a
 * snapshot or across snapshots: each label is put at the first free place next to its
 * arrow (moved up or down, then to the left), and one that finds none is left out (its
 * tooltip keeps the value); the legend says so. One scale for all force arrows: the largest
 * drawn force (reaction or applied) is 10 % of the drawing's span (inside its 12 % margin); a
 * force scale bar (a round force, its length in the drawing's scale) and the group's
 * data-force-scale (pixels per force unit) give it. Rows that are not converged (e.g.
 * singular) draw no arrows. Allocates; runs after the sweep.
 */
#pragma once

#include <algorithm>
#include <cmath>
#include <cstring>
#include <functional>
#include <ostream>
#include <string>
#include <type_traits>
#include <utility>
#include <vector>

#include "mechgen/io/format.h"
#include "mechgen/io/svg.h"
#include "mechgen/statics/columns.h"

namespace mechgen::statics {

namespace internal {

/// Model::AppliedLoads<Scalar>(p, q, phi, out) with kNumAppliedLoads, kAppliedLoadNames,
/// kAppliedLoadKind and kAppliedLoadUnits (EvalAppliedLoads: generated for a model with a
/// scene, statics and loads or springs), as the model's flag kHasAppliedLoads says.
template <class M>
struct HasAppliedLoads : std::bool_constant<::mechgen::internal::ReadFlag_kHasAppliedLoads<M>()> {};

/// M::kNumAppliedLoads where M has them, else 0.
template <class M, bool = HasAppliedLoads<M>::value>
struct NumAppliedLoads : std::integral_constant<int, 0> {};
template <class M>
struct NumAppliedLoads<M, true> : std::integral_constant<int, M::kNumAppliedLoads> {};

/// Places text labels (pixels) so that no two overlap and none leaves the picture's width:
/// each at the first free place of a few next to its anchor, or nowhere. A label's box is
/// estimated from its length (0.62 em a character, sans-serif) and its font size.
class LabelPlacer {
 public:
  explicit LabelPlacer(double width) : width_(width) {}
  /// Keeps the box [x, x + w] x [y - h, y] free (the legend's lines).
  void Reserve(double x, double y, double w, double h) { boxes_.push_back({x, y - h, x + w, y}); }
  /// The place of a label of `text` at font size `size` whose preferred baseline start is
  /// (x, y): true with *px, *py set, or false if every candidate overlaps a placed label.
  bool Place(double x, double y, const std::string& text, double size, double* px, double* py) {
    const double w = 0.62 * size * static_cast<double>(text.size()), h = size;
    const double step = size + 2;
    for (int side = 0; side < 2; ++side)
      for (int k = 0; k < 11; ++k) {
        const double dy = (k % 2 == 1 ? -1 : 1) * step * ((k + 1) / 2);
        const double bx = side == 0 ? x : x - w - 12;
        const Box b{bx, y + dy - h, bx + w, y + dy + 0.25 * h};
        bool free = b.x0 >= 0 && b.x1 <= width_ && b.y0 >= 0;
        for (const Box& o : boxes_) free = free && (b.x1 <= o.x0 || o.x1 <= b.x0 || b.y1 <= o.y0 || o.y1 <= b.y0);
        if (!free) continue;
        boxes_.push_back(b);
        *px = bx;
        *py = y + dy;
        return true;
      }
    ++left_out_;
    return false;
  }
  int left_out() const { return left_out_; }

 private:
  struct Box {
    double x0, y0, x1, y1;
  };
  double width_;
  std::vector<Box> boxes_;
  int left_out_ = 0;
};

}  // namespace internal

/// The applied loads, springs and weights of a model as the force diagram reads them: their
/// number, names, kinds and units, and AppliedLoads at a configuration (7 x number: the point,
/// the other end, the force, the value), from a generated Model or from its view.
template <class M>
struct AppliedLoadsOf {
  using Types = ModelTypes<M>;
  int count = 0;
  std::vector<std::string> names, units;
  std::vector<int> kinds;
  std::function<void(const typename Types::VecQ&, const typename Types::VecPhi&, Eigen::Matrix<double, 7, Eigen::Dynamic>*)>
      evaluate;
};

template <class M>
AppliedLoadsOf<M> DescribeAppliedLoads(const M& model, const typename ModelTypes<M>::Params& params) {
  using Types = ModelTypes<M>;
  AppliedLoadsOf<M> a;
  if constexpr (ModelCalls<M>::kView) {
    const ModelView* v = model.view;
    if (!v->flags.kHasAppliedLoads || v->AppliedLoads == nullptr || v->num_applied_loads <= 0) return a;
    a.count = v->num_applied_loads;
    for (int l = 0; l < a.count; ++l) {
      a.names.emplace_back(v->applied_load_names[l]);
      a.units.emplace_back(v->applied_load_units[l]);
      a.kinds.push_back(v->applied_load_kind[l]);
    }
    a.evaluate = [v, params](const typename Types::VecQ& q, const typename Types::VecPhi& phi,
                             Eigen::Matrix<double, 7, Eigen::Dynamic>* out) {
      out->setZero(7, v->num_applied_loads);
      v->AppliedLoads(params.data(), q.data(), phi.data(), out->data());
    };
  } else if constexpr (internal::HasAppliedLoads<M>::value) {
    (void)model;
    a.count = M::kNumAppliedLoads;
    for (int l = 0; l < a.count; ++l) {
      a.names.emplace_back(M::kAppliedLoadNames[static_cast<size_t>(l)]);
      a.units.emplace_back(M::kAppliedLoadUnits[static_cast<size_t>(l)]);
      a.kinds.push_back(M::kAppliedLoadKind[static_cast<size_t>(l)]);
    }
    a.evaluate = [params](const typename Types::VecQ& q, const typename Types::VecPhi& phi,
                          Eigen::Matrix<double, 7, Eigen::Dynamic>* out) {
      Eigen::Matrix<double, 7, M::kNumAppliedLoads> applied;
      M::template AppliedLoads<double>(params, q, phi, &applied);
      *out = applied;
    };
  } else {
    (void)model, (void)params;
  }
  return a;
}

/**
 * \brief Writes the SVG of io/svg.h for the sweep's configurations with the reaction arrows
 *        and the applied loads, springs and weights of the snapshots (options.snapshots of them).
 * \param[in] model    The model (a generated Model, or a ViewModel).
 * \param[in] params   Parameters the sweep ran with.
 * \param[in] records  The statics sweep.
 */
template <class M>
void WriteStaticsSvg(const M& model, const typename ModelTypes<M>::Params& params,
                     const std::vector<StaticsRecord<M>>& records, SvgOptions options, std::ostream& out) {
  using C = ModelCalls<M>;
  std::vector<SweepRecord<M>> kinematics;
  kinematics.reserve(records.size());
  for (const StaticsRecord<M>& r : records) kinematics.push_back(r.kinematics);
  const ::mechgen::internal::SvgModel<M> d = ::mechgen::internal::DescribeForSvg(model, params);
  const AppliedLoadsOf<M> loads = DescribeAppliedLoads(model, params);
  // What the model has at compile time (a view: everything), then what this one has.
  constexpr bool kMayHaveReactions = StaticsFeatures<M>::kHasReactions && ModelFeatures<M>::kHasScene;
  const bool kReactions = kMayHaveReactions && C::HasReactions(model) && d.has_scene;
  const bool kApplied = loads.count > 0 && d.has_scene;
  const int kNumApplied = loads.count;
  using Applied = Eigen::Matrix<double, 7, Eigen::Dynamic>;
  // Revolute joints with a scene point of the same name: (x index, y index, scene point).
  struct Arrow {
    std::string joint;
    int x, y, point;
    std::string who;  ///< ": force of <link a> on <link b>" when the model names the links
  };
  std::vector<Arrow> arrows;
  if constexpr (kMayHaveReactions) {
    if (kReactions) {
      for (const ReactionJoint& j : ReactionJoints<M>(model)) {
        if (j.x < 0 || j.y < 0) continue;
        for (int s = 0; s < d.num_scene_points; ++s) {
          if (j.joint == ::mechgen::internal::ShortName(d.scene_point_names[s])) {
            std::string who;
            if (C::HasJointLinks(model)) {
              const int joint = C::ReactionJoint(model, j.x);
              who = std::string(": force of ") + C::LinkName(model, C::DrawJointLinkA(model, joint)) + " on " +
                    C::LinkName(model, C::DrawJointLinkB(model, joint));
            }
            arrows.push_back({j.joint, j.x, j.y, s, who});
            break;
          }
        }
      }
    }
  }
  options.overlay = [&](const SvgFrame& frame, std::ostream& svg) {
    (void)frame;
    (void)svg;
    if (kReactions || kApplied) {
      auto converged = [&](size_t index) {
        return records[index].frictionless.summary.status == Status::kConverged;
      };
      // The applied loads of each snapshot (none without them).
      std::vector<Applied> applied(frame.snapshots.size(), Applied::Zero(7, kNumApplied));
      if (kApplied) {
        for (size_t i = 0; i < frame.snapshots.size(); ++i)
          if (converged(frame.snapshots[i])) {
            const auto& state = records[frame.snapshots[i]].kinematics.state;
            loads.evaluate(state.q, state.phi, &applied[i]);
          }
      }
      double largest_reaction = 0, largest = 0;
      for (size_t i = 0; i < frame.snapshots.size(); ++i) {
        if (!converged(frame.snapshots[i])) continue;
        if constexpr (kMayHaveReactions) {
          const StaticsRecord<M>& r = records[frame.snapshots[i]];
          for (const Arrow& a : arrows)
            largest_reaction = std::max(largest_reaction, std::hypot(r.frictionless.statics.R(a.x),
                                                                     r.frictionless.statics.R(a.y)));
        }
        for (int l = 0; l < kNumApplied; ++l)
          if (loads.kinds[static_cast<size_t>(l)] == 0 || loads.kinds[static_cast<size_t>(l)] == 4)
            largest = std::max(largest, std::hypot(applied[i](4, l), applied[i](5, l)));
      }
      largest = std::max(largest, largest_reaction);
      const bool scaled = largest > 0 && std::isfinite(largest);
      if (!scaled && !kApplied) return;
      const double per_unit = scaled ? 0.1 * frame.span / largest : 0;  // model length per force unit
      const double pixels_per_force = per_unit * frame.scale;
      auto number = [](double x) { return ::mechgen::internal::FormatNumber(x, "%.4g"); };
      auto px = [](double v) { return ::mechgen::internal::FormatNumber(v, "%.2f"); };
      auto X = [&frame](double x) { return (x - frame.x_min) * frame.scale; };
      auto Y = [&frame](double y) { return (frame.y_max - y) * frame.scale + 30; };
      internal::LabelPlacer labels(options.width);
      labels.Reserve(0, 24, options.width, 24);  // the title
      if (d.has_points)  // io/svg.h's legend of the paths (top right)
        labels.Reserve(options.width - 198, 18.0 + 18 * d.num_points, 190, 10.0 + 18 * d.num_points);
      const bool several = frame.snapshots.size() > 1;
      // The legend's lines, from y = 40 down: the reactions, their scale, the applied loads,
      // the labels' note.
      double legend_y = 40;
      std::string legend;
      auto legend_line = [&](const std::string& color, const std::string& text) {
        legend += "<text x=\"8\" y=\"" + px(legend_y) + "\" font-family=\"sans-serif\" font-size=\"12\" fill=\"" +
                  color + "\">" + text + "</text>\n";
        labels.Reserve(8, legend_y + 2, 0.62 * 12 * static_cast<double>(text.size()), 14);
        legend_y += 14;
      };
      if (kReactions && largest_reaction > 0)
        legend_line("#c00", "reactions (force of a joint's first link on its second); longest " +
                                number(largest_reaction) + " N");
      // The force scale bar: the round force (1, 2 or 5 times a power of ten) at most the
      // largest force, drawn at the drawing's scale.
      double bar = 0, bar_y = 0;
      if (scaled) {
        const double decade = std::pow(10.0, std::floor(std::log10(largest)));
        const double mantissa = largest / decade;
        bar = (mantissa >= 5 ? 5 : mantissa >= 2 ? 2 : 1) * decade;
        bar_y = legend_y;
        const std::string text = number(bar) + " N (force scale: " + number(1 / per_unit) + " N per model length unit)";
        labels.Reserve(8, bar_y + 6, bar * pixels_per_force + 6 + 0.62 * 12 * static_cast<double>(text.size()), 16);
        legend_y += 18;
      }
      if (kApplied) {
        legend_line("#06c", "applied loads, springs and weights: forces as arrows at the force scale,");
        legend_line("#06c", "torques as curved arrows (counter-clockwise +, not to scale),");
        legend_line("#06c", "springs as zig-zags with their tension (+ pulling), torsional springs dashed;");
        legend_line("#06c", "weights (W_ and the link's name): m g as arrows from the centres of mass");
      }
      if (several) {
        legend_line("#333", "labels of all snapshots moved apart so that none overlap; one with no room");
        legend_line("#333", "is left out (its arrow's tooltip gives the value)");
      }
      svg << "<defs><marker id=\"reaction_head\" viewBox=\"0 0 10 10\" refX=\"9\" refY=\"5\" "
             "markerWidth=\"7\" markerHeight=\"7\" orient=\"auto\"><path d=\"M0,0 L10,5 L0,10 "
             "z\" fill=\"#c00\"/></marker><marker id=\"load_head\" viewBox=\"0 0 10 10\" refX=\"9\" "
             "refY=\"5\" markerWidth=\"7\" markerHeight=\"7\" orient=\"auto\"><path d=\"M0,0 L10,5 "
             "L0,10 z\" fill=\"#06c\"/></marker></defs>\n<g id=\"reactions\" data-force-scale=\""
          << ::mechgen::internal::FormatNumber(pixels_per_force, "%.17g") << "\">\n";
      // A label at the first free place next to (x, y) pixels; none if there is no room.
      auto label = [&](const char* cls, double x, double y, const std::string& text, const char* color,
                       double size) {
        double lx, ly;
        if (!labels.Place(x, y, text, size, &lx, &ly)) return;
        svg << "<text class=\"" << cls << "\" x=\"" << px(lx) << "\" y=\"" << px(ly)
            << "\" font-family=\"sans-serif\" font-size=\"" << size << "\" fill=\"" << color << "\">" << text
            << "</text>\n";
      };
      // The label of a snapshot: at the last scene point of a moving link.
      int label_point = -1;
      for (int s = 0; s < d.num_scene_points; ++s)
        if (d.scene_point_link[s] != d.ground) label_point = s;
      for (size_t i = 0; i < frame.snapshots.size(); ++i) {
        const StaticsRecord<M>& r = records[frame.snapshots[i]];
        if (!converged(frame.snapshots[i])) continue;
        Eigen::Matrix2Xd scene;
        d.scene(r.kinematics.state.q, r.kinematics.state.phi, &scene);
        std::string q_data, q_text;
        for (int j = 0; j < C::Nq(model); ++j) {
          const double q = r.kinematics.state.q(j);
          q_data += (j ? " " : "") + ::mechgen::internal::FormatNumber(q, "%.17g");
          q_text += std::string(j ? ", " : "") + C::QName(model, j) + " = " +
                    (C::QIsAngle(model, j) ? number(::mechgen::internal::ToDegrees(q)) + " deg"
                                           : number(q) + " m");
        }
        svg << "<g class=\"snapshot\" data-q=\"" << q_data << "\">\n";
        if (label_point >= 0)
          label("input", X(scene(0, label_point)) + 8, Y(scene(1, label_point)) - 8, q_text, "#333", 11);
        if constexpr (kMayHaveReactions) {
          for (const Arrow& a : arrows) {
            const double x = scene(0, a.point), y = scene(1, a.point);
            const double fx = r.frictionless.statics.R(a.x), fy = r.frictionless.statics.R(a.y);
            const double magnitude = std::hypot(fx, fy);
            if (!(magnitude > 1e-3 * largest)) continue;
            svg << "<line x1=\"" << frame.X(x) << "\" y1=\"" << frame.Y(y) << "\" x2=\""
                << frame.X(x + per_unit * fx) << "\" y2=\"" << frame.Y(y + per_unit * fy)
                << "\" stroke=\"#c00\" stroke-width=\"2\" marker-end=\"url(#reaction_head)\">"
                << "<title>F_" << a.joint << " = (" << number(fx) << ", " << number(fy) << ") N"
                << a.who << "</title></line>\n";
            label("magnitude", X(x + per_unit * fx) + 4, Y(y + per_unit * fy) - 4,
                  "F_" + a.joint + " " + number(magnitude) + " N", "#c00", 10);
          }
        }
        if (kApplied) {
          const Applied& A = applied[i];
          for (int l = 0; l < kNumApplied; ++l) {
            const int kind = loads.kinds[static_cast<size_t>(l)];
            const std::string& name = loads.names[static_cast<size_t>(l)];
            const std::string& unit = loads.units[static_cast<size_t>(l)];
            const double x = A(0, l), y = A(1, l), value = A(6, l);
            const std::string at = ::mechgen::internal::FormatNumber(x, "%.17g") + " " +
                                   ::mechgen::internal::FormatNumber(y, "%.17g");
            if (kind == 0 || kind == 4) {  // a force load or a weight: an arrow from its point
              const double fx = A(4, l), fy = A(5, l), magnitude = std::hypot(fx, fy);
              if (!scaled || !(magnitude > 1e-3 * largest)) continue;
              svg << "<line class=\"" << (kind == 0 ? "load" : "weight") << "\" data-at=\"" << at << "\" data-value=\""
                  << ::mechgen::internal::FormatNumber(magnitude, "%.17g") << "\" x1=\"" << px(X(x)) << "\" y1=\""
                  << px(Y(y)) << "\" x2=\"" << px(X(x + per_unit * fx)) << "\" y2=\"" << px(Y(y + per_unit * fy))
                  << "\" stroke=\"#06c\" stroke-width=\"2\" marker-end=\"url(#load_head)\"><title>" << name << " = ("
                  << number(fx) << ", " << number(fy) << ") " << unit << " at (" << number(x) << ", " << number(y)
                  << ")" << (kind == 4 ? " (weight m g at the centre of mass)" : "") << "</title></line>\n";
              label(kind == 0 ? "load_magnitude" : "weight_magnitude", X(x + per_unit * fx) + 4, Y(y + per_unit * fy) - 4,
                    name + " " + number(magnitude) + " " + unit, "#06c", 10);
            } else if (kind == 2) {  // a linear spring: a zig-zag between its ends
              const double x0 = X(x), y0 = Y(y), x1 = X(A(2, l)), y1 = Y(A(3, l));
              const double dx = x1 - x0, dy = y1 - y0, length = std::hypot(dx, dy);
              const double nx = length > 0 ? -dy / length : 0, ny = length > 0 ? dx / length : 0;
              std::string points = px(x0) + "," + px(y0);
              constexpr int kZigs = 10;
              for (int z = 0; z <= kZigs; ++z) {
                const double t = 0.15 + 0.7 * z / kZigs;
                const double side = z == 0 || z == kZigs ? 0 : (z % 2 == 1 ? 5 : -5);
                points += " " + px(x0 + t * dx + side * nx) + "," + px(y0 + t * dy + side * ny);
              }
              points += " " + px(x1) + "," + px(y1);
              svg << "<polyline class=\"spring\" data-at=\"" << at << "\" data-b=\""
                  << ::mechgen::internal::FormatNumber(A(2, l), "%.17g") << " "
                  << ::mechgen::internal::FormatNumber(A(3, l), "%.17g") << "\" data-value=\""
                  << ::mechgen::internal::FormatNumber(value, "%.17g") << "\" points=\"" << points
                  << "\" fill=\"none\" stroke=\"#06c\" stroke-width=\"1.5\"><title>" << name << ": tension "
                  << number(value) << " " << unit << " (+ pulling its ends together), force on its end a ("
                  << number(A(4, l)) << ", " << number(A(5, l)) << ") " << unit << "</title></polyline>\n";
              label("spring_force", x0 + 0.5 * dx + 8, y0 + 0.5 * dy - 6,
                    name + " " + number(value) + " " + unit + (value >= 0 ? " (tension)" : " (compression)"),
                    "#06c", 10);
            } else {  // a torque load or a torsional spring: a curved arrow round its point
              if (!(value != 0) || !std::isfinite(value)) continue;
              const double cx = X(x), cy = Y(y), radius = 16;
              // From below the point, three quarters of a turn: counter-clockwise as drawn
              // (increasing angle, y up) for a positive torque.
              const double end = value > 0 ? 3.141592653589793 : 0;
              svg << "<path class=\"" << (kind == 1 ? "torque" : "torsion") << "\" data-at=\"" << at
                  << "\" data-value=\"" << ::mechgen::internal::FormatNumber(value, "%.17g") << "\" d=\"M"
                  << px(cx) << "," << px(cy + radius) << " A" << radius << "," << radius << " 0 1 "
                  << (value > 0 ? 0 : 1) << " " << px(cx + radius * std::cos(end)) << ","
                  << px(cy - radius * std::sin(end)) << "\" fill=\"none\" stroke=\"#06c\" stroke-width=\"2\""
                  << (kind == 3 ? " stroke-dasharray=\"4,2\"" : "") << " marker-end=\"url(#load_head)\"><title>"
                  << name << " = " << number(value) << " " << unit << " (counter-clockwise +"
                  << (kind == 3 ? ", on the joint's second link" : "") << ")</title></path>\n";
              label("torque_magnitude", cx + radius + 4, cy - radius,
                    name + " " + number(value) + " " + unit, "#06c", 10);
            }
          }
        }
        svg << "</g>\n";
      }
      svg << "</g>\n" << legend;
      const std::string line_y = ::mechgen::internal::FormatNumber(bar_y, "%g");
      if (scaled)
        svg << "<g id=\"force_scale\" data-force=\"" << number(bar) << "\"><line x1=\"8\" y1=\"" << line_y
            << "\" x2=\"" << px(8 + bar * pixels_per_force) << "\" y2=\"" << line_y
            << "\" stroke=\"#c00\" stroke-width=\"3\"/><text x=\"" << px(14 + bar * pixels_per_force) << "\" y=\""
            << ::mechgen::internal::FormatNumber(bar_y + 4, "%g") << "\" font-family=\"sans-serif\" font-size=\"12\" fill=\"#c00\">" << number(bar)
            << " N (force scale: " << number(1 / per_unit) << " N per model length unit)</text></g>\n";
    }
  };
  WriteSvg(model, params, kinematics, options, out);
}

/// WriteStaticsSvg of a generated model M (an empty tag).
template <class M, std::enable_if_t<!ModelCalls<M>::kView, int> = 0>
void WriteStaticsSvg(const typename ModelTypes<M>::Params& params, const std::vector<StaticsRecord<M>>& records,
                     SvgOptions options, std::ostream& out) {
  WriteStaticsSvg(M(), params, records, std::move(options), out);
}

}  // namespace mechgen::statics
