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
const KeyTable& JointKeys();
const KeyTable& InputKeys();
const KeyTable& OutputKeys();
const KeyTable& LawSegmentKeys();
const KeyTable& ContourKeys();
const KeyTable& LoadKeys();
const KeyTable& SpringKeys();
const KeyTable& FrictionKeys();

/// Reading helpers over one model being filled. Every failure is a ModelError at the
/// offending node.
class SectionReader {
 public:
  explicit SectionReader(Model* model) : m_(*model) {}
  Model& model() const { return m_; }

  [[noreturn]] void Fail(const YAML::Node& node, const std::string& message) const;

  /// The entries of a mapping node, in document order; duplicate keys are an error, and
  /// so is a key not in `table` (if given).
  std::vector<std::pair<std::string, YAML::Node>> Entries(const YAML::Node& map, const std::string& what,
                                                          const KeyTable* table = nullptr) const;
  std::string Scalar(const YAML::Node& node, const std::string& what) const;
  bool Bool(const YAML::Node& node, const std::string& what) const;
  /// An expression in the parameters (and `deg` = pi/180); with `u`, also in a cam
  /// contour's parameter u.
  GiNaC::ex Expression(const YAML::Node& node, const std::string& what, const GiNaC::symbol* u = nullptr) const;
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

 private:
  Model& m_;
  mutable std::map<int, SourceMark> keymarks_;  // value position -> mark of its key
};

SourceMark MarkOf(const YAML::Node& node);
/// An expression's value at the parameters' defaults; a ModelError at `mark` if it is not
/// a finite real number ("<what> must evaluate to a real number", "<what> is not finite").
double ValueAtDefaults(const Model& m, const GiNaC::ex& e, SourceMark mark, const std::string& what);
bool IsIdentifier(const std::string& s);

// The sections, in the order LoadModel reads them.
void ReadParameters(SectionReader& r, const YAML::Node& node);
void ReadLinks(SectionReader& r, const YAML::Node& node);
void ReadJoints(SectionReader& r, const YAML::Node& node);
void ReadInputs(SectionReader& r, const YAML::Node& node);
void ReadGravity(SectionReader& r, const YAML::Node& node);
void ReadLoads(SectionReader& r, const YAML::Node& node);
void ReadSprings(SectionReader& r, const YAML::Node& node);
void ReadFriction(SectionReader& r, const YAML::Node& node);
void ReadOutputs(SectionReader& r, const YAML::Node& node);
void ReadAssembly(SectionReader& r, const YAML::Node& node);

}  // namespace mechgen
