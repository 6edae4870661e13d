/**
 * \file statics/svg.h
 * An SVG force diagram of a statics sweep: the drawing of io/svg.h (the mechanism at a few
 * configurations, the point paths, the ground pivots) with the reaction vectors drawn at the
 * pins of those snapshot configurations (SvgOptions::overlay).
 *
 * Each arrow is the frictionless reaction F_J = (F_J_x, F_J_y) of a revolute joint J, the
 * force of the joint's first link on its second (the contract's convention), drawn from the
 * pin: at the scene point whose name is J (e.g. "crank.B" for joint B); joints without such
 * a point and the reactions of prismatic, gear and cam joints (whose direction the runtime
 * does not know) are not drawn. Each arrow has its magnitude written at its tip ("F_B 1000 N")
 * and says who acts on whom in its tooltip ("F_B = (..) N: force of crank on rod").
 * Each snapshot's arrows are one group <g class="snapshot" data-q="..."> (the inputs, model
 * units) with a label of its inputs ("theta_crank = 90 deg") at the last point of a moving
 * link; `--snapshots 1` draws one configuration per picture. One scale for all arrows: the
 * largest drawn reaction is 10 % of the drawing's span (inside its 12 % margin); a force
 * scale bar (a round force, its length in the drawing's scale) and the group's
 * data-force-scale (pixels per force unit) give it. Rows that are not converged (e.g.
 * singular) draw no arrows. Allocates; runs after the sweep.
 *
 * Not drawn: the applied loads and the springs themselves (the generated model does not
 * hand their points and vectors to the runtime, only their effect on Q and the reactions).
 */
#pragma once

#include <algorithm>
#include <cmath>
#include <cstring>
#include <ostream>
#include <string>
#include <vector>

#include "mechgen/io/format.h"
#include "mechgen/io/svg.h"
#include "mechgen/statics/columns.h"

namespace mechgen::statics {

/**
 * \brief Writes the SVG of io/svg.h for the sweep's configurations with the reaction arrows
 *        of the snapshots (options.snapshots of them).
 * \param[in] params   Parameters the sweep ran with.
 * \param[in] records  The statics sweep.
 */
template <class M>
void WriteStaticsSvg(const typename ModelTypes<M>::Params& params,
                     const std::vector<StaticsRecord<M>>& records, SvgOptions options,
                     std::ostream& out) {
  std::vector<SweepRecord<M>> kinematics;
  kinematics.reserve(records.size());
  for (const StaticsRecord<M>& r : records) kinematics.push_back(r.kinematics);
  // Revolute joints with a scene point of the same name: (x index, y index, scene point).
  struct Arrow {
    std::string joint;
    int x, y, point;
    std::string who;  ///< ": force of <link a> on <link b>" when the model names the links
  };
  std::vector<Arrow> arrows;
  if constexpr (StaticsFeatures<M>::kHasReactions && ModelFeatures<M>::kHasScene) {
    for (const ReactionJoint& j : ReactionJoints<M>()) {
      if (j.x < 0 || j.y < 0) continue;
      for (int s = 0; s < M::kNumScenePoints; ++s) {
        if (j.joint == ::mechgen::internal::ShortName(M::kScenePointNames[s])) {
          std::string who;
          if constexpr (internal::HasJointLinks<M>::value) {
            const int joint = M::kReactionJoint[j.x];
            who = std::string(": force of ") + M::kLinkNames[M::kDrawJointLinkA[joint]] + " on " +
                  M::kLinkNames[M::kDrawJointLinkB[joint]];
          }
          arrows.push_back({j.joint, j.x, j.y, s, who});
          break;
        }
      }
    }
  }
  options.overlay = [&](const SvgFrame& frame, std::ostream& svg) {
    (void)frame;
    (void)svg;
    if constexpr (StaticsFeatures<M>::kHasReactions && ModelFeatures<M>::kHasScene) {
      double largest = 0;
      for (size_t index : frame.snapshots) {
        const StaticsRecord<M>& r = records[index];
        if (r.frictionless.summary.status != Status::kConverged) continue;
        for (const Arrow& a : arrows)
          largest = std::max(largest, std::hypot(r.frictionless.statics.R(a.x),
                                                 r.frictionless.statics.R(a.y)));
      }
      if (!(largest > 0) || !std::isfinite(largest)) return;
      const double per_unit = 0.1 * frame.span / largest;  // model length per force unit
      const double pixels_per_force = per_unit * frame.scale;
      auto number = [](double x) { return ::mechgen::internal::FormatNumber(x, "%.4g"); };
      // The force scale bar: the round force (1, 2 or 5 times a power of ten) at most the
      // largest reaction, drawn at the drawing's scale.
      const double decade = std::pow(10.0, std::floor(std::log10(largest)));
      const double mantissa = largest / decade;
      const double bar = (mantissa >= 5 ? 5 : mantissa >= 2 ? 2 : 1) * decade;
      const double bar_pixels = bar * pixels_per_force;
      svg << "<defs><marker id=\"reaction_head\" viewBox=\"0 0 10 10\" refX=\"9\" refY=\"5\" "
             "markerWidth=\"7\" markerHeight=\"7\" orient=\"auto\"><path d=\"M0,0 L10,5 L0,10 "
             "z\" fill=\"#c00\"/></marker></defs>\n<g id=\"reactions\" data-force-scale=\""
          << ::mechgen::internal::FormatNumber(pixels_per_force, "%.17g") << "\">\n";
      // The label of a snapshot: at the last scene point of a moving link.
      int label_point = -1;
      for (int s = 0; s < M::kNumScenePoints; ++s)
        if (M::kScenePointLink[s] != M::kGroundLink) label_point = s;
      for (size_t index : frame.snapshots) {
        const StaticsRecord<M>& r = records[index];
        if (r.frictionless.summary.status != Status::kConverged) continue;
        typename ModelTypes<M>::MatScene scene;
        M::template Scene<double>(params, r.kinematics.state.q, r.kinematics.state.phi, &scene);
        std::string q_data, q_text;
        for (int j = 0; j < M::kNq; ++j) {
          const double q = r.kinematics.state.q(j);
          q_data += (j ? " " : "") + ::mechgen::internal::FormatNumber(q, "%.17g");
          q_text += std::string(j ? ", " : "") + M::kQNames[j] + " = " +
                    (M::kQIsAngle[j] ? number(q * ::mechgen::internal::kRadToDeg) + " deg"
                                     : number(q) + " m");
        }
        svg << "<g class=\"snapshot\" data-q=\"" << q_data << "\">\n";
        if (label_point >= 0) {
          svg << "<text class=\"input\" x=\"" << frame.X(scene(0, label_point)) << "\" y=\""
              << frame.Y(scene(1, label_point)) << "\" dx=\"8\" dy=\"-8\" font-family=\"sans-serif\" "
              << "font-size=\"11\" fill=\"#333\">" << q_text << "</text>\n";
        }
        for (const Arrow& a : arrows) {
          const double x = scene(0, a.point), y = scene(1, a.point);
          const double fx = r.frictionless.statics.R(a.x), fy = r.frictionless.statics.R(a.y);
          const double magnitude = std::hypot(fx, fy);
          if (!(magnitude > 1e-3 * largest)) continue;
          svg << "<line x1=\"" << frame.X(x) << "\" y1=\"" << frame.Y(y) << "\" x2=\""
              << frame.X(x + per_unit * fx) << "\" y2=\"" << frame.Y(y + per_unit * fy)
              << "\" stroke=\"#c00\" stroke-width=\"2\" marker-end=\"url(#reaction_head)\">"
              << "<title>F_" << a.joint << " = (" << number(fx) << ", " << number(fy) << ") N"
              << a.who << "</title></line>\n"
              << "<text class=\"magnitude\" x=\"" << frame.X(x + per_unit * fx) << "\" y=\""
              << frame.Y(y + per_unit * fy) << "\" dx=\"4\" dy=\"-4\" font-family=\"sans-serif\" "
              << "font-size=\"10\" fill=\"#c00\">F_" << a.joint << " " << number(magnitude)
              << " N</text>\n";
        }
        svg << "</g>\n";
      }
      svg << "</g>\n<text x=\"8\" y=\"40\" font-family=\"sans-serif\" font-size=\"12\" "
             "fill=\"#c00\">reactions (force of a joint's first link on its second); longest "
          << number(largest) << " N</text>\n"
          << "<g id=\"force_scale\" data-force=\"" << number(bar) << "\"><line x1=\"8\" y1=\"54\" x2=\""
          << ::mechgen::internal::FormatNumber(8 + bar_pixels, "%.2f")
          << "\" y2=\"54\" stroke=\"#c00\" stroke-width=\"3\"/><text x=\""
          << ::mechgen::internal::FormatNumber(14 + bar_pixels, "%.2f")
          << "\" y=\"58\" font-family=\"sans-serif\" font-size=\"12\" fill=\"#c00\">"
          << number(bar) << " N (force scale: " << number(1 / per_unit)
          << " N per model length unit)</text></g>\n";
    }
  };
  WriteSvg<M>(params, kinematics, options, out);
}

}  // namespace mechgen::statics
