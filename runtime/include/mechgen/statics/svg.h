/**
 * \file statics/svg.h
 * An SVG drawing of a statics sweep: the drawing of io/svg.h (the mechanism at a few
 * configurations, the point paths, the ground pivots) with the reaction vectors drawn at the
 * pins of those snapshot configurations (SvgOptions::overlay).
 *
 * Each arrow is the frictionless reaction F_J = (F_J_x, F_J_y) of a revolute joint J, the
 * force of the joint's first link on its second (the contract's convention), drawn from the
 * pin: at the scene point whose name is J (e.g. "crank.B" for joint B); joints without such
 * a point and the reactions of prismatic, gear and cam joints (whose direction the runtime
 * does not know) are not drawn. One scale for all arrows: the largest drawn reaction is 10 %
 * of the drawing's span (inside its 12 % margin); the legend gives it. Rows that are not converged (e.g. singular)
 * draw no arrows. Allocates; runs after the sweep.
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
  };
  std::vector<Arrow> arrows;
  if constexpr (StaticsFeatures<M>::kHasReactions && ModelFeatures<M>::kHasScene) {
    for (const ReactionJoint& j : ReactionJoints<M>()) {
      if (j.x < 0 || j.y < 0) continue;
      for (int s = 0; s < M::kNumScenePoints; ++s) {
        if (j.joint == ::mechgen::internal::ShortName(M::kScenePointNames[s])) {
          arrows.push_back({j.joint, j.x, j.y, s});
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
      svg << "<defs><marker id=\"reaction_head\" viewBox=\"0 0 10 10\" refX=\"9\" refY=\"5\" "
             "markerWidth=\"7\" markerHeight=\"7\" orient=\"auto\"><path d=\"M0,0 L10,5 L0,10 "
             "z\" fill=\"#c00\"/></marker></defs>\n<g id=\"reactions\">\n";
      for (size_t index : frame.snapshots) {
        const StaticsRecord<M>& r = records[index];
        if (r.frictionless.summary.status != Status::kConverged) continue;
        typename ModelTypes<M>::MatScene scene;
        M::template Scene<double>(params, r.kinematics.state.q, r.kinematics.state.phi, &scene);
        for (const Arrow& a : arrows) {
          const double x = scene(0, a.point), y = scene(1, a.point);
          const double fx = r.frictionless.statics.R(a.x), fy = r.frictionless.statics.R(a.y);
          if (!(std::hypot(fx, fy) > 1e-3 * largest)) continue;
          svg << "<line x1=\"" << frame.X(x) << "\" y1=\"" << frame.Y(y) << "\" x2=\""
              << frame.X(x + per_unit * fx) << "\" y2=\"" << frame.Y(y + per_unit * fy)
              << "\" stroke=\"#c00\" stroke-width=\"2\" marker-end=\"url(#reaction_head)\">"
              << "<title>F_" << a.joint << " = ("
              << ::mechgen::internal::FormatNumber(fx, "%.4g") << ", "
              << ::mechgen::internal::FormatNumber(fy, "%.4g") << ")</title></line>\n";
        }
      }
      svg << "</g>\n<text x=\"8\" y=\"40\" font-family=\"sans-serif\" font-size=\"12\" "
             "fill=\"#c00\">reactions (force of a joint's first link on its second); longest "
          << ::mechgen::internal::FormatNumber(largest, "%.4g") << "</text>\n";
    }
  };
  WriteSvg<M>(params, kinematics, options, out);
}

}  // namespace mechgen::statics
