// libFuzzer target: a model file through the generator's front end (targets.h, FuzzModel).
//
// Each input is written to a temporary file (LoadModel reads a path) and run through
// LoadModel (YAML syntax, names, references, expressions), Validate (loops, mobility, cams,
// ...), DeriveKinematics, the symbolic table (Phi, Phi_phi, Phi_q, K, L, the blocks and
// their closed forms) and the function builders with CSE. Emission (templates) is not
// fuzzed: it only formats what the builders produced.
//
// Structure-aware mutations (LLVMFuzzerCustomMutator): a model file is YAML, one entry a
// line, so besides libFuzzer's byte mutations (with the model-aware dictionary yaml.dict)
// half of the mutations work on lines and tokens, keeping the file's indentation:
//   - a number is replaced by an interesting one (0, -1, a tiny or huge magnitude, a
//     multiple of pi, a value equal to another number of the file: coincident points,
//     equal lengths, change points);
//   - a word is replaced by another word of the file (a link, point or joint name) or by
//     a key, joint kind, cam law or function of the model language;
//   - a line is duplicated, deleted, or swapped with another;
//   - a line of a joint, cam, gear, rack, rolling contact, load, spring or input from a
//     built-in list is inserted (indented as its neighbour), so the fuzzer reaches the
//     higher pairs' and the statics' code from models that have none.
#include <algorithm>
#include <cctype>
#include <cstring>
#include <string>
#include <vector>

#include "targets.h"

extern "C" size_t LLVMFuzzerMutate(uint8_t* data, size_t size, size_t max_size);

namespace {

class Random {
 public:
  explicit Random(unsigned seed) : state_(seed * 2654435761u + 1) {}
  unsigned Next() {
    state_ ^= state_ << 13;
    state_ ^= state_ >> 17;
    state_ ^= state_ << 5;
    return state_;
  }
  size_t Below(size_t n) { return n == 0 ? 0 : Next() % n; }

 private:
  unsigned state_;
};

const char* const kNumbers[] = {"0",      "-1",     "1",         "1e-300",    "1e300",     "-0",
                                "1e-100", "1e100",  "0.5",       "2",         "3.5",       "180*deg",
                                "90*deg", "360*deg", "-90*deg",  "Pi",        "1/0",       "0/0",
                                "nan",    ".inf",    "-.inf",    "1e400",     "4.0000000000000001",
                                "2^1000", "sqrt(-1)", "a - a",   "exp(1000)", "1e-308"};

const char* const kWords[] = {
    // keys
    "name", "title", "description", "parameters", "value", "doc", "links", "ground", "points", "joints",
    "inputs", "joint", "range", "outputs", "order", "scene", "quantities", "reactions", "assembly", "mass",
    "center", "inertia", "point_masses", "gravity", "loads", "springs", "friction", "force", "torque", "at", "frame",
    "between", "stiffness", "free_length", "free_angle", "preload", "coefficient", "pin_radius",
    "viscous", "torsional", "derived", "assembly_modes",
    // joint kinds and their keys
    "revolute", "prismatic", "gear", "rack", "cam", "roll", "guide", "slider", "angle", "relative_angle",
    "gears", "radii", "carrier", "internal", "phase", "pinion", "radius", "slide", "wheel", "on",
    "line_angle", "on_radius", "inside", "follower", "point", "start", "law", "roller", "face", "contour",
    "x", "y", "period", "u", "slot", "pin", "through",
    // cam laws
    "dwell", "rise", "return", "lift", "motion", "cycloidal", "harmonic", "poly345",
    // quantities
    "K", "L", "forces", "potential",
    // expression functions and names
    "sin", "cos", "tan", "asin", "acos", "atan", "atan2", "sqrt", "exp", "log", "abs", "deg", "Pi",
    "step", "sign", "min", "max", "clamp", "mod",
    // hostile names
    "class", "std", "M_PI", "_x", "p", "T", "true", "false", "null", "~"};

const char* const kLines[] = {
    "J: {slot: {slot: rocker.D, pin: crank.B, angle: 0}}",
    "J: {slot: {slot: rocker.D, through: rocker.C, pin: crank.B}}",
    "B: {revolute: [crank.B, coupler.B, rocker.C]}",
    "c: {derived: \"sqrt(a^2 + b^2)\"}",
    "assembly_modes: {open: {}, crossed: {theta_coupler: -60*deg}}",
    "G: {gear: {gears: [crank, rocker], radii: [1, 2]}}",
    "G: {gear: {gears: [crank, ground], radii: [1, 3], internal: true}}",
    "G: {gear: {gears: [crank, coupler], radii: [r, r], carrier: rocker, phase: 0.1}}",
    "R: {rack: {pinion: crank, radius: 0.5, slide: S}}",
    "S: {prismatic: {guide: ground.A, slider: coupler.B, angle: 0.001*deg}}",
    "S: {prismatic: {guide: rocker.D, slider: coupler.C, angle: 30*deg, relative_angle: 0}}",
    "W: {roll: {wheel: crank.B, radius: 0.5, on: ground.A, line_angle: 0}}",
    "W: {roll: {wheel: crank.B, radius: 0.5, on: ground.A, on_radius: 2, inside: true}}",
    "C: {cam: {cam: crank, follower: S, point: coupler.B, start: 1, roller: 0.2, "
    "law: [{rise: 120*deg, lift: 1, motion: cycloidal}, {dwell: 60*deg}, {return: 180*deg, lift: 1, "
    "motion: harmonic}]}}",
    "C: {cam: {cam: crank, follower: D, point: rocker.C, start: 0.2, face: 0, "
    "law: [{rise: 180*deg, lift: 0.3, motion: poly345}, {return: 180*deg, lift: 0.3, motion: poly345}]}}",
    "C: {cam: {cam: crank, follower: S, point: coupler.B, roller: 0.1, contour: {x: 2*cos(u), y: sin(u), "
    "period: 2*Pi}}}",
    "C: {cam: {cam: crank, follower: S, point: coupler.B, contour: {points: [[1, 0], [0, 1], [-1, 0], [0, -1]]}}}",
    "- {joint: A, range: [0, 360*deg]}",
    "- {joint: S, range: [-1, 1]}",
    "- {rise: 90*deg, lift: 2, motion: cycloidal}",
    "- {dwell: 90*deg}",
    "crank:  {points: {A: [0, 0], B: [a, 0]}, mass: 1, center: [a/2, 0], inertia: 0.1}",
    "crank:  {points: {A: [0, 0], B: [a, 0]}, point_masses: {h: {at: B, mass: 1, inertia: 0.1}, w: {at: [-a, 0], "
    "mass: 0}}}",
    "coupler: {points: {B: [0, 0], C: [b, 0], P: [xi, eta]}}",
    "a: {value: 1.0, doc: crank}",
    "d: {value: 0, doc: coincident}",
    "gravity: [0, -9.81]",
    "loads: {F: {force: [0, -10], at: rocker.C}, T: {torque: 2, at: crank}}",
    "springs: {k1: {between: [ground.A, coupler.C], stiffness: 100, free_length: 2}}",
    "springs: {k2: {torsional: A, stiffness: 5, free_angle: 0}}",
    "friction: {A: {coefficient: 0.1, pin_radius: 0.01}}",
    "quantities: [K, L, scene, forces, potential]",
    "reactions: [A, B]",
    "theta_coupler: 180*deg",
    "s_S: 0",
};

struct Line {
  std::string indent, text;
};

std::vector<Line> SplitLines(const std::string& s) {
  std::vector<Line> lines;
  size_t start = 0;
  while (start <= s.size()) {
    size_t end = s.find('\n', start);
    if (end == std::string::npos) end = s.size();
    const std::string line = s.substr(start, end - start);
    size_t k = 0;
    while (k < line.size() && (line[k] == ' ' || line[k] == '\t')) ++k;
    lines.push_back({line.substr(0, k), line.substr(k)});
    start = end + 1;
  }
  return lines;
}

std::string JoinLines(const std::vector<Line>& lines) {
  std::string s;
  for (size_t i = 0; i < lines.size(); ++i) s += (i ? "\n" : "") + lines[i].indent + lines[i].text;
  return s;
}

// Tokens [begin, end) of one kind in `text`: numbers or identifiers.
std::vector<std::pair<size_t, size_t>> Tokens(const std::string& text, bool numbers) {
  std::vector<std::pair<size_t, size_t>> out;
  size_t i = 0;
  while (i < text.size()) {
    const unsigned char c = static_cast<unsigned char>(text[i]);
    const bool word_start = std::isalpha(c) || c == '_';
    const bool number_start = std::isdigit(c) || (c == '.' && i + 1 < text.size() && std::isdigit(text[i + 1]));
    if (word_start || number_start) {
      size_t j = i + 1;
      while (j < text.size() &&
             (std::isalnum(static_cast<unsigned char>(text[j])) || text[j] == '_' || (number_start && text[j] == '.')))
        ++j;
      if (number_start == numbers && (numbers || word_start)) out.push_back({i, j});
      i = j;
    } else {
      ++i;
    }
  }
  return out;
}

std::string Mutate(const std::string& input, Random* rng) {
  std::vector<Line> lines = SplitLines(input);
  if (lines.empty()) lines.push_back({"", ""});
  const size_t li = rng->Below(lines.size());
  switch (rng->Below(7)) {
    case 0:
    case 1: {  // a number -> an interesting value, or another number of the file
      const auto tokens = Tokens(lines[li].text, true);
      if (tokens.empty()) break;
      const auto [b, e] = tokens[rng->Below(tokens.size())];
      std::string replacement = kNumbers[rng->Below(sizeof kNumbers / sizeof *kNumbers)];
      if (rng->Below(3) == 0) {
        const size_t other = rng->Below(lines.size());
        const auto more = Tokens(lines[other].text, true);
        if (!more.empty()) {
          const auto [ob, oe] = more[rng->Below(more.size())];
          replacement = lines[other].text.substr(ob, oe - ob);
        }
      }
      lines[li].text.replace(b, e - b, replacement);
      break;
    }
    case 2: {  // a word -> another word of the file or of the language
      const auto tokens = Tokens(lines[li].text, false);
      if (tokens.empty()) break;
      const auto [b, e] = tokens[rng->Below(tokens.size())];
      std::string replacement = kWords[rng->Below(sizeof kWords / sizeof *kWords)];
      if (rng->Below(2) == 0) {
        const size_t other = rng->Below(lines.size());
        const auto more = Tokens(lines[other].text, false);
        if (!more.empty()) {
          const auto [ob, oe] = more[rng->Below(more.size())];
          replacement = lines[other].text.substr(ob, oe - ob);
        }
      }
      lines[li].text.replace(b, e - b, replacement);
      break;
    }
    case 3:  // duplicate a line
      lines.insert(lines.begin() + li, lines[li]);
      break;
    case 4:  // delete a line
      if (lines.size() > 1) lines.erase(lines.begin() + li);
      break;
    case 5:  // swap two lines' texts (each keeps its indentation)
      std::swap(lines[li].text, lines[rng->Below(lines.size())].text);
      break;
    case 6: {  // insert a line of a construct the file may not have
      Line l{lines[li].indent, kLines[rng->Below(sizeof kLines / sizeof *kLines)]};
      lines.insert(lines.begin() + li + (rng->Below(2)), l);
      break;
    }
  }
  return JoinLines(lines);
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  return mechgen_fuzz::FuzzModel(data, size);
}

extern "C" size_t LLVMFuzzerCustomMutator(uint8_t* data, size_t size, size_t max_size, unsigned int seed) {
  Random rng(seed);
  if (rng.Below(2) == 0) return LLVMFuzzerMutate(data, size, max_size);
  const std::string out = Mutate(std::string(reinterpret_cast<const char*>(data), size), &rng);
  if (out.size() > max_size) return LLVMFuzzerMutate(data, size, max_size);
  std::memcpy(data, out.data(), out.size());
  return out.size();
}
