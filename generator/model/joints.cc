// The `joints` section: `NAME: {<kind>: <body>}`, one kind per joint. The kind's file
// (generator/joints/<kind>.cc) reads the body with its own key table; references to other
// joints (a rack's slide, a cam's follower) are resolved once every joint is read.
#include <map>

#include "joints/joint_kind.h"
#include "model/reader.h"


namespace mechgen {

const KeyTable& JointKeys() {
  static const KeyTable table = [] {
    KeyTable t{"joint", {}};
    for (const JointKind* k : JointKinds()) t.keys.push_back({k->Keys().section, "the joint's kind and its data", false});
    return t;
  }();
  return table;
}

void ReadJoints(SectionReader& r, const YAML::Node& node) {
  Model& m = r.model();
  if (!node) m.Fail({1, 1}, "the model has no 'joints'; add a joints: section (the joints between the links)");
  std::map<std::string, SourceMark> later_names;  // the pins' names of revolute joints over several links
  for (const auto& [name, spec] : r.Entries(node, "joints")) {
    Joint j;
    j.name = name;
    j.mark = r.KeyMark(spec);
    CheckName(m, name, NameRole::kJoint, j.mark);
    auto entries = r.Entries(spec, "joint '" + name + "'", &JointKeys());
    if (entries.size() != 1)
      r.Fail(spec, "joint '" + name + "' must have exactly one kind: revolute, prismatic, roll, gear, rack, cam or slot");
    const auto& [kind, body] = entries[0];
    // A cam's data creates its contour parameter's symbol; any other kind makes one here.
    // GiNaC orders terms by symbol serial numbers, so this keeps the generated text as it
    // was when every joint carried that symbol.
    if (kind != "cam") GiNaC::symbol serial_keeper("u");
    if (kind == "revolute" && body.IsSequence() && body.size() > 2) {
      for (Joint& pin : ReadPinOverLinks(r, body, j)) {
        const int other = m.FindJoint(pin.name);
        if (other >= 0)
          m.Fail(pin.mark, "revolute joint '" + name + "' names its pin to link '" + m.links[pin.link_b].name + "' '" +
                               pin.name + "', the name of joint '" + pin.name + "' (line " +
                               std::to_string(m.joints[other].mark.line) + "); rename that joint");
        later_names[pin.name] = pin.mark;
        m.joints.push_back(pin);
      }
      continue;
    }
    if (later_names.count(name))
      m.Fail(j.mark, "joint name '" + name + "' is the name of a pin of a revolute joint over several links (line " +
                         std::to_string(later_names[name].line) + "); rename this joint");
    FindKind(kind)->Read(r, body, &j);
    if (j.link_a == j.link_b)
      m.Fail(j.mark, "joint '" + name + "' connects link '" + m.links[j.link_a].name +
                         "' to itself; a joint must connect two different links");
    m.joints.push_back(j);
  }
  for (size_t k = 0; k < m.joints.size(); ++k) KindOf(m.joints[k]).Resolve(r, static_cast<int>(k));
}

}  // namespace mechgen
