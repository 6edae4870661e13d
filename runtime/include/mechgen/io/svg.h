/**
 * \file io/svg.h
 * An SVG drawing of a sweep: the mechanism at a few configurations (the links through each
 * link's scene points, Model::Scene), the traced paths of its points (the coupler curve),
 * the ground pivots, plus one animated (SMIL) copy running through the whole sweep.
 * Allocates; runs after the sweep.
 */
#pragma once

#include <algorithm>
#include <cmath>
#include <cstring>
#include <functional>
#include <limits>
#include <ostream>
#include <string>
#include <vector>

#include "mechgen/io/format.h"
#include "mechgen/sweep/sweep.h"

namespace mechgen {

namespace internal {
/// "ground.A" -> "A".
inline const char* ShortName(const char* name) {
  const char* dot = std::strrchr(name, '.');
  return dot != nullptr ? dot + 1 : name;
}
}  // namespace internal

/// The drawing's frame, for SvgOptions::overlay: model coordinates to pixels, and which
/// records the faded snapshots show.
struct SvgFrame {
  double x_min = 0, y_max = 0, scale = 1;  ///< pixel x = (x - x_min) scale, y = (y_max - y) scale + 30
  double span = 1;                          ///< the larger side of the drawn box (model units)
  std::vector<size_t> snapshots;            ///< indices into the records of the snapshots
  std::string X(double x) const { return internal::FormatNumber((x - x_min) * scale, "%.2f"); }
  std::string Y(double y) const { return internal::FormatNumber((y_max - y) * scale + 30, "%.2f"); }
};

/// What WriteSvg() draws.
struct SvgOptions {
  int width = 900;           ///< pixels; the height follows the aspect ratio
  int snapshots = 6;         ///< configurations drawn as still, faded copies
  bool animate = true;       ///< add an animated (SMIL) copy through the whole sweep
  double seconds = 6.0;      ///< duration of one animated cycle
  int max_frames = 240;      ///< animation frames (records are subsampled)
  std::string title;         ///< drawn at the top left
  /// Drawn last, over everything (e.g. the reaction arrows of the statics sweep); none if empty.
  std::function<void(const SvgFrame&, std::ostream&)> overlay;
};

/**
 * \brief Writes an SVG: paths of the requested points, the links (lines or polygons through
 *        each link's scene points) at a few configurations, ground pivots, and an animation.
 * \param[in] params   Parameters the sweep ran with (for Model::Scene).
 * \param[in] records  The sweep; only converged rows are drawn.
 */
template <class M>
void WriteSvg(const typename ModelTypes<M>::Params& params,
              const std::vector<SweepRecord<M>>& records,
              const SvgOptions& options,
              std::ostream& out) {
  using F = ModelFeatures<M>;
  using Scene = typename ModelTypes<M>::MatScene;
  // Scene points of every converged row, and the bounding box of everything drawn.
  std::vector<const SweepRecord<M>*> valid;
  for (const SweepRecord<M>& r : records)
    if (r.state.valid) valid.push_back(&r);
  std::vector<Scene> scenes(valid.size());
  double x_min = std::numeric_limits<double>::infinity(), x_max = -x_min;
  double y_min = x_min, y_max = -x_min;
  auto extend = [&](double x, double y) {
    if (!std::isfinite(x) || !std::isfinite(y)) return;
    x_min = std::min(x_min, x);
    x_max = std::max(x_max, x);
    y_min = std::min(y_min, y);
    y_max = std::max(y_max, y);
  };
  for (size_t f = 0; f < valid.size(); ++f) {
    if constexpr (F::kHasScene) {
      M::template Scene<double>(params, valid[f]->state.q, valid[f]->state.phi, &scenes[f]);
      for (int s = 0; s < M::kNumScenePoints; ++s) extend(scenes[f](0, s), scenes[f](1, s));
    }
    if constexpr (F::kHasPoints) {
      for (int p = 0; p < M::kNumPoints; ++p)
        extend(valid[f]->state.r_P(0, p), valid[f]->state.r_P(1, p));
    }
  }
  if (!(x_max >= x_min)) x_min = -1, x_max = 1, y_min = -1, y_max = 1;
  const double span = std::max({x_max - x_min, y_max - y_min, 1e-9});
  const double margin = 0.12 * span;
  x_min -= margin, x_max += margin, y_min -= margin, y_max += margin;
  const double scale = options.width / (x_max - x_min);
  const int height = static_cast<int>(std::ceil((y_max - y_min) * scale)) + 30;
  auto X = [&](double x) { return internal::FormatNumber((x - x_min) * scale, "%.2f"); };
  auto Y = [&](double y) { return internal::FormatNumber((y_max - y) * scale + 30, "%.2f"); };
  const double unit = span / 100;  // marker size in model units
  const char* kColors[] = {"#d62728", "#1f77b4", "#2ca02c", "#9467bd", "#ff7f0e", "#8c564b"};
  const char* kLinkColors[] = {"#444", "#1f77b4", "#ff7f0e", "#2ca02c", "#9467bd", "#8c564b",
                               "#e377c2", "#17becf"};

  out << "<svg xmlns=\"http://www.w3.org/2000/svg\" width=\"" << options.width << "\" height=\""
      << height << "\" viewBox=\"0 0 " << options.width << ' ' << height << "\">\n";
  out << "<rect width=\"100%\" height=\"100%\" fill=\"white\"/>\n";
  out << "<text x=\"8\" y=\"20\" font-family=\"sans-serif\" font-size=\"15\">" << options.title
      << "</text>\n";
  // The fixed x axis through the origin, if visible.
  if (y_min < 0 && y_max > 0) {
    out << "<line x1=\"0\" y1=\"" << Y(0) << "\" x2=\"" << options.width << "\" y2=\"" << Y(0)
        << "\" stroke=\"#ddd\" stroke-dasharray=\"4 4\"/>\n";
  }

  // Link outlines of one configuration as SVG point lists, one per moving link.
  auto link_points = [&](const Scene& scene, int link) {
    std::string points;
    for (int s = 0; s < M::kNumScenePoints; ++s) {
      if (M::kScenePointLink[s] != link) continue;
      points += X(scene(0, s)) + "," + Y(scene(1, s)) + " ";
    }
    return points;
  };
  auto points_on_link = [&](int link) {
    int n = 0;
    for (int s = 0; s < M::kNumScenePoints; ++s) n += M::kScenePointLink[s] == link;
    return n;
  };
  // Each moving link as a line (2 points) or a polygon (3 or more) through its scene points;
  // `faded`: thin outlines for the snapshots.
  auto draw_links = [&](const Scene& scene, bool faded, bool animated,
                        std::vector<std::string>* frames_per_link) {
    for (int link = 0; link < M::kNumLinks; ++link) {
      if (link == M::kGroundLink) continue;
      const int n = points_on_link(link);
      if (n == 0) continue;
      const char* color = kLinkColors[link % 8];
      const char* shape = n >= 3 ? "polygon" : "polyline";
      out << '<' << shape << " points=\"" << link_points(scene, link) << "\" stroke=\"" << color
          << (faded ? "\" stroke-width=\"1.5\" stroke-opacity=\"0.4\" fill=\"none\""
                    : "\" stroke-width=\"5\" fill=\"")
          << (faded ? "" : (n >= 3 ? color : "none"))
          << (faded ? "" : (n >= 3 ? "\" fill-opacity=\"0.2\"" : "\""))
          << " stroke-linejoin=\"round\" stroke-linecap=\"round\"";
      if (n == 1) out << " marker-start=\"url(#block)\"";
      if (animated && frames_per_link != nullptr) {
        out << "><animate attributeName=\"points\" dur=\"" << options.seconds
            << "s\" repeatCount=\"indefinite\" values=\"" << (*frames_per_link)[link] << "\"/></"
            << shape << ">\n";
      } else {
        out << "/>\n";
      }
    }
  };
  out << "<defs><marker id=\"block\" viewBox=\"-5 -5 10 10\" markerWidth=\"10\" "
         "markerHeight=\"10\"><rect x=\"-4\" y=\"-3\" width=\"8\" height=\"6\" fill=\"#555\"/>"
         "</marker></defs>\n";

  if constexpr (F::kHasScene) {
    // Faded snapshots.
    const int snapshots = std::min<int>(options.snapshots, static_cast<int>(valid.size()));
    out << "<g id=\"snapshots\">\n";
    for (int k = 0; k < snapshots; ++k) {
      const size_t f = valid.size() * static_cast<size_t>(k) / static_cast<size_t>(snapshots);
      draw_links(scenes[f], true, false, nullptr);
    }
    out << "</g>\n";
  }
  // Traced paths of the requested points.
  if constexpr (F::kHasPoints) {
    for (int p = 0; p < M::kNumPoints; ++p) {
      out << "<polyline fill=\"none\" stroke=\"" << kColors[p % 6]
          << "\" stroke-width=\"2\" points=\"";
      for (const SweepRecord<M>* r : valid)
        out << X(r->state.r_P(0, p)) << ',' << Y(r->state.r_P(1, p)) << ' ';
      out << "\"/>\n";
      if (!valid.empty()) {
        out << "<text x=\"" << X(valid.front()->state.r_P(0, p) + unit) << "\" y=\""
            << Y(valid.front()->state.r_P(1, p) + unit)
            << "\" font-family=\"sans-serif\" font-size=\"13\" fill=\"" << kColors[p % 6]
            << "\">" << M::kPointNames[p] << "</text>\n";
      }
    }
  }
  if constexpr (F::kHasScene) {
    if (!valid.empty()) {
      // Ground pivots: a triangle with a hatched base under each ground point.
      const Scene& first = scenes.front();
      for (int s = 0; s < M::kNumScenePoints; ++s) {
        if (M::kScenePointLink[s] != M::kGroundLink) continue;
        const double x = first(0, s), y = first(1, s);
        const double u = 2.5 * unit;
        out << "<polygon points=\"" << X(x) << ',' << Y(y) << ' ' << X(x - u) << ','
            << Y(y - 1.6 * u) << ' ' << X(x + u) << ',' << Y(y - 1.6 * u)
            << "\" fill=\"#bbb\" stroke=\"#333\"/>\n";
        out << "<line x1=\"" << X(x - 1.5 * u) << "\" y1=\"" << Y(y - 1.6 * u) << "\" x2=\""
            << X(x + 1.5 * u) << "\" y2=\"" << Y(y - 1.6 * u)
            << "\" stroke=\"#333\" stroke-width=\"2\"/>\n";
        out << "<text x=\"" << X(x + 1.2 * u) << "\" y=\"" << Y(y - 2.6 * u)
            << "\" font-family=\"sans-serif\" font-size=\"12\" fill=\"#333\">"
            << internal::ShortName(M::kScenePointNames[s]) << "</text>\n";
      }
      // The first configuration, solid, or an animated copy through the sweep (whose still
      // image, for viewers without SMIL, is the first configuration).
      const bool animate = options.animate && valid.size() > 1;
      if (!animate) {
        draw_links(first, false, false, nullptr);
        for (int s = 0; s < M::kNumScenePoints; ++s) {
          out << "<circle cx=\"" << X(first(0, s)) << "\" cy=\"" << Y(first(1, s))
              << "\" r=\"3.5\" fill=\"white\" stroke=\"#222\" stroke-width=\"1.5\"/>\n";
        }
      } else {
        const size_t frames = std::min<size_t>(valid.size(), static_cast<size_t>(options.max_frames));
        std::vector<std::string> per_link(M::kNumLinks);
        std::vector<std::string> per_point_x(M::kNumPoints), per_point_y(M::kNumPoints);
        for (size_t k = 0; k < frames; ++k) {
          const size_t f = (valid.size() - 1) * k / (frames - 1);
          for (int link = 0; link < M::kNumLinks; ++link) {
            if (!per_link[link].empty()) per_link[link] += ';';
            per_link[link] += link_points(scenes[f], link);
          }
          if constexpr (F::kHasPoints) {
            for (int p = 0; p < M::kNumPoints; ++p) {
              per_point_x[p] += (k ? ";" : "") + X(valid[f]->state.r_P(0, p));
              per_point_y[p] += (k ? ";" : "") + Y(valid[f]->state.r_P(1, p));
            }
          }
        }
        out << "<g id=\"animation\">\n";
        draw_links(first, false, true, &per_link);
        if constexpr (F::kHasPoints) {
          for (int p = 0; p < M::kNumPoints; ++p) {
            out << "<circle r=\"5\" fill=\"" << kColors[p % 6] << "\"><animate attributeName=\"cx\" dur=\""
                << options.seconds << "s\" repeatCount=\"indefinite\" values=\"" << per_point_x[p]
                << "\"/><animate attributeName=\"cy\" dur=\"" << options.seconds
                << "s\" repeatCount=\"indefinite\" values=\"" << per_point_y[p] << "\"/></circle>\n";
          }
        }
        out << "</g>\n";
      }
    }
  }
  if (options.overlay) {
    SvgFrame frame;
    frame.x_min = x_min;
    frame.y_max = y_max;
    frame.scale = scale;
    frame.span = span;
    const size_t snapshots = std::min<size_t>(static_cast<size_t>(std::max(options.snapshots, 0)),
                                              valid.size());
    for (size_t k = 0; k < snapshots; ++k)
      frame.snapshots.push_back(static_cast<size_t>(valid[valid.size() * k / snapshots] -
                                                    records.data()));
    options.overlay(frame, out);
  }
  out << "</svg>\n";
}

}  // namespace mechgen
