/**
 * \file synthesis/output.h
 * What path synthesis hands back (issue 28): the synthesized mechanism as an ordinary model
 * file (the input model's text with the new parameter values written in place of the old
 * ones, %.17g: comments, layout and every other line unchanged, so every analysis of the
 * project works on it), an SVG of the coupler curve against the targets, and a short text
 * report (error per target, the defect checks, the transmission-angle range).
 */
#pragma once

#include <algorithm>
#include <array>
#include <cstdio>
#include <string>
#include <vector>

#include <yaml-cpp/yaml.h>

#include "mechgen/synthesis/path.h"

namespace mechgen::synthesis {

inline std::string Num(double v) {
  char buffer[40];
  std::snprintf(buffer, sizeof(buffer), "%.17g", v);
  return buffer;
}

inline std::string Short(double v, int digits = 6) {
  char buffer[40];
  std::snprintf(buffer, sizeof(buffer), "%.*g", digits, v);
  return buffer;
}

/// The model text with each (name, value) written into its `parameters:` entry (`name: v` or
/// `name: {value: v, ...}`). false and *error if an entry is not a plain one-line scalar.
inline bool RewriteParameters(const std::string& model_text, const std::vector<std::string>& names,
                              const std::vector<double>& values, std::string* out, std::string* error) {
  YAML::Node root;
  try {
    root = YAML::Load(model_text);
  } catch (const YAML::Exception& e) {
    return *error = "the model is not valid YAML: " + e.msg, false;
  }
  const YAML::Node params = root["parameters"];
  if (!params || !params.IsMap()) return *error = "the model has no `parameters:` mapping", false;
  struct Edit {
    size_t pos, length;
    std::string text;
  };
  std::vector<Edit> edits;
  for (size_t k = 0; k < names.size(); ++k) {
    YAML::Node entry = params[names[k]];
    if (!entry) return *error = "the model has no parameter '" + names[k] + "'", false;
    YAML::Node value = entry.IsMap() ? entry["value"] : entry;
    if (!value || !value.IsScalar()) return *error = "parameter '" + names[k] + "' has no scalar value", false;
    const size_t pos = static_cast<size_t>(value.Mark().pos);
    const std::string& s = value.Scalar();
    if (pos + s.size() > model_text.size() || model_text.compare(pos, s.size(), s) != 0)
      return *error = "parameter '" + names[k] + "': its value is not written as a plain scalar (quoted or "
                      "multi-line); write it as a number",
             false;
    edits.push_back({pos, s.size(), Num(values[k])});
  }
  std::sort(edits.begin(), edits.end(), [](const Edit& a, const Edit& b) { return a.pos > b.pos; });
  *out = model_text;
  for (const Edit& e : edits) out->replace(e.pos, e.length, e.text);
  return true;
}

/// The coupler curve (the full turn, broken where it does not assemble), the targets (circles)
/// and the synthesized points (crosses, joined to their targets), in an SVG of width 640.
template <class M>
std::string CurveSvg(PathEvaluator<M>* eval, const Candidate& c, int samples = 720) {
  const BoundPath<M>& b = eval->bound();
  const auto p = eval->ParamsOf(c.x);
  typename PathEvaluator<M>::VecPhi phi;
  typename PathEvaluator<M>::Coeffs co;
  std::vector<std::vector<std::array<double, 2>>> pieces(1);
  double xmin = kInf, xmax = -kInf, ymin = kInf, ymax = -kInf;
  auto grow = [&](double x, double y) {
    xmin = std::min(xmin, x), xmax = std::max(xmax, x), ymin = std::min(ymin, y), ymax = std::max(ymax, y);
  };
  for (int k = 0; k <= samples; ++k) {
    if (!eval->PointAt(p, c.q[0] + kTwoPi * k / samples, &phi, &co)) {
      if (!pieces.back().empty()) pieces.emplace_back();
      continue;
    }
    pieces.back().push_back({co.r_P(0, b.point), co.r_P(1, b.point)});
    grow(co.r_P(0, b.point), co.r_P(1, b.point));
  }
  std::vector<std::array<double, 2>> reached;
  for (int i = 0; i < b.n; ++i) {
    grow(b.task.tx[static_cast<size_t>(i)], b.task.ty[static_cast<size_t>(i)]);
    if (eval->PointAt(p, c.q[static_cast<size_t>(i)], &phi, &co)) reached.push_back({co.r_P(0, b.point), co.r_P(1, b.point)});
    else reached.push_back({b.task.tx[static_cast<size_t>(i)], b.task.ty[static_cast<size_t>(i)]});
  }
  const double span = std::max({xmax - xmin, ymax - ymin, 1e-9});
  const double size = 600, margin = 20, scale = size / span;
  const double height = (ymax - ymin) * scale + 2 * margin;
  auto X = [&](double x) { return Short(margin + (x - xmin) * scale, 7); };
  auto Y = [&](double y) { return Short(margin + (ymax - y) * scale, 7); };
  std::string svg = "<svg xmlns=\"http://www.w3.org/2000/svg\" width=\"" + Short(size + 2 * margin) + "\" height=\"" +
                    Short(height) + "\">\n<title>" + std::string(M::kName) + ": " + b.task.point +
                    " (curve) against the targets (circles), synthesized points (crosses)</title>\n";
  svg += "<rect width=\"100%\" height=\"100%\" fill=\"white\"/>\n";
  for (const auto& piece : pieces) {
    if (piece.size() < 2) continue;
    svg += "<polyline fill=\"none\" stroke=\"#1f5fa8\" stroke-width=\"1.5\" points=\"";
    for (const auto& pt : piece) svg += X(pt[0]) + "," + Y(pt[1]) + " ";
    svg += "\"/>\n";
  }
  for (int i = 0; i < b.n; ++i) {
    const double tx = b.task.tx[static_cast<size_t>(i)], ty = b.task.ty[static_cast<size_t>(i)];
    const auto& r = reached[static_cast<size_t>(i)];
    svg += "<circle cx=\"" + X(tx) + "\" cy=\"" + Y(ty) + "\" r=\"5\" fill=\"none\" stroke=\"#c0392b\" stroke-width=\"1.5\"/>\n";
    svg += "<line x1=\"" + X(tx) + "\" y1=\"" + Y(ty) + "\" x2=\"" + X(r[0]) + "\" y2=\"" + Y(r[1]) +
           "\" stroke=\"#c0392b\"/>\n";
    svg += "<path d=\"M" + X(r[0]) + " " + Y(r[1]) + " m-4 -4 l8 8 m0 -8 l-8 8\" stroke=\"black\"/>\n";
    svg += "<text x=\"" + X(tx) + "\" y=\"" + Y(ty) + "\" dx=\"7\" dy=\"-7\" font-size=\"12\" font-family=\"sans-serif\">" +
           std::to_string(i + 1) + "</text>\n";
  }
  svg += "</svg>\n";
  return svg;
}

}  // namespace mechgen::synthesis
