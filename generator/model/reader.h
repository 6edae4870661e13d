// The model reader's shared parts: the key tables every section declares, and the
// SectionReader each section's reader (parameters.cc, links.cc, joints.cc, inputs.cc,
// outputs.cc, assembly.cc in this folder) and each joint kind (joints/<kind>.cc) reads
// with. A section or a kind accepts exactly the keys of its table and rejects any other
// with file:line:column; models/README.md lists the same keys (tests/generator/
// model_keys_test.cc compares the two).
#pragma once

#include <yaml-cpp/yaml.h>

#include <map>
#include <string>
#include <utility>
#include <vector>

#include "model/model.h"

namespace mechgen {

/// One key a section (or a joint kind) accepts.
struct Key {
  const char* name;
  const char* meaning;  ///< one line, for the reader of the code (README holds the prose)
  bool required;
};

/// The keys of one mapping of the model file. `section` names it as models/README.md's
/// key tables do: "model", "parameter", "link", "joint", "input", "outputs", "law segment",
/// "contour", and the joint kinds "revolute", "prismatic", ... (assembly and points take
/// any name: they have no table).
struct KeyTable {
  const char* section;
  std::vector<Key> keys;
  bool Accepts(const std::string& key) const;
};

/// Every key table of the reader, sections first, then the joint kinds in registry order.
std::vector<const KeyTable*> AllKeyTables();

// Sections' key tables (defined with their readers).
const KeyTable& ModelKeys();
const KeyTable& ParameterKeys();
const KeyTable& LinkKeys();
const KeyTable& PointMassKeys();
const KeyTable& JointKeys();
const KeyTable& InputKeys();
const KeyTable& OutputKeys();
const KeyTable& LawSegmentKeys();
const KeyTable& ContourKeys();
const KeyTable& LoadKeys();
const KeyTable& SpringKeys();
const KeyTable& FrictionKeys();
const KeyTable& DamperKeys();
const KeyTable& TableKeys();
const KeyTable& DesignKeys();

/// Reading helpers over one model being filled. Every failure is a ModelError at the
/// offending node.
class SectionReader {
 public:
  explicit SectionReader(Model* model) : m_(*model) {}
  Model& model() const { return m_; }
  /// The model file's text, so that an expression's error can point at the character
  /// (else it points at the node).
  void SetSource(const std::string* text) { source_ = text; }

  [[noreturn]] void Fail(const YAML::Node& node, const std::string& message) const;

  /// The entries of a mapping node, in document order; duplicate keys are an error, and
  /// so is a key not in `table` (if given).
  std::vector<std::pair<std::string, YAML::Node>> Entries(const YAML::Node& map, const std::string& what,
                                                          const KeyTable* table = nullptr) const;
  std::string Scalar(const YAML::Node& node, const std::string& what) const;
  bool Bool(const YAML::Node& node, const std::string& what) const;
  /// An expression of the language models/README.md documents ("Expressions"): numbers,
  /// the parameters, `deg` and `Pi`, + - * / ^ and the whitelisted functions; with `u`,
  /// also a cam contour's parameter u. Checked before GiNaC reads it (characters, syntax,
  /// names, at most kMaxExpressionNesting parentheses, kMaxExpressionLength characters), and,
  /// if it does not use `u`, evaluated at the parameters' defaults: every sub-expression must be finite
  /// and real there (no division by zero, no square root or logarithm of a negative number).
  /// Any failure is a ModelError at the offending character.
  GiNaC::ex Expression(const YAML::Node& node, const std::string& what, const GiNaC::symbol* u = nullptr) const;
  /// The same with more names than `u` (e.g. the coordinates a load depends on): `extra`
  /// maps each name to its symbol; the value at the defaults is checked only if the
  /// expression uses none of them.
  GiNaC::ex Expression(const YAML::Node& node, const std::string& what, const GiNaC::symtab& extra) const;
  /// Whether the model's tables may be called in the expressions read next (loads only).
  void AllowTables(bool allow) { tables_ = allow; }
  /// The parameters not yet defined while a derived parameter is read (itself first, then
  /// those below it), so that naming one is an error that says so; empty otherwise.
  void SetPendingNames(std::vector<std::pair<std::string, SourceMark>> names) { pending_ = std::move(names); }
  /// A number: an expression evaluated at the parameters' default values.
  double Number(const YAML::Node& node, const std::string& what) const;
  /// "link.point" -> PointRef.
  PointRef Point(const YAML::Node& node, const std::string& what) const;
  /// "<rolling joint>.contact": the contact point of a rolling joint; else link = -1.
  PointRef ContactPoint(const YAML::Node& node) const;
  /// A link by name -> its index.
  int LinkIndex(const YAML::Node& node, const std::string& what) const;
  /// The mark of the key whose value is `value` (the value's own mark if unknown).
  SourceMark KeyMark(const YAML::Node& value) const;
  /// The mark of the character at `offset` of the expression `text`, the value of `node`
  /// (the node's mark where the text cannot be located in the file, e.g. a block scalar).
  SourceMark MarkAt(const YAML::Node& node, const std::string& text, size_t offset) const;

 private:
  [[noreturn]] void FailAt(const YAML::Node& node, const std::string& text, size_t offset,
                           const std::string& message) const;

  Model& m_;
  const std::string* source_ = nullptr;
  bool tables_ = false;
  std::vector<std::pair<std::string, SourceMark>> pending_;
  mutable std::map<int, SourceMark> keymarks_;  // value position -> mark of its key
  mutable std::map<int, std::string> keynames_;  // value position -> its key
};

SourceMark MarkOf(const YAML::Node& node);
/// An expression's value at the parameters' defaults; a ModelError at `mark` if it is not
/// a finite real number ("<what> must evaluate to a real number", "<what> is not finite").
double ValueAtDefaults(const Model& m, const GiNaC::ex& e, SourceMark mark, const std::string& what);
bool IsIdentifier(const std::string& s);
/// Why points `a` and `b` (of different links) are always at one place, whatever the motion:
/// joined by revolute joints (directly, or through a pin over several links), possibly via
/// other points of a link at the same coordinates (equal expressions). "" if not; else how,
/// e.g. "the revolute joint A keeps them together". A spring or damper between them would
/// have no length and no direction.
std::string AlwaysTogether(const Model& m, const PointRef& a, const PointRef& b);
/// The functions of the expression language, each with its number of arguments: exactly
/// these are accepted (models/README.md, "Expressions", lists the same; an unknown function's
/// error lists them).
const std::map<std::string, int>& ExpressionFunctions();

/// Limits of the reader (models/README.md, "Errors"): a model file is a regular file of at
/// most kMaxModelBytes; an expression has at most kMaxExpressionLength characters and nests
/// at most kMaxExpressionNesting parentheses (GiNaC's parser is recursive); numbers (parameter
/// defaults and literals) are 0 or of magnitude in [kMinMagnitude, kMaxMagnitude], so that
/// products of a few stay within double range when the generator evaluates them.
constexpr size_t kMaxModelBytes = 1 << 20;
constexpr size_t kMaxExpressionLength = 4096;
constexpr int kMaxExpressionNesting = 64;
constexpr double kMinMagnitude = 1e-100;
constexpr double kMaxMagnitude = 1e100;
/// A power whose exponent has no parameter in it is computed exactly by GiNaC's reader (2^1000
/// is an integer of 302 digits): its exponent is at most kMaxConstantExponent in magnitude, and
/// a power of two constants at most kMaxExactDigits decimal digits, so that no model can make
/// the reader run for minutes (fuzzing found 22222222222222^2222222222).
constexpr double kMaxConstantExponent = 1000;
constexpr double kMaxExactDigits = 100000;

/// What a name of the model becomes in the generated C++ (models/README.md, "Names").
enum class NameRole { kModel, kParameter, kLink, kPoint, kJoint, kTable };
/// Why `name` cannot be a `role` name ("is a C++ keyword", ...), or "" if it can: not an
/// ASCII identifier, a C++ keyword, reserved (a leading underscore, a double underscore), and
/// for the model and the parameters (C++ names of their own) a macro of the headers the
/// generated code includes or a name the generated code uses; for the model also a trailing
/// underscore and the name of a C header; for a table (called like a function, `name(x)`, and
/// a C++ name of its own like a parameter) also the name of a function of the expression language.
std::string NameProblem(const std::string& name, NameRole role);
/// A ModelError at `mark` if NameProblem(name, role) is not empty.
void CheckName(const Model& m, const std::string& name, NameRole role, SourceMark mark);
/// Why free text (title, description, a parameter's doc) cannot be carried into the
/// generated header's comments, or "": control characters (a newline only if `multiline`),
/// invalid UTF-8, or a trailing backslash (it would continue a // comment onto the next line).
std::string FreeTextProblem(const std::string& text, bool multiline);

// The sections, in the order LoadModel reads them.
void ReadParameters(SectionReader& r, const YAML::Node& node);
void ReadLinks(SectionReader& r, const YAML::Node& node);
void ReadJoints(SectionReader& r, const YAML::Node& node);
void ReadInputs(SectionReader& r, const YAML::Node& node);
void ReadGravity(SectionReader& r, const YAML::Node& node);
void ReadLoads(SectionReader& r, const YAML::Node& node);
void ReadSprings(SectionReader& r, const YAML::Node& node);
void ReadFriction(SectionReader& r, const YAML::Node& node);
void ReadTables(SectionReader& r, const YAML::Node& node);
void ReadDampers(SectionReader& r, const YAML::Node& node);
/// After the outputs: a load that reads t or a velocity needs the `dynamics` quantity.
void CheckDynamicRefs(const Model& m);
void ReadOutputs(SectionReader& r, const YAML::Node& node);
void ReadDesign(SectionReader& r, const YAML::Node& node);
void ReadAssembly(SectionReader& r, const YAML::Node& node);
void ReadAssemblyModes(SectionReader& r, const YAML::Node& node);

}  // namespace mechgen
