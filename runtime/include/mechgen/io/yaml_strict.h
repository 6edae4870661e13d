/**
 * \file io/yaml_strict.h
 * What yaml-cpp reads silently but a mechgen input file (a study, a synthesis task) must not
 * hold (issue 45): a key given twice in one mapping (yaml-cpp keeps both, and `node[key]` finds
 * the first: the second `count:` would be ignored) and a second YAML document after `---`
 * (YAML::Load reads the first only). The model reader refuses both the same way
 * (generator/model/reader.cc). Errors are YAML::ParserException with the place of the second
 * key or document, so that a reader's existing `catch (const YAML::Exception& e)` reports them at
 * e.mark like a syntax error.
 */
#pragma once

#include <yaml-cpp/eventhandler.h>
#include <yaml-cpp/yaml.h>

#include <istream>
#include <map>
#include <sstream>
#include <string>
#include <vector>

namespace mechgen::io {

/// Throws YAML::ParserException at the second of two equal scalar keys of any mapping in the
/// tree under `root` ("key 'count' given twice in this mapping (first at 3:1); give it once").
inline void RefuseDuplicateKeys(const YAML::Node& root) {
  std::vector<YAML::Node> todo = {root};  // explicit stack: no recursion on a deep tree
  while (!todo.empty()) {
    const YAML::Node node = todo.back();
    todo.pop_back();
    if (node.IsSequence()) {
      for (const YAML::Node& item : node) todo.push_back(item);
    } else if (node.IsMap()) {
      std::map<std::string, YAML::Mark> seen;
      for (const auto& kv : node) {
        if (kv.first.IsScalar()) {
          const auto [at, fresh] = seen.emplace(kv.first.Scalar(), kv.first.Mark());
          if (!fresh)
            throw YAML::ParserException(kv.first.Mark(), "key '" + kv.first.Scalar() +
                                                             "' given twice in this mapping (first at " +
                                                             std::to_string(at->second.line + 1) + ":" +
                                                             std::to_string(at->second.column + 1) +
                                                             "); give it once");
        } else {
          todo.push_back(kv.first);
        }
        todo.push_back(kv.second);
      }
    }
  }
}

namespace yaml_strict_internal {
// Counts the documents of a stream; throws at the start of the second.
class Documents : public YAML::EventHandler {
 public:
  void OnDocumentStart(const YAML::Mark& mark) override {
    if (++documents_ > 1)
      throw YAML::ParserException(mark, "a second YAML document; the file holds one: remove the '---' and what "
                                        "follows");
  }
  void OnDocumentEnd() override {}
  void OnNull(const YAML::Mark&, YAML::anchor_t) override {}
  void OnAlias(const YAML::Mark&, YAML::anchor_t) override {}
  void OnScalar(const YAML::Mark&, const std::string&, YAML::anchor_t, const std::string&) override {}
  void OnSequenceStart(const YAML::Mark&, const std::string&, YAML::anchor_t, YAML::EmitterStyle::value) override {}
  void OnSequenceEnd() override {}
  void OnMapStart(const YAML::Mark&, const std::string&, YAML::anchor_t, YAML::EmitterStyle::value) override {}
  void OnMapEnd() override {}

 private:
  int documents_ = 0;
};
}  // namespace yaml_strict_internal

/// YAML::Load of `text` that also refuses a second document and a key given twice in a
/// mapping: throws YAML::Exception (a syntax error, or YAML::ParserException at the place).
inline YAML::Node LoadStrict(const std::string& text) {
  {
    std::istringstream in(text);
    YAML::Parser parser(in);
    yaml_strict_internal::Documents documents;
    while (parser.HandleNextDocument(documents)) {
    }
  }
  YAML::Node root = YAML::Load(text);
  RefuseDuplicateKeys(root);
  return root;
}

/// The same, reading the stream to its end; a stream that cannot be read (a directory opened
/// as a file: its read fails) throws YAML::Exception at 1:1, not std::ios_base::failure.
inline YAML::Node LoadStrict(std::istream& in) {
  std::string text;
  char buffer[65536];
  // istream::read turns the buffer's exceptions into badbit (a streambuf iterator would not).
  while (in.read(buffer, sizeof(buffer)) || in.gcount() > 0) text.append(buffer, static_cast<size_t>(in.gcount()));
  if (in.bad()) throw YAML::Exception(YAML::Mark(), "cannot read the file (a directory, or a read error)");
  return LoadStrict(text);
}

}  // namespace mechgen::io
