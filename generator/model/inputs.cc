// The `inputs` section: the driven joints, in the order of the generalized coordinates q
// (InputKeys).
#include <cmath>
#include <set>

#include "model/reader.h"

namespace mechgen {

const KeyTable& InputKeys() {
  static const KeyTable table{"input",
                              {{"joint", "the driven joint: revolute or rolling (on the ground), or prismatic", true},
                               {"range", "[min, max]: the default sweep range (default [0, 360*deg], or [0, 1] for a slide)",
                                false}}};
  return table;
}

void ReadInputs(SectionReader& r, const YAML::Node& node) {
  Model& m = r.model();
  if (!node) m.Fail({1, 1}, "the model has no 'inputs'; list the driven joints: inputs: [{joint: <name>}]");
  m.inputs_mark = MarkOf(node);
  if (!node.IsSequence()) r.Fail(node, "inputs must be a list: - {joint: A, range: [0, 360*deg]}");
  std::set<int> used;
  for (const auto& item : node) {
    Input in;
    in.mark = MarkOf(item);
    bool has_range = false;
    for (const auto& [key, value] : r.Entries(item, "input", &InputKeys())) {
      if (key == "joint") {
        const std::string jn = r.Scalar(value, "joint");
        for (size_t k = 0; k < m.joints.size(); ++k)
          if (m.joints[k].name == jn) in.joint = static_cast<int>(k);
        if (in.joint < 0) r.Fail(value, "input: unknown joint '" + jn + "'");
        if (!used.insert(in.joint).second)
          r.Fail(value, "joint '" + jn + "' is driven twice; list each input once");
        const Joint& j = m.joints[in.joint];
        if (!j.IsLowerPair())
          r.Fail(value, "joint '" + jn + "' is a gear, rack or cam pair and cannot be driven; drive a " +
                          "revolute or prismatic joint of one of its links");
        if (j.type() == JointType::kSlot)
          r.Fail(value, "joint '" + jn + "' is a slot joint and cannot be driven; drive a revolute joint of one of "
                        "its links (or make the slot a prismatic joint with a block)");
        if ((j.type() == JointType::kRevolute || j.type() == JointType::kRoll) && !j.Joins(m.ground))
          r.Fail(value, "input joint '" + jn +
                          "' connects two moving links; drive a revolute joint attached to " +
                          "the ground, or a prismatic joint");
      } else {
        if (!value.IsSequence() || value.size() != 2)
          r.Fail(value, "range must be [min, max]");
        in.range_mark = MarkOf(value);
        in.min = r.Number(value[0], "range min");
        in.max = r.Number(value[1], "range max");
        has_range = true;
      }
    }
    if (in.joint < 0) r.Fail(item, "input needs joint: <joint name>");
    if (!has_range) {
      const bool angle = m.joints[in.joint].type() != JointType::kPrismatic;
      in.min = 0;
      in.max = angle ? 2 * M_PI : 1;
    }
    m.inputs.push_back(in);
  }
}

}  // namespace mechgen
