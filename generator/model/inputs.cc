// The `inputs` section: the driven joints, in the order of the generalized coordinates q
// (InputKeys).
#include <cmath>
#include <set>

#include "model/reader.h"

namespace mechgen {

const KeyTable& InputKeys() {
  static const KeyTable table{"input",
                              {{"joint", "the driven joint: revolute or rolling (on the ground), prismatic, or a pin "
                                         "in a slot (its slide)", false},
                               {"angle", "instead of joint: a link whose absolute angle is driven", false},
                               {"point", "instead of joint: link.point, a point whose x or y is driven", false},
                               {"coordinate", "with point: x or y, the driven coordinate in the fixed frame", false},
                               {"range", "[min, max]: the default sweep range (default [0, 360*deg], or [0, 1] for a slide; "
                                         "required for a point)",
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
    YAML::Node driver, coordinate;  // the first of joint/angle/point, and `coordinate`
    bool has_driver = false, has_coordinate = false;
    std::string driver_key;
    for (const auto& [key, value] : r.Entries(item, "input", &InputKeys())) {
      if (key == "joint" || key == "angle" || key == "point") {
        if (has_driver)
          r.Fail(value, "input has both '" + driver_key + "' and '" + key + "'; an input drives one joint, one link's "
                        "angle or one coordinate of a point: keep one of them (a point's x and y are two inputs)");
        driver = value;
        driver_key = key;
        has_driver = true;
      }
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
                          "revolute or prismatic joint of one of its links, or a link's angle (angle: <link>)");
        if ((j.type() == JointType::kRevolute || j.type() == JointType::kRoll) && !j.Joins(m.ground))
          r.Fail(value, "input joint '" + jn +
                          "' connects two moving links; drive a revolute joint attached to " +
                          "the ground, a prismatic joint, or the absolute angle of one of its links (angle: " +
                          m.links[j.link_b].name + ")");
      } else if (key == "angle") {
        in.kind = Input::Kind::kAngle;
        in.link = r.LinkIndex(value, "input angle");
        if (in.link == m.ground)
          r.Fail(value, "input angle: '" + m.links[in.link].name + "' is the ground, whose angle is fixed; name a "
                        "moving link");
      } else if (key == "point") {
        in.kind = Input::Kind::kPointX;
        in.point = r.Point(value, "input point");
        if (in.point.link == m.ground)
          r.Fail(value, "input point: '" + m.PointName(in.point) + "' is a point of the ground, which does not move; "
                        "name a point of a moving link");
      } else if (key == "coordinate") {
        coordinate = value;
        has_coordinate = true;
      } else {
        if (!value.IsSequence() || value.size() != 2)
          r.Fail(value, "range must be [min, max]");
        in.range_mark = MarkOf(value);
        in.min = r.Number(value[0], "range min");
        in.max = r.Number(value[1], "range max");
        has_range = true;
      }
    }
    if (!has_driver)
      r.Fail(item, "input needs joint: <joint name>, angle: <link> or point: <link.point> with coordinate: x|y");
    if (has_coordinate && !in.IsPoint())
      r.Fail(coordinate, "coordinate is a point input's (point: <link.point>, coordinate: x|y); remove it");
    if (in.IsPoint()) {
      if (!has_coordinate) r.Fail(item, "input point '" + m.PointName(in.point) + "' needs coordinate: x or coordinate: y");
      const std::string c = r.Scalar(coordinate, "coordinate");
      if (c != "x" && c != "y")
        r.Fail(coordinate, "coordinate must be x or y (the point's coordinate in the fixed frame), not '" + c + "'");
      in.kind = c == "x" ? Input::Kind::kPointX : Input::Kind::kPointY;
      if (!has_range)
        r.Fail(item, "input point '" + m.PointName(in.point) + "' needs range: [min, max] (its " + c +
                       " over the default sweep, in the model's length unit)");
    }
    for (const Input& other : m.inputs) {
      const bool same = in.kind == other.kind &&
                        (in.kind == Input::Kind::kJoint ? false
                         : in.kind == Input::Kind::kAngle ? in.link == other.link
                                                          : in.point == other.point);
      if (same)
        r.Fail(driver, "input " + driver_key + " '" +
                           (in.kind == Input::Kind::kAngle ? m.links[in.link].name : m.PointName(in.point)) +
                           "' is driven twice; list each input once");
    }
    if (!has_range) {
      const bool angle = in.kind == Input::Kind::kAngle || (m.joints[in.joint].type() != JointType::kPrismatic &&
                                                            m.joints[in.joint].type() != JointType::kSlot);
      in.min = 0;
      in.max = angle ? 2 * M_PI : 1;
    }
    m.inputs.push_back(in);
  }
}

}  // namespace mechgen
