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
#include <cmath>
#include <cstdio>
#include <string>
#include <utility>
#include <vector>

#include <yaml-cpp/yaml.h>

#include "mechgen/core/linear_algebra.h"
#include "mechgen/position/solver.h"
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

namespace output_internal {

/// A change of the model's text: [pos, pos + length) replaced by text.
struct Edit {
  size_t pos, length;
  std::string text;
};

/// The length of a scalar's text at its mark when it is written on one line: plain (the
/// scalar itself), 'single' or "double" quoted (to the closing quote); false otherwise.
inline bool ScalarLength(const std::string& text, const YAML::Node& value, size_t* length) {
  if (!value.IsScalar() || value.Mark().pos < 0) return false;
  const size_t pos = static_cast<size_t>(value.Mark().pos);
  if (pos >= text.size()) return false;
  const char quote = text[pos];
  if (quote == '"' || quote == '\'') {
    for (size_t k = pos + 1; k < text.size() && text[k] != '\n'; ++k) {
      if (quote == '"' && text[k] == '\\') {
        ++k;
      } else if (text[k] == quote) {
        if (quote == '\'' && k + 1 < text.size() && text[k + 1] == '\'') {
          ++k;
          continue;
        }
        *length = k + 1 - pos;
        return true;
      }
    }
    return false;
  }
  const std::string& s = value.Scalar();
  if (pos + s.size() > text.size() || text.compare(pos, s.size(), s) != 0) return false;
  *length = s.size();
  return true;
}

/// The edits that give the mapping `map` each (key, value): an existing key's scalar value
/// replaced, the missing keys inserted as one run (a block mapping: on lines of their own
/// before its first key, at its column; a flow mapping: after its '{'). `what` names the
/// mapping in a message.
inline bool SetEntries(const std::string& text, const YAML::Node& map,
                       const std::vector<std::pair<std::string, std::string>>& entries, const std::string& what,
                       std::vector<Edit>* edits, std::string* error) {
  if (!map.IsMap() || map.size() == 0 || map.Mark().pos < 0)
    return *error = what + " is not a mapping with entries", false;
  std::string inserted;
  std::vector<std::string> added;
  for (const auto& [key, value] : entries) {
    if (const YAML::Node v = map[key]) {
      size_t length = 0;
      if (!ScalarLength(text, v, &length))
        return *error = what + " '" + key + "': its value is not one scalar on one line; write it as a number", false;
      edits->push_back({static_cast<size_t>(v.Mark().pos), length, value});
    } else {
      added.push_back(key + ": " + value);
    }
  }
  if (added.empty()) return true;
  if (map.Style() == YAML::EmitterStyle::Flow) {
    const size_t pos = static_cast<size_t>(map.Mark().pos);
    if (pos >= text.size() || text[pos] != '{') return *error = what + ": its '{' is not where YAML says", false;
    for (const std::string& a : added) inserted += a + ", ";
    edits->push_back({pos + 1, 0, inserted});
  } else {
    const YAML::Mark first = map.begin()->first.Mark();
    if (first.pos < 0 || first.column < 0) return *error = what + ": its first key has no place", false;
    for (const std::string& a : added) inserted += a + "\n" + std::string(static_cast<size_t>(first.column), ' ');
    edits->push_back({static_cast<size_t>(first.pos), 0, inserted});
  }
  return true;
}

/// The edits writing (name, value) into each `parameters:` entry (`name: v` or `name: {value:
/// v, ...}`); false and *error if an entry is missing or not a plain one-line scalar.
inline bool ParameterEdits(const std::string& model_text, const YAML::Node& root, const std::vector<std::string>& names,
                           const std::vector<double>& values, std::vector<Edit>* edits, std::string* error) {
  const YAML::Node params = root["parameters"];
  if (!params || !params.IsMap()) return *error = "the model has no `parameters:` mapping", false;
  for (size_t k = 0; k < names.size(); ++k) {
    const YAML::Node entry = params[names[k]];
    if (!entry) return *error = "the model has no parameter '" + names[k] + "'", false;
    const YAML::Node value = entry.IsMap() ? entry["value"] : entry;
    size_t length = 0;
    if (!value || !ScalarLength(model_text, value, &length))
      return *error = "parameter '" + names[k] + "': its value is not written as a scalar on one line; write it as a "
                      "number",
             false;
    edits->push_back({static_cast<size_t>(value.Mark().pos), length, Num(values[k])});
  }
  return true;
}

/// model_text with the edits made (they must not overlap; false if they do).
inline bool Apply(const std::string& model_text, std::vector<Edit> edits, std::string* out) {
  std::stable_sort(edits.begin(), edits.end(), [](const Edit& a, const Edit& b) { return a.pos > b.pos; });
  for (size_t k = 1; k < edits.size(); ++k)
    if (edits[k].pos + edits[k].length > edits[k - 1].pos) return false;
  *out = model_text;
  for (const Edit& e : edits) out->replace(e.pos, e.length, e.text);
  return true;
}

}  // namespace output_internal

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
  std::vector<output_internal::Edit> edits;
  if (!output_internal::ParameterEdits(model_text, root, names, values, &edits, error)) return false;
  if (!output_internal::Apply(model_text, edits, out)) return *error = "two parameters share one value's text", false;
  return true;
}

/// What the synthesized model file says besides its parameters (WriteSynthesizedModel).
struct WrittenAssembly {
  double q = 0;                 ///< `assembly:` the input: the first target's, on the input's range
  std::vector<double> phi;      ///< `assembly:` each dependent coordinate there (angles in (-pi, pi])
  int branch = 0;               ///< sign det Phi_phi there: the branch the synthesis used
  std::vector<std::string> set;  ///< parameters written besides `names` (their values differ from the model's)
  bool range_written = false;   ///< the input's range narrowed to the motion (the model's own is not swept through)
  double range_lo = 0, range_hi = 0;  ///< the input's range in the written model
  std::string continuation;     ///< "" when the runtime's continuation sweeps that range, else why not
};

/// The synthesized model file: the input model's text with
///  - `parameters:` every name of `names` and every other parameter whose value in p differs
///    from the model's (those set by --set or --params: the search used them) at p's values;
///  - `assembly:` the configuration the synthesis used at its first target: the input
///    motion[0] (a revolute input moved by whole turns onto its range's first turn) and every
///    dependent coordinate as M::Solve gives it on the model's assembly mode (kDefaultModes)
///    there. The generator picks the mode whose root is nearest these values, and the sweep
///    assembles on the branch (sign det Phi_phi) they have, so that both reproduce the
///    synthesized linkage (the original hints may pick the other mode of the new lengths, or
///    an input where it does not assemble);
///  - the input's `range:` narrowed to the motion [min, max of `motion`] when the runtime's
///    continuation (PositionSolver: assembled there, moved to the range's start, then through
///    it in steps of at most 1 deg, as the sweep does) cannot sweep the model's own range (a
///    crank that does not turn fully: the generator refuses a range the loop cannot close
///    over).
/// `motion`: the input at each target in the order the mechanism moves through them, each one
/// reached from the one before directly (the unwrapped angles). Comments, layout and every
/// other line stay. false and *error when the text cannot be edited or the mechanism does not
/// assemble at motion[0]. `modes`: the assembly mode the synthesis used when it is not the
/// model's (exact synthesis: a solution on the mirror mode); the hints written are that mode's
/// configuration, so the generator picks it as the written model's mode (nullptr: kDefaultModes).
/// The model is reached through ModelCalls<M> (a generated model, or the model view); it has
/// one input.
template <class M>
bool WriteSynthesizedModel(const M& model, const std::string& model_text, const typename ModelTypes<M>::Params& p,
                           const std::vector<std::string>& names, const std::vector<double>& motion, std::string* out,
                           WrittenAssembly* written, std::string* error,
                           const typename ModelCalls<M>::Modes* modes = nullptr) {
  using C = ModelCalls<M>;
  using Params = typename ModelTypes<M>::Params;
  using VecQ = typename ModelTypes<M>::VecQ;
  using VecPhi = typename ModelTypes<M>::VecPhi;
  static_assert(ModelTypes<M>::kNq == 1 || ModelTypes<M>::kNq == Eigen::Dynamic, "synthesis writes one-input models");
  YAML::Node root;
  try {
    root = YAML::Load(model_text);
  } catch (const YAML::Exception& e) {
    return *error = "the model is not valid YAML: " + e.msg, false;
  }
  if (!root.IsMap() || motion.empty()) return *error = "the model is not a mapping", false;
  WrittenAssembly w;
  // The parameters: the given names, then every other one that differs from the model's.
  std::vector<std::string> write = names;
  std::vector<double> values;
  {
    Params value = p, defaults = C::DefaultParams(model);
    for (int i = 0; i < C::NumFreeParameters(model); ++i) {
      const char* n = C::FreeParameterName(model, i);
      if (std::find(names.begin(), names.end(), n) != names.end()) continue;
      if (*C::FindParameter(model, &value, n) != *C::FindParameter(model, &defaults, n))
        write.push_back(n), w.set.push_back(n);
    }
    for (const std::string& n : write) values.push_back(*C::FindParameter(model, &value, n.c_str()));
  }
  std::vector<output_internal::Edit> edits;
  if (!output_internal::ParameterEdits(model_text, root, write, values, &edits, error)) return false;
  // The motion's input, moved by whole turns so that its start lies in [kQMin, kQMin + 2 pi).
  double q0 = motion[0], lo = *std::min_element(motion.begin(), motion.end()),
         hi = *std::max_element(motion.begin(), motion.end());
  if (C::QIsAngle(model, 0)) {
    const double shift = kTwoPi * std::floor((lo - C::QMin(model)[0]) / kTwoPi);
    q0 -= shift, lo -= shift, hi -= shift;
  }
  VecQ q;
  q.resize(1);
  q(0) = q0;
  VecPhi phi;
  if (!SolveOnMode(model, p, q0, &phi, /*judge=*/true, modes))
    return *error = "the synthesized mechanism does not assemble on its mode at its first target", false;
  for (int i = 0; i < C::Nphi(model); ++i)
    if (C::PhiIsAngle(model, i)) phi(i) = std::remainder(phi(i), kTwoPi);
  {
    typename ModelTypes<M>::MatCPhi Phi_phi;
    C::Phi(model, p, q, phi, nullptr, &Phi_phi, nullptr);
    double cond = 0, det = 0;
    ConditionAndDeterminant(Phi_phi, &cond, &det);
    w.branch = det > 0 ? 1 : det < 0 ? -1 : 0;
  }
  w.q = q0;
  w.phi.assign(phi.data(), phi.data() + C::Nphi(model));
  // The sweep's way through a range [a, b]: assembled at the hints on their branch, moved to a,
  // then to b in steps of at most 1 deg (model units: 1/360 of the range).
  auto sweeps = [&](double a, double b, std::string* why) {
    position::PositionSolver<M> solver(model, position::Options(), p);
    if (solver.Assemble(q, phi, w.branch, nullptr) != position::Status::kConverged)
      return *why = "the runtime cannot assemble at the first target", false;
    VecQ qa;
    qa.resize(1);
    qa(0) = a;
    if (solver.MoveTo(qa, nullptr) != position::Status::kConverged)
      return *why = "the continuation stops between the first target and the range's start", false;
    const double step = C::QIsAngle(model, 0) ? kTwoPi / 360 : (b - a) / 360;
    const int steps = std::max(1, static_cast<int>(std::ceil((b - a) / std::max(step, 1e-300))));
    for (int s = 1; s <= steps; ++s) {
      qa(0) = a + (b - a) * s / steps;
      if (solver.MoveTo(qa, nullptr) != position::Status::kConverged)
        return *why = "the continuation stops at input " + Short(qa(0)) + " (a dead point)", false;
    }
    return true;
  };
  std::string why;
  w.range_lo = C::QMin(model)[0], w.range_hi = C::QMax(model)[0];
  if (!sweeps(w.range_lo, w.range_hi, &why)) {
    w.range_written = true;
    w.range_lo = lo, w.range_hi = hi;
    if (!sweeps(lo, hi, &w.continuation)) w.continuation = "over the motion through the targets: " + w.continuation;
  }
  // The `assembly:` hints.
  std::vector<std::pair<std::string, std::string>> hints;
  hints.emplace_back(C::QName(model, 0), Num(q0));
  for (int i = 0; i < C::Nphi(model); ++i) hints.emplace_back(C::PhiName(model, i), Num(phi(i)));
  if (const YAML::Node assembly = root["assembly"]) {
    if (!output_internal::SetEntries(model_text, assembly, hints, "the model's assembly:", &edits, error)) return false;
  } else {
    std::string text = (model_text.empty() || model_text.back() == '\n' ? "" : "\n") + std::string("assembly:\n");
    for (const auto& [key, value] : hints) text += "  " + key + ": " + value + "\n";
    edits.push_back({model_text.size(), 0, text});
  }
  // The input's range.
  if (w.range_written) {
    const YAML::Node inputs = root["inputs"];
    if (!inputs || !inputs.IsSequence() || inputs.size() != 1 || !inputs[0].IsMap())
      return *error = "the model's inputs: is not one mapping to narrow its range in", false;
    const YAML::Node range = inputs[0]["range"];
    if (range) {
      size_t l0 = 0, l1 = 0;
      if (!range.IsSequence() || range.size() != 2 || !output_internal::ScalarLength(model_text, range[0], &l0) ||
          !output_internal::ScalarLength(model_text, range[1], &l1))
        return *error = "the input's range: is not [min, max] on one line", false;
      edits.push_back({static_cast<size_t>(range[0].Mark().pos), l0, Num(lo)});
      edits.push_back({static_cast<size_t>(range[1].Mark().pos), l1, Num(hi)});
    } else if (!output_internal::SetEntries(model_text, inputs[0], {{"range", "[" + Num(lo) + ", " + Num(hi) + "]"}},
                                            "the model's input", &edits, error)) {
      return false;
    }
  }
  if (!output_internal::Apply(model_text, edits, out))
    return *error = "the model's text cannot be edited in place (two edits overlap)", false;
  *written = w;
  return true;
}
/// The same on a generated model's type (default-constructed: its functions are static).
template <class M>
bool WriteSynthesizedModel(const std::string& model_text, const typename M::template ParamsT<double>& p,
                           const std::vector<std::string>& names, const std::vector<double>& motion, std::string* out,
                           WrittenAssembly* written, std::string* error,
                           const std::array<int, M::kNumBlocks>* modes = nullptr) {
  return WriteSynthesizedModel(M(), model_text, p, names, motion, out, written, error, modes);
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
                    Short(height) + "\">\n<title>" + std::string(ModelCalls<M>::Name(eval->model())) + ": " + b.task.point +
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
