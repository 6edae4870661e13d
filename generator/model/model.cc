// The model's own methods. See model.h.
#include "model/model.h"

#include <sstream>

namespace mechgen {
namespace {

std::string Format(const std::string& file, SourceMark mark, const std::string& message) {
  std::ostringstream os;
  os << file;
  if (mark.line > 0) os << ":" << mark.line << ":" << mark.column;
  os << ": error: " << message;
  return os.str();
}

}  // namespace

ModelError::ModelError(const std::string& file, SourceMark mark, const std::string& message)
    : std::runtime_error(Format(file, mark, message)),
      file_(file),
      mark_(mark),
      message_(message) {}

int Link::FindPoint(const std::string& point) const {
  for (size_t i = 0; i < points.size(); ++i)
    if (points[i].name == point) return static_cast<int>(i);
  return -1;
}

std::string Model::PointName(PointRef r) const {
  if (r.contact_joint >= 0) return joints[r.contact_joint].name + ".contact";
  return links[r.link].name + "." + links[r.link].points[r.point].name;
}

int Model::FindJoint(const std::string& name) const {
  for (size_t k = 0; k < joints.size(); ++k)
    if (joints[k].name == name) return static_cast<int>(k);
  return -1;
}

GiNaC::exmap Model::Defaults() const {
  GiNaC::exmap d;
  for (const Parameter& p : params) d[p.symbol] = p.value;
  return d;
}

PointRef Joint::End(int link) const {
  switch (type()) {
    case JointType::kRevolute: {
      const RevoluteData& d = Data<RevoluteData>();
      return link_a == link ? d.a : d.b;
    }
    case JointType::kPrismatic: {
      const PrismaticData& d = Data<PrismaticData>();
      return link_a == link ? d.guide : d.slider;
    }
    case JointType::kRoll: {
      const RollData& d = Data<RollData>();
      return link_a == link ? d.on : d.wheel;
    }
    case JointType::kSlot: {
      const SlotData& d = Data<SlotData>();
      return link_a == link ? d.slot : d.pin;
    }
    default: return {};
  }
}

void Model::Fail(SourceMark mark, const std::string& message) const {
  throw ModelError(file, mark, message);
}

}  // namespace mechgen
