/**
 * \file io/svg.h
 * An SVG drawing of a sweep: the mechanism at a few configurations, the traced paths of its
 * requested points with a legend, a scale bar and the axes, plus one animated (SMIL) copy
 * running through the whole sweep whose still image (static renderers, rsvg-convert) is the
 * first configuration.
 *
 * What is drawn comes from the generated drawing description (Model::kDrawJoint*,
 * Model::Drawing, Model::CamProfile; models generated without it get bars and plates only):
 * a link with two points is a bar between them, with more a filled plate (their convex
 * hull); a pin is a small circle, a pin to the ground a hatched pivot; a prismatic joint a
 * block on the slider link over its guide (rails on the ground, a slot in a moving guide,
 * as long as the slider travels); a slot joint a slot in the slotted link (a rounded groove
 * as long as the pin travels, class "slot") with the pin in it (a small circle on the pin's
 * link, class "slot-pin"); gears their pitch circles (with spokes, so that they are seen to
 * turn), a rolling wheel its circle on its line or circle, a cam its profile and its
 * follower's roller or face. Every moving link is drawn once in its own frame and moved by
 * animateTransform. Allocates; runs after the sweep.
 */
#pragma once

#include <algorithm>
#include <array>
#include <cmath>
#include <cstring>
#include <functional>
#include <limits>
#include <ostream>
#include <string>
#include <type_traits>
#include <vector>

#include <Eigen/Core>

#include "mechgen/core/constants.h"
#include "mechgen/core/model_calls.h"
#include "mechgen/core/model_view.h"
#include "mechgen/core/model_traits.h"
#include "mechgen/io/format.h"

namespace mechgen {

namespace internal {
/// "ground.A" -> "A".
inline const char* ShortName(const char* name) {
  const char* dot = std::strrchr(name, '.');
  return dot != nullptr ? dot + 1 : name;
}

/// Whether the model has the generated drawing description (kDrawJoint*, Drawing) and cams to
/// draw (Model::CamProfile): its flags kHasDrawing and kHasCamProfile (core/model_traits.h).
template <class M>
using HasDrawing = mechgen::HasDrawing<M>;
template <class M>
using HasCamProfile = mechgen::HasCamProfile<M>;

/// Joint kinds of Model::kDrawJointKind.
enum DrawJoint { kDrawRevolute = 0, kDrawPrismatic, kDrawRoll, kDrawGear, kDrawRack, kDrawCam, kDrawSlot };

/// Whether a joint kind slides along a line of its first link (its value: the line's angle in
/// the fixed frame; its points: a point of the line, the sliding point).
constexpr bool SlidesOnLine(int kind) { return kind == kDrawPrismatic || kind == kDrawSlot; }

/// What WriteSvg draws from, read once from the model: its sizes, names and drawing
/// description (the generated Model's constants, or its view's arrays) and its scene, drawing
/// and cam functions at the sweep's parameters. One source for a generated model and the
/// model view (core/view_model.h); the numbers drawn are the same either way.
template <class M>
struct SvgModel {
  using Types = ModelTypes<M>;
  bool has_scene = false, has_points = false, has_drawing = false, has_cam = false;
  int num_links = 0, ground = 0, num_points = 0, num_scene_points = 0, num_draw_joints = 0, num_draw_values = 0;
  std::vector<const char*> link_names, point_names, scene_point_names;
  std::vector<int> scene_point_link, kind, link_a, link_b, point_a, point_b, value;
  /// The scene points at (q, phi): 2 x num_scene_points.
  std::function<void(const typename Types::VecQ&, const typename Types::VecPhi&, Eigen::Matrix2Xd*)> scene;
  /// The links' frames (x, y, theta: 3 x num_links, set to zero first) and the joints' values.
  std::function<void(const typename Types::VecQ&, const typename Types::VecPhi&, Eigen::Matrix3Xd*,
                     std::vector<double>*)>
      drawing;
  /// Cam joint j's profile at t in [0, 1), in its cam's frame.
  std::function<std::array<double, 2>(int, double)> cam;
};

template <class M>
SvgModel<M> DescribeForSvg(const M& model, const typename ModelTypes<M>::Params& params) {
  using F = ModelFeatures<M>;
  using Types = ModelTypes<M>;
  SvgModel<M> d;
  auto list = [](auto* to, const auto* from, int n) {
    if (from != nullptr) to->assign(from, from + n);
  };
  if constexpr (ModelCalls<M>::kView) {
    const ModelView& v = *model.view;
    d.has_scene = v.num_scene_points > 0 && v.Scene != nullptr;
    d.has_points = v.num_points > 0 && v.flags.kHasPoints;
    d.has_drawing = d.has_scene && v.flags.kHasDrawing && v.Drawing != nullptr;
    d.has_cam = d.has_drawing && v.flags.kHasCamProfile && v.CamProfile != nullptr;
    d.num_links = v.num_links;
    d.ground = v.ground_link;
    d.num_points = d.has_points ? v.num_points : 0;
    d.num_scene_points = d.has_scene ? v.num_scene_points : 0;
    d.num_draw_joints = d.has_drawing ? v.num_draw_joints : 0;
    d.num_draw_values = d.has_drawing ? v.num_draw_values : 0;
    list(&d.link_names, v.link_names, v.num_links);
    list(&d.point_names, v.point_names, d.num_points);
    list(&d.scene_point_names, v.scene_point_names, d.num_scene_points);
    list(&d.scene_point_link, v.scene_point_links, d.num_scene_points);
    list(&d.kind, v.draw_joint_kind, d.num_draw_joints);
    list(&d.link_a, v.draw_joint_link_a, d.num_draw_joints);
    list(&d.link_b, v.draw_joint_link_b, d.num_draw_joints);
    list(&d.point_a, v.draw_joint_point_a, d.num_draw_joints);
    list(&d.point_b, v.draw_joint_point_b, d.num_draw_joints);
    list(&d.value, v.draw_joint_value, d.num_draw_joints);
    const ModelView* view = &v;
    d.scene = [view, params](const typename Types::VecQ& q, const typename Types::VecPhi& phi, Eigen::Matrix2Xd* r) {
      r->resize(2, view->num_scene_points);
      view->Scene(params.data(), q.data(), phi.data(), r->data());
    };
    d.drawing = [view, params](const typename Types::VecQ& q, const typename Types::VecPhi& phi,
                               Eigen::Matrix3Xd* frames, std::vector<double>* values) {
      frames->setZero(3, view->num_links);
      values->assign(static_cast<size_t>(view->num_draw_values), 0.0);
      view->Drawing(params.data(), q.data(), phi.data(), frames->data(), values->data());
    };
    d.cam = [view, params](int j, double t) {
      std::array<double, 2> r{};
      view->CamProfile(params.data(), j, t, r.data());
      return r;
    };
  } else {
    (void)model;
    d.has_scene = F::kHasScene;
    d.has_points = F::kHasPoints && M::kNumPoints > 0;
    d.has_drawing = HasDrawing<M>::value && F::kHasScene;
    d.has_cam = d.has_drawing && HasCamProfile<M>::value;
    d.num_links = M::kNumLinks;
    d.ground = M::kGroundLink;
    list(&d.link_names, M::kLinkNames.data(), M::kNumLinks);
    if constexpr (F::kHasPoints) {
      d.num_points = M::kNumPoints;
      list(&d.point_names, M::kPointNames.data(), M::kNumPoints);
    }
    if constexpr (F::kHasScene) {
      d.num_scene_points = M::kNumScenePoints;
      list(&d.scene_point_names, M::kScenePointNames.data(), M::kNumScenePoints);
      list(&d.scene_point_link, M::kScenePointLink.data(), M::kNumScenePoints);
      d.scene = [params](const typename Types::VecQ& q, const typename Types::VecPhi& phi, Eigen::Matrix2Xd* r) {
        typename Types::MatScene scene;
        M::template Scene<double>(params, q, phi, &scene);
        *r = scene;
      };
      if constexpr (HasDrawing<M>::value) {
        d.num_draw_joints = M::kNumDrawJoints;
        d.num_draw_values = M::kNumDrawValues;
        list(&d.kind, M::kDrawJointKind.data(), M::kNumDrawJoints);
        list(&d.link_a, M::kDrawJointLinkA.data(), M::kNumDrawJoints);
        list(&d.link_b, M::kDrawJointLinkB.data(), M::kNumDrawJoints);
        list(&d.point_a, M::kDrawJointPointA.data(), M::kNumDrawJoints);
        list(&d.point_b, M::kDrawJointPointB.data(), M::kNumDrawJoints);
        list(&d.value, M::kDrawJointValue.data(), M::kNumDrawJoints);
        d.drawing = [params](const typename Types::VecQ& q, const typename Types::VecPhi& phi,
                             Eigen::Matrix3Xd* frames, std::vector<double>* values) {
          Eigen::Matrix<double, 3, M::kNumLinks> f = Eigen::Matrix<double, 3, M::kNumLinks>::Zero();
          Eigen::Matrix<double, M::kNumDrawValues, 1> v;
          M::template Drawing<double>(params, q, phi, &f, &v);
          *frames = f;
          values->assign(v.data(), v.data() + M::kNumDrawValues);
        };
        if constexpr (HasCamProfile<M>::value) {
          d.cam = [params](int j, double t) {
            Eigen::Matrix<double, 2, 1> r;
            M::template CamProfile<double>(params, j, t, &r);
            return std::array<double, 2>{r(0), r(1)};
          };
        }
      }
    }
  }
  return d;
}

/// A length of 1, 2 or 5 times a power of ten, at most `limit` (> 0).
inline double RoundLength(double limit) {
  const double p = std::pow(10.0, std::floor(std::log10(limit)));
  for (double f : {5.0, 2.0, 1.0})
    if (f * p <= limit) return f * p;
  return p;
}

/// Indices of the convex hull of `pts` (counter-clockwise, Andrew's monotone chain).
inline std::vector<int> ConvexHull(const std::vector<std::array<double, 2>>& pts) {
  std::vector<int> idx(pts.size());
  for (size_t i = 0; i < idx.size(); ++i) idx[i] = static_cast<int>(i);
  std::sort(idx.begin(), idx.end(), [&](int a, int b) {
    return pts[a][0] < pts[b][0] || (pts[a][0] == pts[b][0] && pts[a][1] < pts[b][1]);
  });
  if (idx.size() < 3) return idx;
  auto cross = [&](int o, int a, int b) {
    return (pts[a][0] - pts[o][0]) * (pts[b][1] - pts[o][1]) -
           (pts[a][1] - pts[o][1]) * (pts[b][0] - pts[o][0]);
  };
  std::vector<int> hull(2 * idx.size());
  size_t k = 0;
  for (size_t i = 0; i < idx.size(); ++i) {
    while (k >= 2 && cross(hull[k - 2], hull[k - 1], idx[i]) <= 0) --k;
    hull[k++] = idx[i];
  }
  for (size_t i = idx.size() - 1, t = k + 1; i-- > 0;) {
    while (k >= t && cross(hull[k - 2], hull[k - 1], idx[i]) <= 0) --k;
    hull[k++] = idx[i];
  }
  hull.resize(k - 1);
  return hull;
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
 * \brief Writes an SVG: the mechanism (bars, plates, pins, ground pivots, sliders on their
 *        guides, gears, cams) at a few configurations, the paths of the requested points with
 *        a legend, a scale bar, and an animation.
 * \param[in] model    The model (a generated Model, or a ViewModel: DescribeForSvg reads either).
 * \param[in] params   Parameters the sweep ran with (for Model::Scene and Model::Drawing).
 * \param[in] records  The sweep (SweepRecord<M> of sweep/sweep.h, or any record template
 *                     with a position::State<M> `state`); only converged rows are drawn.
 *
 * The root element carries the mapping from model coordinates to pixels as data-x-min,
 * data-y-max and data-scale (pixel x = (x - x_min) scale, y = (y_max - y) scale + 30), and
 * every moving link's group its data-link name.
 */
template <class M, template <class> class Record>
void WriteSvg(const M& model, const typename ModelTypes<M>::Params& params, const std::vector<Record<M>>& records,
              const SvgOptions& options, std::ostream& out) {
  using P2 = std::array<double, 2>;
  const internal::SvgModel<M> d = internal::DescribeForSvg(model, params);
  const bool kDraw = d.has_drawing;
  const int kLinks = d.num_links;
  const int ground = d.ground;

  std::vector<const Record<M>*> valid;
  for (const Record<M>& r : records)
    if (r.state.valid) valid.push_back(&r);
  const size_t nv = valid.size();

  // ---- Every configuration: the scene points, the links' frames (x, y, theta) and the
  // joints' values. Without the drawing description the frames are the identity and each
  // link is drawn in the fixed frame (bars and plates only, not animated by transforms).
  std::vector<Eigen::Matrix2Xd> scenes(nv);
  std::vector<Eigen::Matrix3Xd> frames(nv, Eigen::Matrix3Xd::Zero(3, kLinks));
  std::vector<std::vector<double>> values(nv);
  for (size_t f = 0; f < nv; ++f) {
    if (d.has_scene) d.scene(valid[f]->state.q, valid[f]->state.phi, &scenes[f]);
    if (kDraw) d.drawing(valid[f]->state.q, valid[f]->state.phi, &frames[f], &values[f]);
  }
  // Continuous link angles (an animation interpolates them).
  for (size_t f = 1; f < nv; ++f)
    for (int l = 0; l < kLinks; ++l) {
      const double turn = frames[f](2, l) - frames[f - 1](2, l);
      frames[f](2, l) -= 2 * kPi * std::floor(turn / (2 * kPi) + 0.5);
    }
  auto scene_point = [&](size_t f, int s) -> P2 {
    if (d.has_scene) return {scenes[f](0, s), scenes[f](1, s)};
    return {0, 0};
  };
  // Point `p` (fixed frame) in link l's frame at configuration f.
  auto to_local = [&](size_t f, int l, const P2& p) -> P2 {
    const double c = std::cos(frames[f](2, l)), s = std::sin(frames[f](2, l));
    const double dx = p[0] - frames[f](0, l), dy = p[1] - frames[f](1, l);
    return {c * dx + s * dy, -s * dx + c * dy};
  };
  auto to_fixed = [&](size_t f, int l, const P2& p) -> P2 {
    const double c = std::cos(frames[f](2, l)), s = std::sin(frames[f](2, l));
    return {frames[f](0, l) + c * p[0] - s * p[1], frames[f](1, l) + s * p[0] + c * p[1]};
  };
  auto link_of_point = [&](int s) {
    if (d.has_scene) {
      // A rolling contact point ("<joint>.contact") is on no link's body.
      const char* name = d.scene_point_names[s];
      const char* link = d.link_names[d.scene_point_link[s]];
      const size_t n = std::strlen(link);
      if (std::strncmp(name, link, n) != 0 || name[n] != '.') return -1;
      return d.scene_point_link[s];
    }
    return -1;
  };

  // ---- The bounding box of the scene and the paths, then the shapes' sizes.
  double x_min = std::numeric_limits<double>::infinity(), x_max = -x_min;
  double y_min = x_min, y_max = -x_min;
  auto extend = [&](double x, double y) {
    if (!std::isfinite(x) || !std::isfinite(y)) return;
    x_min = std::min(x_min, x);
    x_max = std::max(x_max, x);
    y_min = std::min(y_min, y);
    y_max = std::max(y_max, y);
  };
  for (size_t f = 0; f < nv; ++f) {
    for (int s = 0; s < d.num_scene_points; ++s) extend(scenes[f](0, s), scenes[f](1, s));
    for (int p = 0; p < d.num_points; ++p) extend(valid[f]->state.r_P(0, p), valid[f]->state.r_P(1, p));
  }
  if (!(x_max >= x_min)) x_min = -1, x_max = 1, y_min = -1, y_max = 1;
  double span = std::max({x_max - x_min, y_max - y_min, 1e-9});
  const double unit = span / 100;  // shape sizes in model units
  const double tol = 1e-9 * span;

  // Cam profiles in their cams' frames (96 points each), per joint.
  constexpr int kProfile = 96;
  std::vector<std::vector<P2>> profiles;
  // Travel along each prismatic or slot joint's line: s = (slider or pin - guide or slot
  // point) . direction.
  std::vector<double> s_lo, s_hi;
  if (kDraw) {
    profiles.resize(static_cast<size_t>(d.num_draw_joints));
    s_lo.assign(static_cast<size_t>(d.num_draw_joints), std::numeric_limits<double>::infinity());
    s_hi.assign(static_cast<size_t>(d.num_draw_joints), -std::numeric_limits<double>::infinity());
    for (int j = 0; j < d.num_draw_joints; ++j) {
      const int kind = d.kind[j], a = d.point_a[j], b = d.point_b[j];
      const int v = d.value[j];
      if (d.has_cam && kind == internal::kDrawCam)
        for (int i = 0; i < kProfile; ++i) profiles[j].push_back(d.cam(j, static_cast<double>(i) / kProfile));
      for (size_t f = 0; f < nv; ++f) {
        if (internal::SlidesOnLine(kind) && a >= 0 && b >= 0) {
          const P2 g = scene_point(f, a), p = scene_point(f, b);
          const double s = (p[0] - g[0]) * std::cos(values[f][v]) + (p[1] - g[1]) * std::sin(values[f][v]);
          s_lo[j] = std::min(s_lo[j], s);
          s_hi[j] = std::max(s_hi[j], s);
        }
        // What reaches beyond the points: pitch circles, wheels, cam profiles.
        auto circle = [&](int s, double r) {
          if (s < 0) return;
          const P2 c = scene_point(f, s);
          extend(c[0] - r, c[1] - r);
          extend(c[0] + r, c[1] + r);
        };
        if (kind == internal::kDrawGear) circle(a, values[f][v]), circle(b, values[f][v + 1]);
        if (kind == internal::kDrawRack) circle(a, values[f][v]);
        if (kind == internal::kDrawRoll) circle(b, values[f][v]), circle(a, values[f][v + 1]);
        if (kind == internal::kDrawCam) {
          circle(b, values[f][v]);
          for (const P2& p : profiles[j]) {
            const P2 q = to_fixed(f, d.link_a[j], p);
            extend(q[0], q[1]);
          }
        }
      }
    }
    span = std::max({x_max - x_min, y_max - y_min, 1e-9});
  }
  const double margin = 0.12 * span;
  x_min -= margin, x_max += margin, y_min -= margin, y_max += margin;
  const double scale = options.width / (x_max - x_min);
  const int height = static_cast<int>(std::ceil((y_max - y_min) * scale)) + 60;
  auto X = [&](double x) { return internal::FormatNumber((x - x_min) * scale, "%.2f"); };
  auto Y = [&](double y) { return internal::FormatNumber((y_max - y) * scale + 30, "%.2f"); };
  auto L = [&](double v) { return internal::FormatNumber(v * scale, "%.2f"); };  // a length
  auto num = [](double v) { return internal::FormatNumber(v, "%.2f"); };
  const double px = 1 / scale;  // one pixel in model units
  const double block_len = std::max(8 * px, 5 * unit), block_h = std::max(6 * px, 3 * unit);
  const char* kPathColors[] = {"#d62728", "#1f77b4", "#2ca02c", "#9467bd", "#ff7f0e", "#8c564b"};
  const char* kLinkColors[] = {"#555", "#1f77b4", "#ff7f0e", "#2ca02c", "#9467bd", "#8c564b",
                               "#e377c2", "#17becf"};

  out << "<svg xmlns=\"http://www.w3.org/2000/svg\" width=\"" << options.width << "\" height=\""
      << height << "\" viewBox=\"0 0 " << options.width << ' ' << height << "\" data-x-min=\""
      << internal::FormatNumber(x_min, "%.9g") << "\" data-y-max=\""
      << internal::FormatNumber(y_max, "%.9g") << "\" data-scale=\""
      << internal::FormatNumber(scale, "%.9g") << "\">\n";
  out << "<rect width=\"100%\" height=\"100%\" fill=\"white\"/>\n";
  out << "<defs><pattern id=\"hatch\" width=\"6\" height=\"6\" patternUnits=\"userSpaceOnUse\" "
         "patternTransform=\"rotate(45)\"><line x1=\"0\" y1=\"0\" x2=\"0\" y2=\"6\" stroke=\"#555\" "
         "stroke-width=\"1.5\"/></pattern></defs>\n";
  out << "<text x=\"8\" y=\"20\" font-family=\"sans-serif\" font-size=\"15\">" << options.title
      << "</text>\n";

  // ---- Axes through the origin (when it is in view) and the scale bar.
  {
    const double len = internal::RoundLength(0.2 * span);
    const bool origin = x_min < 0 && x_max > 0 && y_min < 0 && y_max > 0;
    if (origin) {
      const double a = std::min(len, 0.08 * span);
      out << "<g id=\"axes\" stroke=\"#999\" stroke-width=\"1\" fill=\"#999\" font-family=\"sans-serif\" "
             "font-size=\"11\">"
          << "<line x1=\"" << X(0) << "\" y1=\"" << Y(0) << "\" x2=\"" << X(a) << "\" y2=\"" << Y(0)
          << "\"/><line x1=\"" << X(0) << "\" y1=\"" << Y(0) << "\" x2=\"" << X(0) << "\" y2=\"" << Y(a)
          << "\"/><text x=\"" << X(a + 4 * px) << "\" y=\"" << Y(-4 * px) << "\" stroke=\"none\">x</text>"
          << "<text x=\"" << X(-3 * px) << "\" y=\"" << Y(a + 5 * px) << "\" stroke=\"none\">y</text></g>\n";
    }
    const double x0 = 16, y0 = height - 16, w = len * scale;
    out << "<g id=\"scale\" stroke=\"#222\" stroke-width=\"1.5\"><line x1=\"" << num(x0) << "\" y1=\""
        << num(y0) << "\" x2=\"" << num(x0 + w) << "\" y2=\"" << num(y0) << "\"/><line x1=\"" << num(x0)
        << "\" y1=\"" << num(y0 - 5) << "\" x2=\"" << num(x0) << "\" y2=\"" << num(y0 + 5)
        << "\"/><line x1=\"" << num(x0 + w) << "\" y1=\"" << num(y0 - 5) << "\" x2=\"" << num(x0 + w)
        << "\" y2=\"" << num(y0 + 5) << "\"/><text x=\"" << num(x0 + w + 8) << "\" y=\"" << num(y0 + 4)
        << "\" stroke=\"none\" font-family=\"sans-serif\" font-size=\"12\" fill=\"#222\">"
        << internal::FormatNumber(len, "%g") << " (model length units)</text></g>\n";
  }

  // ---- A link's shapes in its own frame (pixels, y down), as SVG elements.
  // layer 0: the body (bar or plate, gear and wheel circles, cam profile, slots);
  // layer 1: what rides on it (slider blocks, rollers, pins).
  auto lp = [&](const P2& p) { return L(p[0]) + "," + L(-p[1]); };
  auto body = [&](size_t f, int link, bool faded) {
    std::string s;
    const char* color = kLinkColors[link % 8];
    std::vector<P2> pts;
    {
      for (int k = 0; k < d.num_scene_points; ++k) {
        if (link_of_point(k) != link) continue;
        const P2 p = to_local(f, link, scene_point(f, k));
        bool seen = false;
        for (const P2& q : pts) seen = seen || std::hypot(p[0] - q[0], p[1] - q[1]) <= tol;
        if (!seen) pts.push_back(p);
      }
    }
    const std::string stroke = faded ? "\" stroke-width=\"1.5\" stroke-opacity=\"0.35\" fill=\"none\""
                                     : "\" stroke-width=\"6\"";
    if (link == ground) pts.clear();  // the ground is its pivots and guides
    const std::vector<int> hull = internal::ConvexHull(pts);
    double area = 0;
    for (size_t i = 0; i < hull.size(); ++i) {
      const P2& a = pts[hull[i]];
      const P2& b = pts[hull[(i + 1) % hull.size()]];
      area += a[0] * b[1] - a[1] * b[0];
    }
    if (hull.size() >= 3 && std::abs(area) > 1e-4 * span * span) {
      s += "<polygon points=\"";
      for (int i : hull) s += lp(pts[i]) + " ";
      s += "\" stroke=\"" + std::string(color) +
           (faded ? stroke : "\" stroke-width=\"4\" fill=\"" + std::string(color) + "\" fill-opacity=\"0.25\"") +
           " stroke-linejoin=\"round\"/>\n";
    } else if (pts.size() >= 2) {
      // A bar between its two farthest points.
      size_t ia = 0, ib = 1;
      double best = -1;
      for (size_t i = 0; i < pts.size(); ++i)
        for (size_t k = i + 1; k < pts.size(); ++k) {
          const double d = std::hypot(pts[i][0] - pts[k][0], pts[i][1] - pts[k][1]);
          if (d > best) best = d, ia = i, ib = k;
        }
      s += "<line x1=\"" + L(pts[ia][0]) + "\" y1=\"" + L(-pts[ia][1]) + "\" x2=\"" + L(pts[ib][0]) +
           "\" y2=\"" + L(-pts[ib][1]) + "\" stroke=\"" + color + stroke + " stroke-linecap=\"round\"/>\n";
    }
    if (kDraw) {
      const char* opacity = faded ? "0.35" : "1";
      std::vector<std::array<double, 3>> drawn;  // circles drawn: centre and radius
      auto wheel = [&](const P2& c, double r, bool spokes) {
        for (const auto& d : drawn)
          if (std::hypot(d[0] - c[0], d[1] - c[1]) <= tol && std::abs(d[2] - r) <= tol) return;
        drawn.push_back({c[0], c[1], r});
        if (link == ground) {  // a ring gear or a base circle: the ground's colour, no spokes
          s += "<circle cx=\"" + L(c[0]) + "\" cy=\"" + L(-c[1]) + "\" r=\"" + L(r) +
               "\" fill=\"none\" stroke=\"#555\" stroke-width=\"3\"/>\n";
          return;
        }
        s += "<circle cx=\"" + L(c[0]) + "\" cy=\"" + L(-c[1]) + "\" r=\"" + L(r) + "\" fill=\"" +
             (faded ? std::string("none") : std::string(color)) + "\" fill-opacity=\"0.12\" stroke=\"" + color +
             "\" stroke-width=\"2\" stroke-opacity=\"" + opacity + "\"" +
             (faded ? "" : " stroke-dasharray=\"6 3\"") + "/>\n";
        if (!spokes || faded) return;
        for (int k = 0; k < 3; ++k) {
          const double t = 2 * kPi * k / 3;
          s += "<line x1=\"" + L(c[0]) + "\" y1=\"" + L(-c[1]) + "\" x2=\"" + L(c[0] + r * std::cos(t)) +
               "\" y2=\"" + L(-(c[1] + r * std::sin(t))) + "\" stroke=\"" + color + "\" stroke-width=\"1.5\"/>\n";
        }
      };
      for (int j = 0; j < d.num_draw_joints; ++j) {
        const int kind = d.kind[j], a = d.point_a[j], b = d.point_b[j];
        const int la = d.link_a[j], lb = d.link_b[j], v = d.value[j];
        const std::vector<double>& val = values[f];
        if (kind == internal::kDrawGear || kind == internal::kDrawRack) {
          if (la == link && a >= 0) wheel(to_local(f, link, scene_point(f, a)), val[v], true);
          if (kind == internal::kDrawGear && lb == link && b >= 0)
            wheel(to_local(f, link, scene_point(f, b)), val[v + 1], true);
        } else if (kind == internal::kDrawRoll) {
          if (lb == link && b >= 0) wheel(to_local(f, link, scene_point(f, b)), val[v], true);
          if (la == link && a >= 0) {
            const P2 c = to_local(f, link, scene_point(f, a));
            if (val[v + 1] > 0) {
              wheel(c, val[v + 1], false);
            } else {
              const double t = val[v + 2] - frames[f](2, link), r = 0.6 * span;
              s += "<line x1=\"" + L(c[0] - r * std::cos(t)) + "\" y1=\"" + L(-(c[1] - r * std::sin(t))) +
                   "\" x2=\"" + L(c[0] + r * std::cos(t)) + "\" y2=\"" + L(-(c[1] + r * std::sin(t))) +
                   "\" stroke=\"#555\" stroke-width=\"2\"/>\n";
            }
          }
        } else if (kind == internal::kDrawCam && la == link && !profiles[j].empty() && !faded) {
          s += "<polygon points=\"";
          for (const P2& p : profiles[j]) s += lp(p) + " ";
          s += std::string("\" fill=\"") + (faded ? "none" : color) + "\" fill-opacity=\"0.25\" stroke=\"" + color +
               "\" stroke-width=\"2\" stroke-opacity=\"" + opacity + "\"/>\n";
        } else if (kind == internal::kDrawPrismatic && la == link && a >= 0 && s_hi[j] >= s_lo[j]) {
          // The guide: rails on the ground, a slot in a moving link, as long as the travel.
          const double t = val[v] - frames[f](2, link);
          const P2 g = to_local(f, link, scene_point(f, a));
          const double c = std::cos(t), sn = std::sin(t);
          const double s0 = s_lo[j] - 0.7 * block_len, s1 = s_hi[j] + 0.7 * block_len;
          auto at = [&](double along, double across) -> P2 {
            return {g[0] + along * c - across * sn, g[1] + along * sn + across * c};
          };
          const double h = 0.5 * block_h + 1.5 * px;
          if (link == ground) {
            for (double side : {-1.0, 1.0}) {
              const P2 p0 = at(s0, side * h), p1 = at(s1, side * h);
              const P2 q0 = at(s0, side * (h + 2 * unit)), q1 = at(s1, side * (h + 2 * unit));
              s += "<polygon points=\"" + lp(p0) + " " + lp(p1) + " " + lp(q1) + " " + lp(q0) +
                   "\" fill=\"url(#hatch)\" stroke=\"none\" opacity=\"" + opacity + "\"/>\n";
              s += "<line x1=\"" + L(p0[0]) + "\" y1=\"" + L(-p0[1]) + "\" x2=\"" + L(p1[0]) + "\" y2=\"" +
                   L(-p1[1]) + "\" stroke=\"#333\" stroke-width=\"2\" stroke-opacity=\"" + opacity + "\"/>\n";
            }
          } else {
            const P2 p0 = at(s0, -h), p1 = at(s1, -h), p2 = at(s1, h), p3 = at(s0, h);
            s += "<polygon points=\"" + lp(p0) + " " + lp(p1) + " " + lp(p2) + " " + lp(p3) + "\" fill=\"" +
                 (faded ? "none" : "white") + "\" stroke=\"" + color + "\" stroke-width=\"2\" stroke-opacity=\"" +
                 opacity + "\" stroke-linejoin=\"round\"/>\n";
          }
        } else if (kind == internal::kDrawSlot && la == link && a >= 0 && s_hi[j] >= s_lo[j]) {
          // The slot: a groove from the pin's nearest to its farthest place along the line
          // (round ends: the pin's circle fits at both), the link's colour round a white inside.
          const double t = val[v] - frames[f](2, link);
          const P2 g = to_local(f, link, scene_point(f, a));
          const P2 p0 = {g[0] + s_lo[j] * std::cos(t), g[1] + s_lo[j] * std::sin(t)};
          const P2 p1 = {g[0] + s_hi[j] * std::cos(t), g[1] + s_hi[j] * std::sin(t)};
          const std::string ends = "x1=\"" + L(p0[0]) + "\" y1=\"" + L(-p0[1]) + "\" x2=\"" + L(p1[0]) +
                                   "\" y2=\"" + L(-p1[1]) + "\"";
          s += "<line class=\"slot\" " + ends + " stroke=\"" + color + "\" stroke-width=\"13\" stroke-opacity=\"" +
               opacity + "\" stroke-linecap=\"round\"/>\n";
          if (!faded)
            s += "<line " + ends + " stroke=\"white\" stroke-width=\"10\" stroke-linecap=\"round\"/>\n";
        }
      }
    }
    return s;
  };
  auto riders = [&](size_t f, int link) {
    std::string s;
    if (kDraw) {
      const char* color = kLinkColors[link % 8];
      for (int j = 0; j < d.num_draw_joints; ++j) {
        const int kind = d.kind[j], a = d.point_a[j], b = d.point_b[j];
        const int lb = d.link_b[j], v = d.value[j];
        const std::vector<double>& val = values[f];
        if (kind == internal::kDrawPrismatic && lb == link && b >= 0) {
          const double t = val[v] - frames[f](2, link);
          const P2 p = to_local(f, link, scene_point(f, b));
          const double c = std::cos(t), sn = std::sin(t);
          auto at = [&](double along, double across) -> P2 {
            return {p[0] + along * c - across * sn, p[1] + along * sn + across * c};
          };
          const double hl = 0.5 * block_len, hh = 0.5 * block_h;
          s += "<polygon points=\"" + lp(at(-hl, -hh)) + " " + lp(at(hl, -hh)) + " " + lp(at(hl, hh)) + " " +
               lp(at(-hl, hh)) + "\" fill=\"" + color + "\" fill-opacity=\"0.85\" stroke=\"#222\" "
               "stroke-width=\"1.5\" stroke-linejoin=\"round\"/>\n";
        } else if (kind == internal::kDrawCam && lb == link && b >= 0) {
          const P2 p = to_local(f, link, scene_point(f, b));
          if (val[v] > 0) {
            s += "<circle cx=\"" + L(p[0]) + "\" cy=\"" + L(-p[1]) + "\" r=\"" + L(val[v]) + "\" fill=\"white\" "
                 "stroke=\"" + color + "\" stroke-width=\"2.5\"/>\n";
          } else if (val[v + 1] != 0 || a < 0) {
            const double t = val[v + 1] - frames[f](2, link), r = 0.25 * span;
            s += "<line x1=\"" + L(p[0] - r * std::cos(t)) + "\" y1=\"" + L(-(p[1] - r * std::sin(t))) +
                 "\" x2=\"" + L(p[0] + r * std::cos(t)) + "\" y2=\"" + L(-(p[1] + r * std::sin(t))) +
                 "\" stroke=\"" + color + "\" stroke-width=\"4\" stroke-linecap=\"round\"/>\n";
          }
        } else if (kind == internal::kDrawSlot && lb == link && b >= 0) {
          // The pin, free to turn in the slot (on the pin's link; the slot is on the other).
          const P2 p = to_local(f, link, scene_point(f, b));
          s += "<circle class=\"slot-pin\" cx=\"" + L(p[0]) + "\" cy=\"" + L(-p[1]) + "\" r=\"4\" fill=\"white\" "
               "stroke=\"#222\" stroke-width=\"1.5\"/>\n";
        } else if (kind == internal::kDrawRevolute && lb == link && b >= 0) {
          const P2 p = to_local(f, link, scene_point(f, b));
          s += "<circle cx=\"" + L(p[0]) + "\" cy=\"" + L(-p[1]) + "\" r=\"4\" fill=\"white\" stroke=\"#222\" "
               "stroke-width=\"1.5\"/>\n";
        }
      }
    }
    (void)f, (void)link;
    return s;
  };
  // A link's placement at configuration f as an SVG transform, and its values for animation.
  auto translate = [&](size_t f, int l) { return X(frames[f](0, l)) + " " + Y(frames[f](1, l)); };
  auto rotate = [&](size_t f, int l) { return internal::FormatNumber(-frames[f](2, l) * 180 / kPi, "%.3f"); };
  auto open_group = [&](size_t f, int l, const std::string& extra) {
    return "<g data-link=\"" + std::string(d.link_names[l]) + "\" transform=\"translate(" + translate(f, l) +
           ") rotate(" + rotate(f, l) + ")\"" + extra + ">\n";
  };

  // ---- Faded snapshots.
  if (d.has_scene) {
    const int snapshots = std::min<int>(options.snapshots, static_cast<int>(nv));
    out << "<g id=\"snapshots\">\n";
    for (int k = 0; k < snapshots; ++k) {
      const size_t f = nv * static_cast<size_t>(k) / static_cast<size_t>(snapshots);
      for (int l = 0; l < kLinks; ++l) {
        if (l == ground) continue;
        const std::string b = body(f, l, true);
        if (!b.empty()) out << open_group(f, l, "") << b << "</g>\n";
      }
    }
    out << "</g>\n";
  }
  // ---- Traced paths of the requested points.
  if (d.has_points) {
    out << "<g id=\"paths\">\n";
    for (int p = 0; p < d.num_points; ++p) {
      out << "<polyline fill=\"none\" stroke=\"" << kPathColors[p % 6] << "\" stroke-width=\"2\" points=\"";
      for (const Record<M>* r : valid) out << X(r->state.r_P(0, p)) << ',' << Y(r->state.r_P(1, p)) << ' ';
      out << "\"><title>" << d.point_names[p] << "</title></polyline>\n";
    }
    out << "</g>\n";
  }
  if (d.has_scene) {
    if (nv > 0) {
      // ---- The ground: its body (rails, base lines and circles), then a hatched pivot under
      // each of its revolute joints.
      out << "<g id=\"ground\">\n" << open_group(0, ground, "") << body(0, ground, false) << "</g>\n";
      std::vector<int> pivots;
      if (kDraw) {
        for (int j = 0; j < d.num_draw_joints; ++j) {
          if (d.kind[j] != internal::kDrawRevolute) continue;
          const int la = d.link_a[j], lb = d.link_b[j];
          const int s = la == ground ? d.point_a[j] : lb == ground ? d.point_b[j] : -1;
          if (s >= 0 && std::find(pivots.begin(), pivots.end(), s) == pivots.end()) pivots.push_back(s);
        }
      } else {
        for (int s = 0; s < d.num_scene_points; ++s)
          if (d.scene_point_link[s] == ground) pivots.push_back(s);
      }
      for (int s : pivots) {
        const P2 c = scene_point(0, s);
        const double u = 9 * px, h = 14 * px;  // pixels
        out << "<polygon points=\"" << X(c[0]) << ',' << Y(c[1]) << ' ' << X(c[0] - u) << ',' << Y(c[1] - h) << ' '
            << X(c[0] + u) << ',' << Y(c[1] - h) << "\" fill=\"#ddd\" stroke=\"#333\" stroke-width=\"1.5\"/>\n";
        out << "<rect x=\"" << X(c[0] - 1.6 * u) << "\" y=\"" << Y(c[1] - h) << "\" width=\"" << num(3.2 * u * scale)
            << "\" height=\"7\" fill=\"url(#hatch)\"/><line x1=\"" << X(c[0] - 1.6 * u) << "\" y1=\"" << Y(c[1] - h)
            << "\" x2=\"" << X(c[0] + 1.6 * u) << "\" y2=\"" << Y(c[1] - h) << "\" stroke=\"#333\" stroke-width=\"2\"/>\n";
        out << "<text x=\"" << X(c[0]) << "\" y=\"" << Y(c[1] - h - 17 * px)
            << "\" text-anchor=\"middle\" font-family=\"sans-serif\" font-size=\"11\" fill=\"#333\">"
            << internal::ShortName(d.scene_point_names[s]) << "</text>\n";
      }
      out << "</g>\n";

      // ---- The mechanism at the first configuration, each moving link animated through the
      // sweep (translate and rotate of its frame) when asked.
      const bool animate = kDraw && options.animate && nv > 1;
      std::vector<std::string> anim(static_cast<size_t>(kLinks));
      if (animate) {
        const size_t frames_n = std::min<size_t>(nv, static_cast<size_t>(std::max(options.max_frames, 2)));
        for (int l = 0; l < kLinks; ++l) {
          if (l == ground) continue;
          std::string tv, rv;
          for (size_t k = 0; k < frames_n; ++k) {
            const size_t f = (nv - 1) * k / (frames_n - 1);
            tv += (k ? ";" : "") + translate(f, l);
            rv += (k ? ";" : "") + rotate(f, l);
          }
          const std::string dur = internal::FormatNumber(options.seconds, "%g") + "s";
          anim[l] = "<animateTransform attributeName=\"transform\" type=\"translate\" dur=\"" + dur +
                    "\" repeatCount=\"indefinite\" values=\"" + tv + "\"/><animateTransform attributeName=\"transform\" "
                    "type=\"rotate\" additive=\"sum\" dur=\"" + dur + "\" repeatCount=\"indefinite\" values=\"" + rv +
                    "\"/>\n";
        }
      }
      // Links with a slot (a prismatic guide or a slot joint) first: its white inside must not
  // hide the links that cross it.
      std::vector<int> order;
      for (int pass = 0; pass < 2; ++pass)
        for (int l = 0; l < kLinks; ++l) {
          bool slotted = false;
          for (int j = 0; j < d.num_draw_joints; ++j)
            slotted = slotted || (internal::SlidesOnLine(d.kind[j]) && d.link_a[j] == l);
          if (slotted == (pass == 0)) order.push_back(l);
        }
      out << "<g id=\"mechanism\">\n";
      for (int layer = 0; layer < 2; ++layer)
        for (int l : order) {
          if (l == ground && layer == 0) continue;
          const std::string s = layer == 0 ? body(0, l, false) : riders(0, l);
          if (s.empty()) continue;
          if (l == ground) {
            out << open_group(0, l, "") << s << "</g>\n";
          } else {
            out << open_group(0, l, layer == 0 ? " class=\"link\"" : "") << anim[l] << s << "</g>\n";
          }
        }
      out << "</g>\n";
      // ---- Dots running along the paths (a static renderer shows them at the first row).
      if (d.has_points) {
        for (int p = 0; p < d.num_points; ++p) {
          out << "<circle cx=\"" << X(valid[0]->state.r_P(0, p)) << "\" cy=\"" << Y(valid[0]->state.r_P(1, p))
              << "\" r=\"5\" fill=\"" << kPathColors[p % 6] << "\" stroke=\"white\" stroke-width=\"1\">";
          if (options.animate && nv > 1) {
            const size_t frames_n = std::min<size_t>(nv, static_cast<size_t>(std::max(options.max_frames, 2)));
            std::string xs, ys;
            for (size_t k = 0; k < frames_n; ++k) {
              const size_t f = (nv - 1) * k / (frames_n - 1);
              xs += (k ? ";" : "") + X(valid[f]->state.r_P(0, p));
              ys += (k ? ";" : "") + Y(valid[f]->state.r_P(1, p));
            }
            out << "<animate attributeName=\"cx\" dur=\"" << options.seconds
                << "s\" repeatCount=\"indefinite\" values=\"" << xs << "\"/><animate attributeName=\"cy\" dur=\""
                << options.seconds << "s\" repeatCount=\"indefinite\" values=\"" << ys << "\"/>";
          }
          out << "</circle>\n";
        }
      }
    }
  }
  // ---- Legend: the traced paths' colours and names (top right).
  if (d.has_points) {
    if (d.num_points > 0) {
      const int w = 190, row = 18;
      const int x0 = options.width - w - 8, y0 = 8;
      out << "<g id=\"legend\" font-family=\"sans-serif\" font-size=\"12\"><rect x=\"" << x0 << "\" y=\"" << y0
          << "\" width=\"" << w << "\" height=\"" << row * d.num_points + 10
          << "\" fill=\"white\" fill-opacity=\"0.85\" stroke=\"#bbb\"/>\n";
      for (int p = 0; p < d.num_points; ++p) {
        const int y = y0 + 14 + row * p;
        out << "<line x1=\"" << x0 + 8 << "\" y1=\"" << y << "\" x2=\"" << x0 + 34 << "\" y2=\"" << y
            << "\" stroke=\"" << kPathColors[p % 6] << "\" stroke-width=\"3\"/><text x=\"" << x0 + 42 << "\" y=\""
            << y + 4 << "\">path of " << d.point_names[p] << "</text>\n";
      }
      out << "</g>\n";
    }
  }
  if (options.overlay) {
    SvgFrame frame;
    frame.x_min = x_min;
    frame.y_max = y_max;
    frame.scale = scale;
    frame.span = span;
    const size_t snapshots = std::min<size_t>(static_cast<size_t>(std::max(options.snapshots, 0)), nv);
    for (size_t k = 0; k < snapshots; ++k)
      frame.snapshots.push_back(static_cast<size_t>(valid[nv * k / snapshots] - records.data()));
    options.overlay(frame, out);
  }
  out << "</svg>\n";
}

/// WriteSvg of a generated model M (an empty tag: its constants and functions are static).
template <class M, template <class> class Record>
void WriteSvg(const typename ModelTypes<M>::Params& params, const std::vector<Record<M>>& records,
              const SvgOptions& options, std::ostream& out) {
  WriteSvg(M(), params, records, options, out);
}

}  // namespace mechgen
