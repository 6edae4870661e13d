// Template filling and file writing. See emit.h.
#include "codegen/emit.h"

#include <kainjow/mustache.hpp>

#include <algorithm>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <map>
#include <regex>
#include <set>
#include <sstream>
#include <stdexcept>
#include <utility>

#include "codegen/drawing.h"
#include "codegen/output_spec.h"
#include "codegen/sha256.h"
#include "model/reader.h"
#include "symbolic/statics.h"

#ifndef MECHGEN_VERSION
#define MECHGEN_VERSION "0.0.0"
#endif

namespace mechgen {
namespace {

namespace mus = kainjow::mustache;

// The bytes of a file; `what` names it in the error ("template", "model file").
std::string ReadFile(const std::string& path, const std::string& what = "template") {
  std::ifstream in(path, std::ios::binary);
  if (!in) throw std::runtime_error("cannot read " + what + " " + path);
  std::ostringstream os;
  os << in.rdbuf();
  return os.str();
}

// Free text (the model's title, description, a parameter's doc, the model file's name) as it
// can stand in a comment: "*/" and "/*" are broken up ("*\/", "/\*": a block comment would
// end, or -Wcomment warn), and control characters (the reader rejects them in the model's
// text; a file name may hold one) become '?', so that no line ends early.
std::string CommentText(const std::string& text) {
  std::string out;
  for (size_t i = 0; i < text.size(); ++i) {
    const char c = text[i];
    if (i > 0 && ((c == '/' && text[i - 1] == '*') || (c == '*' && text[i - 1] == '/'))) out += '\\';
    out += (static_cast<unsigned char>(c) < 0x20 && c != '\t' && c != '\n') || c == 0x7f ? '?' : c;
  }
  return out;
}

std::string Number(double v) {
  char buf[64];
  std::snprintf(buf, sizeof buf, "%.17g", v);
  std::string s = buf;
  if (s.find_first_of(".en") == std::string::npos) s += ".0";
  return s;
}

template <typename T, typename F>
std::string Join(const std::vector<T>& v, F f) {
  std::string s;
  for (size_t i = 0; i < v.size(); ++i) s += (i ? ", " : "") + f(v[i]);
  return s;
}

std::string Quote(const std::string& s) { return "\"" + s + "\""; }

// Data for the templates, remembering every key so that a template naming a value the
// generator does not provide is an error instead of an empty string.
class TemplateData {
 public:
  void Set(const std::string& key, const std::string& value) {
    keys_.insert(key);
    data_.set(key, value);
  }
  void Set(const std::string& key, bool value) {
    keys_.insert(key);
    data_.set(key, value ? mus::data::type::bool_true : mus::data::type::bool_false);
  }
  void Set(const std::string& key, int value) { Set(key, std::to_string(value)); }
  void SetList(const std::string& key, const std::vector<std::map<std::string, std::string>>& items,
               const std::set<std::string>& item_keys) {
    keys_.insert(key);
    for (const auto& k : item_keys) keys_.insert(k);
    mus::data list{mus::data::type::list};
    for (const auto& item : items) {
      mus::data obj{mus::data::type::object};
      for (const auto& [k, v] : item) obj.set(k, v);
      list.push_back(obj);
    }
    data_.set(key, list);
  }
  /// A value built by hand (lists of objects with lists); `item_keys` are the keys its
  /// objects use, so that the placeholder check knows them.
  void SetData(const std::string& key, const mus::data& value, const std::set<std::string>& item_keys) {
    keys_.insert(key);
    for (const auto& k : item_keys) keys_.insert(k);
    data_.set(key, value);
  }
  std::string Render(const std::string& path) const {
    const std::string text = ReadFile(path);
    static const std::regex tag(R"(\{\{\{?\s*[#^/&]?\s*([A-Za-z_][A-Za-z0-9_]*)\s*\}?\}\})");
    for (auto it = std::sregex_iterator(text.begin(), text.end(), tag); it != std::sregex_iterator(); ++it) {
      const std::string key = (*it)[1];
      if (!keys_.count(key))
        throw std::runtime_error(path + ": placeholder '" + key + "' has no value in mechgen");
    }
    mus::mustache tmpl(text);
    if (!tmpl.is_valid()) throw std::runtime_error(path + ": " + tmpl.error_message());
    tmpl.set_custom_escape([](const std::string& s) { return s; });
    const std::string out = tmpl.render(data_);
    if (!tmpl.is_valid()) throw std::runtime_error(path + ": " + tmpl.error_message());
    return out;
  }

 private:
  mus::data data_{mus::data::type::object};
  std::set<std::string> keys_;
};

std::vector<std::map<std::string, std::string>> LineMaps(const std::string& text) {
  std::vector<std::map<std::string, std::string>> out;
  std::istringstream in(text);
  std::string line;
  while (std::getline(in, line)) {
    while (!line.empty() && (line.back() == ' ' || line.back() == '\r')) line.pop_back();
    out.push_back({{"line", line}});
  }
  while (!out.empty() && out.back().at("line").empty()) out.pop_back();
  return out;
}

// Indents by brace depth (the position solver nests loops and blocks).
std::string Reindent(const std::string& text) {
  std::istringstream in(text);
  std::string line, out;
  int depth = 1;
  while (std::getline(in, line)) {
    const auto first = line.find_first_not_of(' ');
    if (first == std::string::npos) {
      out += "\n";
      continue;
    }
    line = line.substr(first);
    std::string code = line.substr(0, line.find("//"));
    if (!code.empty() && code[0] == '}') --depth;
    out += std::string(2 * depth, ' ') + line + "\n";
    for (char c : code) depth += c == '{' ? 1 : c == '}' ? -1 : 0;
    if (!code.empty() && code[0] == '}') ++depth;
  }
  return out;
}

// Deletes // comments (the names they mention are not uses).
std::string StripComments(const std::string& text) {
  static const std::regex comment("//[^\n]*");
  return std::regex_replace(text, comment, "");
}

// Whether `code` uses the variable `name`: a member of the same spelling (`p.c`, a parameter
// named like the coefficients' argument `c`; `out->q`, `ns::t`) is not a use.
bool Mentions(const std::string& code, const std::string& name) {
  const std::regex word("(^|[^A-Za-z0-9_.:>])" + name + "([^A-Za-z0-9_]|$)");
  return std::regex_search(code, word);
}

mus::data Bool(bool b) { return b ? mus::data::type::bool_true : mus::data::type::bool_false; }

// The template scalar `name` replaced by a concrete scalar type (explicit instantiations).
std::string WithScalar(const std::string& type, const std::string& name, const std::string& scalar) {
  return std::regex_replace(type, std::regex("\\b" + name + "\\b"), scalar);
}

// The \param lines of a function's documentation, aligned.
std::vector<std::string> ParamDoc(const FunctionSpec& f) {
  size_t tag_width = 0, name_width = 0;
  auto tag = [](const Argument& a) {
    return std::string(a.direction == Argument::Direction::kIn    ? "\\param[in]"
                       : a.direction == Argument::Direction::kOut ? "\\param[out]"
                                                                  : "\\param[in,out]");
  };
  for (const Argument& a : f.args) {
    tag_width = std::max(tag_width, tag(a).size());
    name_width = std::max(name_width, a.name.size());
  }
  std::vector<std::string> lines;
  for (const Argument& a : f.args) {
    std::string text = a.doc;
    if (!a.size.empty()) {
      if (!text.empty() && text.back() == '.')
        text = text.substr(0, text.size() - 1) + " (" + a.size + ").";
      else
        text += " (" + a.size + ")";
    }
    if (!text.empty() && text.back() != '.') text += ".";
    if (a.nullable) text += " May be nullptr.";
    std::string t = tag(a), n = a.name;
    t.resize(tag_width, ' ');
    n.resize(name_width, ' ');
    // Wrapped at 100 columns (" * " and the text), continued under the text.
    const std::string head = t + " " + n + "  ";
    std::istringstream words(text);
    std::string word, line = head;
    while (words >> word) {
      if (line.size() > head.size() && 3 + line.size() + 1 + word.size() > 100) {
        lines.push_back(line);
        line = std::string(head.size(), ' ');
      }
      line += (line.size() > head.size() ? " " : "") + word;
    }
    lines.push_back(line);
  }
  return lines;
}

mus::data Lines(const std::vector<std::string>& lines) {
  mus::data list{mus::data::type::list};
  for (const std::string& l : lines) {
    mus::data o{mus::data::type::object};
    o.set("line", l.empty() ? std::string() : " " + l);
    list.push_back(o);
  }
  return list;
}

// Arguments as the template renders them: type, name and default.
mus::data ArgList(const FunctionSpec& f, const std::string& scalar, bool defaults, bool member) {
  const std::vector<Argument>& args = f.args;
  mus::data list{mus::data::type::list};
  for (size_t i = 0; i < args.size(); ++i) {
    const Argument& a = args[i];
    const std::string def = member && !a.member_default.empty() ? a.member_default : a.default_value;
    mus::data o{mus::data::type::object};
    o.set("arg_type", scalar.empty() ? a.type : WithScalar(a.type, f.scalar, scalar));
    o.set("arg_name", a.name);
    o.set("has_default", Bool(defaults && !def.empty()));
    o.set("arg_default", def);
    o.set("first", Bool(i == 0));
    list.push_back(o);
  }
  return list;
}

std::string Spaces(size_t n) { return std::string(n, ' '); }

bool StartsWith(const std::string& s, const std::string& prefix) { return s.compare(0, prefix.size(), prefix) == 0; }
bool EndsWith(const std::string& s, const std::string& suffix) {
  return s.size() >= suffix.size() && s.compare(s.size() - suffix.size(), suffix.size(), suffix) == 0;
}

// How the model view (templates/mechanism_view.cc.mustache) passes one argument of a Model
// function: its type in the view's signature (core/model_view.h), the lines before the call
// (the array copied into the fixed-size type), what the call gets, the lines after it (the
// result copied back). Every pointer may be nullptr (it stays nullptr). A struct of the view
// (ViewLayout) is copied member by member, only the members the function's body names
// (StructUse): an input's members it reads; an output's members it reads or stores to, each
// read from its buffer before the call (so that what the function does not write keeps its
// value, as in the struct the buffer stands for) unless the body, without a `return`, stores
// every one of its entries unconditionally (GetUnlessStored: then its buffer is not read, nor
// need it be initialized), and copied back after it; a member the body does not name is
// neither read nor written (its buffer keeps its value). An output the view writes whole
// (WrittenWhole()) starts at zero instead, and its buffer is not read.
// A struct argument may instead be passed on the caller's storage (in_place: the struct at its
// buffer, no copy in or out) where its members lie at their offsets in the buffer and the
// buffer is aligned for it (`check`: view_buffers::InPlace); an output the view writes whole is
// set to 0 there first but for what the function stores whole (in_place_before). The same
// values either way: the function reads and writes the same entries, and what it does not
// write keeps the buffer's value.
struct FlatArgument {
  FlatArgument(std::string t, std::vector<std::string> b, std::vector<std::string> a, std::string p)
      : type(std::move(t)), before(std::move(b)), after(std::move(a)), pass(std::move(p)) {}
  std::string type;
  std::vector<std::string> before, after;
  std::string pass;
  std::string check;                       // empty: not a struct, always copied
  std::vector<std::string> in_place_before;
  std::string in_place_pass;
};

// The outputs the view writes whole (core/model_view.h says which): Coeffs' Coefficients (the
// generated function writes each of its entries) and the sin and cos of Solve and SolveTrig (0
// where a coordinate is a displacement, which they do not write). The runtime's continuation
// step passes them every step: nothing to copy in, nothing to initialize.
bool WrittenWhole(const std::string& member, const Argument& a) {
  return (member == "Coeffs" && a.name == "out") || ((member == "Solve" || member == "SolveTrig") && a.name == "trig");
}

// How a function's body (its text without comments) uses its struct argument `name`: through
// members only (name.X, name->X, and tests against nullptr), or otherwise (passed on whole:
// every member is read). `read`: the members it reads, adds to or stores to under a
// condition (inside braces); `stored`: for the others it stores to, the distinct entries
// ("(0, 1)", "" for a scalar) stored by a statement `name->X(...) = ...;` at the top level of
// the body (on every path that does not return first; may_return: the body has a `return`).
struct StructUse {
  static StructUse Whole() {
    StructUse u;
    u.whole = true;
    return u;
  }
  bool whole = false;
  bool may_return = false;
  std::set<std::string> read;
  std::map<std::string, std::set<std::string>> stored;
};

StructUse UseOf(const std::string& code, const std::string& name) {
  StructUse u;
  auto word = [](char c) { return std::isalnum(static_cast<unsigned char>(c)) || c == '_'; };
  u.may_return = Mentions(code, "return");
  int depth = 0;
  size_t line = 0;  // the start of the current line
  for (size_t i = 0; i < code.size(); ++i) {
    const char c = code[i];
    if (c == '{') ++depth;
    if (c == '}') --depth;
    if (c == '\n') line = i + 1;
    if (code.compare(i, name.size(), name) != 0) continue;
    if (i > 0 && (word(code[i - 1]) || code[i - 1] == '.' || code[i - 1] == '>' || code[i - 1] == ':')) continue;
    if (i >= 6 && code.compare(i - 6, 6, "(void)") == 0) continue;  // (RenderBody's mark of an unread argument)
    size_t j = i + name.size();
    if (j < code.size() && word(code[j])) continue;
    const size_t access = code.compare(j, 2, "->") == 0 ? 2 : (j < code.size() && code[j] == '.' ? 1 : 0);
    if (access == 0) {
      if (code.compare(j, 11, " != nullptr") == 0 || code.compare(j, 11, " == nullptr") == 0) continue;
      u.whole = true;
      return u;
    }
    size_t k = j + access;
    const size_t m = k;
    while (k < code.size() && word(code[k])) ++k;
    const std::string member = code.substr(m, k - m);
    std::string index;
    if (k < code.size() && code[k] == '(') {
      size_t close = k;
      for (int open = 0; close < code.size(); ++close) {
        if (code[close] == '(') ++open;
        if (code[close] == ')' && --open == 0) break;
      }
      index = code.substr(k, close + 1 - k);
      k = close + 1;
    }
    const bool statement = code.find_first_not_of(' ', line) == i;
    if (statement && depth == 0 && code.compare(k, 3, " = ") == 0)
      u.stored[member].insert(index);
    else
      u.read.insert(member);
  }
  for (const std::string& r : u.read) u.stored.erase(r);
  return u;
}

FlatArgument Flatten(const Argument& a, const std::string& scalar, bool written_whole, const std::string& code,
                     const std::map<std::string, std::vector<std::string>>& structs) {
  const std::string type = WithScalar(a.type, scalar, "double");
  const std::string& n = a.name;
  const std::string local = n + "_";
  auto array = [](const std::string& core, bool in) {
    return std::string(in ? "const " : "") + (StartsWith(core, "std::array<int,") ? "int*" : "double*");
  };
  // The view's struct `core` is ("Statics<double>": Statics), or nullptr.
  auto struct_of = [&structs](const std::string& core) -> const std::vector<std::string>* {
    const size_t open = core.find('<');
    if (open == std::string::npos || core.substr(open) != "<double>") return nullptr;
    const auto it = structs.find(core.substr(0, open));
    return it != structs.end() ? &it->second : nullptr;
  };
  // An input struct: the members the body reads, each from its offset (all where it is passed on).
  auto struct_input = [&](const std::string& core, const std::string& guard) -> std::vector<std::string> {
    const std::vector<std::string>* members = struct_of(core);
    const StructUse use = members != nullptr ? UseOf(code, n) : StructUse::Whole();
    if (use.whole) return {core + " " + local + ";", guard + "Get(" + n + ", &" + local + ");"};
    std::vector<std::string> lines{core + " " + local + ";"};
    const std::string offsets = "k" + core.substr(0, core.find('<')) + "Members";
    for (size_t i = 0; i < members->size(); ++i)
      if (use.read.count((*members)[i]))
        lines.push_back(guard + "Get(" + n + " + " + offsets + "[" + std::to_string(i) + "].offset, &" + local +
                        "." + (*members)[i] + ");");
    // None read: the function still takes the struct (and hands it on to a function the
    // compiler may not see into, which would then warn of an uninitialized read): a static
    // one, zero as static storage starts, stands for it at no cost per call.
    if (lines.size() == 1) lines = {"static const " + core + " " + local + "{};", "(void)" + n + ";"};
    return lines;
  };
  if (type == "const Params<double>&")
    // (The view's array itself where it lies as Params<double> does: ParamsArg, kParamsInPlace.)
    return {"const double*",
            {"const ParamsArg<kParamsInPlace> " + local + "arg(" + n + ");",
             "const Params<double>& " + local + " = " + local + "arg.p;"},
            {},
            local};
  if (type == "int") return {"int", {}, {}, n};
  if (type == "const double&") return {"double", {}, {}, n};
  // The struct `core` at its buffer n (view_buffers::At), and the check that it may be.
  auto in_place = [&struct_of, &n](const std::string& core, FlatArgument* flat, bool reference) {
    if (struct_of(core) == nullptr) return;
    const std::string name = core.substr(0, core.find('<'));
    flat->check = "InPlace<k" + name + "InPlace, " + core + ">(" + n + ")";
    flat->in_place_pass = (reference ? "*At<" : "At<") + core + ">(" + n + ")";
  };
  if (StartsWith(type, "const typename NonDeduced<") && EndsWith(type, ">::type*")) {  // an input, or nullptr
    const std::string core = type.substr(26, type.size() - 26 - 8);
    FlatArgument flat{array(core, true), struct_input(core, "if (" + n + " != nullptr) "), {},
                      n + " != nullptr ? &" + local + " : nullptr"};
    in_place(core, &flat, false);
    // An input vector (Forces' friction loads) on the caller's array itself where it is aligned
    // for the vector (nullptr stays nullptr): the statics' friction iteration writes it entry by
    // entry just before the call, and a copy that read it back as wider loads waited on those
    // stores (5 % of a slider-crank's statics row through the view, 2026-11-30).
    if (flat.check.empty() && StartsWith(core, "Vec<double, ")) {
      flat.check = "InPlace<true, " + core + ">(" + n + ")";
      flat.in_place_pass = "At<" + core + ">(" + n + ")";
    }
    return flat;
  }
  if (StartsWith(type, "const ") && EndsWith(type, "&")) {  // an input
    const std::string core = type.substr(6, type.size() - 7);
    FlatArgument flat{array(core, true), struct_input(core, ""), {}, local};
    in_place(core, &flat, true);
    return flat;
  }
  std::string core;  // an output (or input and output)
  if (StartsWith(type, "Out<") && EndsWith(type, ">"))
    core = type.substr(4, type.size() - 5);
  else if (EndsWith(type, "*") && !StartsWith(type, "const "))
    core = type.substr(0, type.size() - 1);
  else
    throw std::runtime_error("the model view cannot pass argument '" + n + "' of type " + a.type +
                             " (codegen/emit.cc: Flatten)");
  const std::string guard = "if (" + n + " != nullptr) ";
  const std::string pass = n + " != nullptr ? &" + local + " : nullptr";
  const std::vector<std::string>* members = struct_of(core);
  const StructUse use = members != nullptr ? UseOf(code, n) : StructUse::Whole();
  const std::string at_n = "At<" + core + ">(" + n + ")";
  if (use.whole || (written_whole && use.may_return)) {
    FlatArgument flat{array(core, false),
                      {core + " " + local + ";", guard + (written_whole ? "Zero(&" + local + ");" : "Get(" + n + ", &" + local + ");")},
                      {guard + "Put(" + local + ", " + n + ");"},
                      pass};
    in_place(core, &flat, false);
    if (written_whole && !flat.check.empty()) flat.in_place_before.push_back(guard + "Zero(" + at_n + ");");
    return flat;
  }
  FlatArgument flat{array(core, false), {core + " " + local + ";"}, {}, pass};
  in_place(core, &flat, false);
  const std::string offsets = "k" + core.substr(0, core.find('<')) + "Members";
  for (size_t i = 0; i < members->size(); ++i) {
    const std::string& member = (*members)[i];
    const std::string at = n + " + " + offsets + "[" + std::to_string(i) + "].offset";
    const auto stored = use.stored.find(member);
    if (written_whole) {  // every member 0 but those the body stores whole, and every one copied back
      const std::string zero =
          stored != use.stored.end() ? "ZeroUnlessStored<" + std::to_string(stored->second.size()) + ">(" : "Zero(";
      flat.before.push_back(guard + zero + "&" + local + "." + member + ");");
      flat.in_place_before.push_back(guard + zero + "&" + at_n + "->" + member + ");");
    } else if (use.read.count(member) || (stored != use.stored.end() && use.may_return)) {
      flat.before.push_back(guard + "Get(" + at + ", &" + local + "." + member + ");");
    } else if (stored != use.stored.end()) {
      flat.before.push_back(guard + "GetUnlessStored<" + std::to_string(stored->second.size()) + ">(" + at + ", &" +
                            local + "." + member + ");");
    } else {
      continue;  // not named by the body: its buffer keeps its value
    }
    flat.after.push_back(guard + "Put(" + local + "." + member + ", " + at + ");");
  }
  if (flat.after.empty()) flat.before.push_back("(void)" + n + ";");
  return flat;
}

// The model view's adapter of one Model function: Flat<member>(flat arrays), which calls
// Model::<member> on the fixed-size types.
mus::data ViewFunction(const FunctionSpec& f, const std::string& rendered,
                       const std::map<std::string, std::vector<std::string>>& structs) {
  const std::string code = StripComments(rendered);
  std::string returns;
  if (f.returns == "void")
    returns = "void";
  else if (f.returns == "SolveReport<" + f.scalar + ">")
    returns = "mechgen::ViewSolveReport";
  else
    throw std::runtime_error("the model view cannot return " + f.returns + " (" + f.name + ", codegen/emit.cc)");
  // copied_args: args but the unnamed `velocities` (Forces), Flat<member>Copied's signature.
  mus::data args{mus::data::type::list}, copied_args{mus::data::type::list};
  // The copies of the arguments that are not structs (common), of the structs (copied), and the
  // structs at their buffers where each may be (in place: checks).
  std::vector<std::string> common, before, after, pass, after_common;
  std::vector<std::string> checks, in_place_before, in_place_pass, in_place_after;
  bool has_velocities = false;
  for (size_t i = 0; i < f.args.size(); ++i) {
    const FlatArgument flat = Flatten(f.args[i], f.scalar, WrittenWhole(f.model_member, f.args[i]), code, structs);
    mus::data o{mus::data::type::object};
    o.set("arg_type", flat.type);
    o.set("arg_name", f.args[i].name);
    o.set("first", Bool(i == 0));
    args.push_back(o);
    copied_args.push_back(o);
    if (flat.check.empty()) {
      common.insert(common.end(), flat.before.begin(), flat.before.end());
      after_common.insert(after_common.end(), flat.after.begin(), flat.after.end());
      in_place_pass.push_back(flat.pass);
    } else {
      before.insert(before.end(), flat.before.begin(), flat.before.end());
      checks.push_back(flat.check);
      in_place_before.insert(in_place_before.end(), flat.in_place_before.begin(), flat.in_place_before.end());
      in_place_pass.push_back(flat.in_place_pass);
    }
    after.insert(after.end(), flat.after.begin(), flat.after.end());
    pass.push_back(flat.pass);
    has_velocities = has_velocities || f.args[i].name == "velocities";
  }
  // One signature for every model (ModelView::Forces): a model whose loads read no velocity
  // takes the statics' `velocities` and has nothing to read from it.
  if (f.model_member == "Forces" && !has_velocities) {
    mus::data o{mus::data::type::object};
    o.set("arg_type", std::string("const double*"));
    o.set("arg_name", std::string("/*velocities*/"));
    o.set("first", Bool(false));
    args.push_back(o);
  }
  // The call on one line, or one argument a line under the first where that is over 100 columns
  // (`indent`: the columns before the line).
  auto call = [&f](const std::string& head, const std::vector<std::string>& pass, size_t indent) {
    const std::string open = head + "Model::" + f.model_member + "(";
    std::string line = open;
    for (size_t i = 0; i < pass.size(); ++i) line += (i ? ", " : "") + pass[i];
    if (indent + line.size() + 2 <= 100) return line + ");";
    line = open;
    for (size_t i = 0; i < pass.size(); ++i) line += (i ? ",\n" + Spaces(indent + open.size()) : "") + pass[i];
    return line + ");";
  };
  auto call_and_after = [&](const std::vector<std::string>& pass, const std::vector<std::string>& after,
                            const std::string& indent, std::vector<std::string>* body) {
    const std::string head = returns == "void" ? "" : "const SolveReport<double> report = ";
    body->push_back(indent + call(head, pass, 2 + indent.size()));
    for (const std::string& l : after) body->push_back(indent + l);
    body->push_back(indent + (returns == "void" ? "return;" : "return Report(report);"));
  };
  // Every struct copied in and out (the body of Flat<member>, or of Flat<member>Copied where
  // the structs may also be passed in place).
  std::vector<std::string> copied = common;
  copied.insert(copied.end(), before.begin(), before.end());
  call_and_after(pass, after, "", &copied);
  if (returns == "void") copied.pop_back();  // (no `return;` at the end)
  std::vector<std::string> body;
  if (!checks.empty()) {
    // The structs on the caller's storage where they may be (no copy), else the copies in
    // Flat<member>Copied: out of line, so that the model's function has one call here, which
    // the compiler inlines (called from three places, it was not, and its SolveReport came
    // back through memory).
    std::string condition = "if (";
    for (size_t i = 0; i < checks.size(); ++i) {
      const std::string sep = i == 0 ? "" : " &&";
      if (2 + condition.size() + sep.size() + 1 + checks[i].size() + 3 > 100) {
        body.push_back(condition + sep);
        condition = "    " + checks[i];
      } else {
        condition += (i == 0 ? "" : sep + " ") + checks[i];
      }
    }
    body.push_back(condition + ") {");
    for (const std::string& l : common) body.push_back("  " + l);
    for (const std::string& l : in_place_before) body.push_back("  " + l);
    call_and_after(in_place_pass, after_common, "  ", &body);
    body.push_back("}");
    std::string forward = "Flat" + f.model_member + "Copied<>(";
    for (size_t i = 0; i < f.args.size(); ++i) forward += (i ? ", " : "") + f.args[i].name;
    body.push_back((returns == "void" ? "" : "return ") + forward + ");");
  } else {
    body = copied;
  }
  auto as_lines = [](const std::vector<std::string>& from) {
    mus::data out{mus::data::type::list};
    for (const std::string& l : from) {
      mus::data o{mus::data::type::object};
      o.set("line", l);
      out.push_back(o);
    }
    return out;
  };
  mus::data o{mus::data::type::object};
  o.set("member", f.model_member);
  o.set("returns", returns);
  o.set("indent", Spaces(returns.size() + 6 + f.model_member.size()));
  o.set("args", args);
  o.set("lines", as_lines(body));
  o.set("has_copied", Bool(!checks.empty()));
  if (!checks.empty()) {
    o.set("copied_args", copied_args);
    o.set("copied_indent", Spaces(returns.size() + 12 + f.model_member.size()));
    o.set("copied_lines", as_lines(copied));
  }
  return o;
}

// The names of a struct member description ("T, V, P_nc": three members).
std::vector<std::string> MemberNames(const std::string& names) {
  std::vector<std::string> out;
  std::istringstream in(names);
  for (std::string n; std::getline(in, n, ',');) {
    n.erase(0, n.find_first_not_of(' '));
    out.push_back(n);
  }
  return out;
}

}  // namespace

std::string RenderBody(const FunctionSpec& f, CxxPrinter* printer, OpCounts* ops) {
  Body total;
  for (const Program& p : f.body) {
    const Body b = EmitProgram(p, printer);
    total.text += b.text;
    total.ops += b.ops;
    total.num_temps += b.num_temps;
  }
  total.ops.calls += f.extra_calls;
  if (f.reindent) total.text = Reindent(total.text);
  const std::string code = StripComments(total.text);
  std::ostringstream os;
  if (f.count_ops)
    os << "  // Total ops: " << total.ops.Text() << "; intermediate terms: " << total.num_temps << "\n";
  // Unqualified calls, so that ceres::Jet's overloads are found; std:: for the others.
  for (const char* fn : {"abs", "acos", "asin", "atan", "atan2", "cos", "exp", "floor", "log", "pow", "sin", "sqrt", "tan"})
    if (std::regex_search(code, std::regex(std::string("(^|[^A-Za-z0-9_.:>])") + fn + "\\(")))
      os << "  using std::" << fn << ";\n";
  for (const Argument& a : f.args)
    if (!Mentions(code, a.name)) os << "  (void)" << a.name << ";\n";
  os << total.text;
  std::string s = os.str();
  while (!s.empty() && s.back() == '\n') s.pop_back();
  if (ops != nullptr) *ops = total.ops;
  return s;
}

EmittedModel Emit(const Model& m, const Topology& t, const Kinematics& k, const SymbolicTable& table,
                  const std::vector<TransmissionAngle>& transmission, const std::vector<FunctionSpec>& functions,
                  CxxPrinter* printer, const std::string& templates_dir) {
  EmittedModel out;
  std::vector<std::string> bodies;
  for (const FunctionSpec& f : functions) {
    OpCounts ops;
    bodies.push_back(RenderBody(f, printer, &ops));
    out.ops[f.name] = ops;
  }

  TemplateData data;
  std::string upper = m.name;
  for (char& c : upper) c = static_cast<char>(std::toupper(static_cast<unsigned char>(c)));
  data.Set("version", std::string(MECHGEN_VERSION));
  data.Set("model_file", CommentText(std::filesystem::path(m.file).filename().string()));
  data.Set("model_sha256", Sha256Hex(ReadFile(m.file, "model file")));  // the bytes mechgen read
  data.Set("name", m.name);
  data.Set("NAME", upper);
  data.Set("title", CommentText(m.title.empty() ? m.name : m.title));
  data.SetList("description", LineMaps(CommentText(m.description)), {"line"});
  data.Set("num_links", static_cast<int>(m.links.size()));
  data.Set("num_moving_links", static_cast<int>(m.links.size()) - 1);
  data.Set("num_joints", static_cast<int>(m.joints.size()));
  data.Set("num_loops", static_cast<int>(t.loops.size()));
  data.Set("mobility", t.loop_mobility);
  std::vector<std::map<std::string, std::string>> loops, qdoc, phidoc, rows, pdoc, params;
  for (size_t i = 0; i < t.loops.size(); ++i)
    loops.push_back({{"index", std::to_string(i + 1)}, {"text", t.loops[i].Text(m)}});
  data.SetList("loops", loops, {"index", "text"});
  for (int i = 0; i < k.nq(); ++i)
    qdoc.push_back({{"index", std::to_string(i)}, {"name", k.q[i].name}, {"what", k.q[i].what}});
  for (int i = 0; i < k.nphi(); ++i)
    phidoc.push_back({{"index", std::to_string(i)}, {"name", k.phi[i].name}, {"what", k.phi[i].what}});
  data.SetList("q_doc", qdoc, {"index", "name", "what"});
  data.SetList("phi_doc", phidoc, {"index", "name", "what"});
  for (int i = 0; i < k.nc(); ++i) {
    CxxPrinter plain;  // GiNaC's own term order varies between runs: print ours
    for (const CamLaw& law : k.cam_laws) plain.NameCamLaw(m.joints[law.joint].Data<CamData>().index, law.cxx_name);
    for (const CamContour& c : k.cam_contours) plain.NameCamContour(m.joints[c.joint].Data<CamData>().index, c.cxx_name);
    for (const auto& c : k.q) plain.Name(c.symbol, c.name);
    for (const auto& c : k.phi) plain.Name(c.symbol, c.name);
    for (const auto& p : m.params) plain.Name(p.symbol, p.name);
    std::string text = plain.Print(k.Phi[i]);
    text = std::regex_replace(text, std::regex(R"(Scalar\(([^()]*)\))"), "$1");
    rows.push_back({{"index", std::to_string(i)}, {"text", text + "   [" + k.Phi_source[i] + "]"}});
  }
  data.SetList("phi_rows", rows, {"index", "text"});
  data.Set("nq", k.nq());
  data.Set("nphi", k.nphi());
  data.Set("nc", k.nc());
  data.Set("order", m.outputs.order);
  static const char* kOrderText[] = {"positions", "positions, velocity coefficients K",
                                     "positions, velocity coefficients K, centripetal coefficients L"};
  data.Set("order_text", std::string(kOrderText[m.outputs.order]));
  for (const auto& n : k.point_names) pdoc.push_back({{"name", n}});
  data.SetList("points_doc", pdoc, {"name"});
  data.Set("solve_strategy", table.strategy);
  // Operation counts of the functions the Model exposes, in the header's order.
  std::string op_counts;
  for (const FunctionSpec& f : functions)
    if (!f.model_member.empty() && f.count_ops)
      op_counts += (op_counts.empty() ? "" : "; ") + f.name + " " + out.Ops(f.name).Text() +
                   (f.ops_note.empty() ? "" : " (" + f.ops_note + ")");
  data.Set("op_counts", op_counts);
  data.Set("numeric_solve", table.numeric_solve);
  data.Set("num_points", static_cast<int>(k.points.size()));
  data.Set("num_scene_points", static_cast<int>(k.scene.size()));
  for (const Parameter& p : m.params)
    params.push_back({{"name", p.name}, {"value", Number(p.value)}, {"comment", CommentText(p.doc)}});
  data.SetList("params", params, {"name", "value", "comment"});
  data.Set("num_params", static_cast<int>(m.params.size()));
  data.Set("param_names", Join(m.params, [](const Parameter& p) { return Quote(p.name); }));
  data.Set("num_derived_params", static_cast<int>(m.derived.size()));
  data.Set("derived_param_names", Join(m.derived, [](const DerivedParameter& d) { return Quote(d.name); }));
  // Coefficients' optional members: exactly where the model's flags say (ModelFlags).
  const ModelFlags model_flags = ModelFlagsOf(m, table, functions);
  data.Set("has_K", model_flags.K.value);
  data.Set("has_L", model_flags.L.value);
  data.Set("has_points", model_flags.points.value);
  data.Set("has_K_P", model_flags.point_velocities.value);
  data.Set("has_L_P", model_flags.point_accelerations.value);
  data.Set("num_transmission", static_cast<int>(transmission.size()));
  data.Set("transmission_joints", Join(transmission, [](const TransmissionAngle& a) { return Quote(a.joint); }));

  // ---- The generated functions, from their descriptions ----
  mus::data fns{mus::data::type::list}, members{mus::data::type::list}, instances{mus::data::type::list};
  for (size_t i = 0; i < functions.size(); ++i) {
    const FunctionSpec& f = functions[i];
    std::vector<std::string> doc = f.doc;
    if (!f.args.empty()) {
      const auto pd = ParamDoc(f);
      doc.insert(doc.end(), pd.begin(), pd.end());
    }
    doc.insert(doc.end(), f.notes.begin(), f.notes.end());
    mus::data o{mus::data::type::object};
    o.set("name", f.name);
    o.set("template_scalar", f.scalar);
    o.set("inline", Bool(f.inline_hint));
    o.set("returns", f.returns);
    o.set("indent", Spaces((f.inline_hint ? 7 : 0) + f.returns.size() + f.name.size() + 2));
    o.set("doc", Lines(doc));
    o.set("args", ArgList(f, "", true, false));
    o.set("body", bodies[i]);
    fns.push_back(o);
    if (!f.model_member.empty()) {
      mus::data mo{mus::data::type::object};
      std::string call;
      for (const Argument& a : f.args) call += (call.empty() ? "" : ", ") + a.name;
      mo.set("name", f.name);
      mo.set("template_scalar", f.scalar);
      mo.set("member_name", f.model_member);
      mo.set("returns", f.returns);
      mo.set("returns_value", Bool(f.returns != "void"));
      mo.set("indent", Spaces(2 + 7 + f.returns.size() + f.model_member.size() + 2));
      mo.set("args", ArgList(f, "", true, true));
      mo.set("call", call);
      members.push_back(mo);
    }
  }
  for (const char* scalar : {"double", "float"}) {
    mus::data inst{mus::data::type::object}, list{mus::data::type::list};
    inst.set("scalar", std::string(scalar));
    for (const FunctionSpec& f : functions) {
      if (!f.instantiate) continue;
      mus::data o{mus::data::type::object};
      const std::string returns = WithScalar(f.returns, f.scalar, scalar);
      const size_t head = returns.size() + f.name.size() + std::string(scalar).size() + 4;  // "R N<S>("
      o.set("name", f.name);
      o.set("returns", returns);
      o.set("extern_indent", Spaces(16 + head));
      o.set("instance_indent", Spaces(9 + head));
      o.set("args", ArgList(f, scalar, false, false));
      list.push_back(o);
    }
    inst.set("instantiated", list);
    instances.push_back(inst);
  }
  const std::set<std::string> fn_keys = {"name", "template_scalar", "inline", "returns", "indent", "doc", "line", "args", "arg_type", "arg_name",
                                         "has_default", "arg_default", "first", "body"};
  data.SetData("functions", fns, fn_keys);
  data.SetData("members", members, {"member_name", "returns_value", "call"});
  data.SetData("instances", instances, {"scalar", "instantiated", "extern_indent", "instance_indent"});

  // ---- The cams' documentation, the blocks, the Model's constants ----
  std::vector<std::map<std::string, std::string>> cam_doc;
  for (const std::string& s : k.cam_summary)
    for (const auto& l : LineMaps(s)) cam_doc.push_back(l);
  for (const CamContour& c : k.cam_contours)
    for (const auto& l : LineMaps(c.summary)) cam_doc.push_back(l);
  data.Set("has_cams", !k.cam_laws.empty());
  data.SetList("cam_doc", cam_doc, {"line"});
  std::vector<std::map<std::string, std::string>> blocks_doc;
  for (size_t i = 0; i < table.blocks.size(); ++i)
    blocks_doc.push_back({{"index", std::to_string(i)}, {"text", table.blocks[i].Describe(k)}});
  data.SetList("blocks_doc", blocks_doc, {"index", "text"});
  // Change points in the inputs' ranges (issue 26), only for a model that passes some: the
  // generator's note in the file comment (wrapped) and the points as constants.
  std::vector<std::map<std::string, std::string>> change_point_doc;
  for (const std::string& note : ChangePointNotes(k, table.blocks)) {
    std::string line = "Note:";
    std::istringstream words(CommentText(note));
    for (std::string w; words >> w;) {
      if (line.size() + 1 + w.size() > 92) {
        change_point_doc.push_back({{"line", line}});
        line = "  " + w;
      } else {
        line += " " + w;
      }
    }
    change_point_doc.push_back({{"line", line}});
  }
  data.SetList("change_point_doc", change_point_doc, {"line"});
  std::vector<int> cp_input, cp_block;
  std::vector<double> cp_q;
  for (size_t i = 0; i < table.blocks.size(); ++i)
    for (const ChangePoint& c : table.blocks[i].change_points) {
      cp_input.push_back(c.input);
      cp_block.push_back(static_cast<int>(i));
      cp_q.push_back(c.value);
    }
  data.Set("has_change_points", !cp_q.empty());
  data.Set("num_change_points", static_cast<int>(cp_q.size()));
  data.Set("change_point_inputs", Join(cp_input, [](int i) { return std::to_string(i); }));
  data.Set("change_point_blocks", Join(cp_block, [](int i) { return std::to_string(i); }));
  data.Set("change_point_q", Join(cp_q, [](double x) { return Number(x); }));
  data.Set("num_blocks", static_cast<int>(table.blocks.size()));
  data.Set("default_modes", Join(table.blocks, [](const Block& b) { return std::to_string(b.default_mode); }));
  // Named assembly modes (issue 13), only for a model that has `assembly_modes`.
  data.Set("has_named_modes", model_flags.named_modes.value);
  data.Set("num_named_modes", static_cast<int>(m.assembly_modes.size()));
  data.Set("mode_names", Join(m.assembly_modes, [](const NamedMode& n) { return Quote(n.name); }));
  std::vector<size_t> mode_index(m.assembly_modes.size());
  for (size_t i = 0; i < mode_index.size(); ++i) mode_index[i] = i;
  data.Set("named_modes", Join(mode_index, [&table](size_t i) {
             return "{ {" + Join(table.blocks, [i](const Block& b) { return std::to_string(b.named_modes[i]); }) + "} }";
           }));
  data.Set("block_closed_form", Join(table.blocks, [](const Block& b) {
             return std::string(b.solve == BlockSolve::kNewton ? "false" : "true");
           }));
  auto names = [](const std::vector<Coordinate>& v) { return Join(v, [](const Coordinate& c) { return Quote(c.name); }); };
  auto angles = [](const std::vector<Coordinate>& v) {
    return Join(v, [](const Coordinate& c) { return std::string(c.is_angle ? "true" : "false"); });
  };
  auto numbers = [](const std::vector<double>& v) { return Join(v, [](double x) { return Number(x); }); };
  data.Set("q_names", names(k.q));
  data.Set("phi_names", names(k.phi));
  data.Set("q_is_angle", angles(k.q));
  data.Set("phi_is_angle", angles(k.phi));
  data.Set("point_names", Join(k.point_names, Quote));
  data.Set("link_names", Join(m.links, [](const Link& l) { return Quote(l.name); }));
  data.Set("ground_index", m.ground);
  data.Set("scene_point_names", Join(k.scene_names, Quote));
  data.Set("scene_point_links", Join(k.scene_link, [](int l) { return std::to_string(l); }));
  std::string function_constants;
  for (const FunctionSpec& f : functions) function_constants += f.model_constants;
  data.Set("drawing_constants", DrawingConstants(m, k) + function_constants);
  data.Set("assembly_q", numbers(k.assembly_q));
  data.Set("assembly_phi", numbers(k.assembly_phi));
  data.Set("q_min", numbers(k.q_min));
  data.Set("q_max", numbers(k.q_max));

  // ---- Statics: the Statics struct and the reactions' and friction joints' names ----
  const StaticsLayout statics = StaticsLayout::Of(m);
  data.Set("statics_sizes",
           !statics.any ? std::string()
                        : "  static constexpr int kNumReactions = " + std::to_string(statics.reactions.size()) +
                              ";  ///< reaction components (kReactionNames)\n"
                              "  static constexpr int kNumFriction = " + std::to_string(statics.friction.size()) +
                              ";   ///< joints with Coulomb friction (kFrictionJoints)\n");
  // ---- Switch modes: kNumSwitches where the applied loads have switching items ----
  int num_switches = 0;
  for (const FunctionSpec& f : functions) num_switches += f.switches;
  data.Set("switch_sizes", num_switches == 0 ? std::string()
                                             : "  static constexpr int kNumSwitches = " + std::to_string(num_switches) +
                                                   ";  ///< switching items of the loads (EvalSwitchModes)\n");
  // ---- Design parameters: kNumDesign and their names where the model has a `design` section ----
  const std::string num_design = std::to_string(m.design.params.size());
  std::vector<std::string> design_checks;  // EvalDesignChecks' margins, by name
  for (const FunctionSpec& f : functions)
    design_checks.insert(design_checks.end(), f.design_checks.begin(), f.design_checks.end());
  data.Set("design_sizes", !m.design.any() ? std::string()
                                           : "  static constexpr int kNumDesign = " + num_design +
                                                 ";  ///< design parameters (kDesignNames)\n"
                                                 "  static constexpr int kNumDesignChecks = " +
                                                 std::to_string(design_checks.size()) +
                                                 ";  ///< design checks (kDesignCheckNames, EvalDesignChecks)\n");
  data.Set("design_constants",
           !m.design.any() ? std::string()
                           : "  /// The design parameters (`design`): EvalDesignDerivatives differentiates with respect to\n"
                             "  /// these Params members, in this order.\n"
                             "  static constexpr std::array<const char*, kNumDesign> kDesignNames{ " +
                                 Join(m.design.params, [&m](int i) { return Quote(m.params[i].name); }) + " };\n"
                                 "  /// The design checks' margins (EvalDesignChecks), in order.\n"
                                 "  static constexpr std::array<const char*, kNumDesignChecks> kDesignCheckNames{ " +
                                 Join(design_checks, Quote) + " };\n");
  // ---- The model's flags; the output structs, their flags and aliases, from their descriptions ----
  mus::data outputs{mus::data::type::list}, flags{mus::data::type::list}, aliases{mus::data::type::list};
  mus::data other_flags{mus::data::type::list};
  auto flag_to = [](mus::data* list, const OutputFlag& f) {
    mus::data o{mus::data::type::object};
    o.set("flag_name", f.name);
    o.set("flag_doc", f.doc);
    o.set("flag_value", std::string(f.value ? "true" : "false"));
    list->push_back(o);
  };
  auto flag = [&flags, &flag_to](const OutputFlag& f) { flag_to(&flags, f); };
  mus::data flags_all{mus::data::type::list};  // every flag in the header's order (the model view's)
  for (const OutputFlag* f : model_flags.All()) flag_to(&other_flags, *f), flag_to(&flags_all, *f);
  data.SetData("model_flags", other_flags, {"flag_name", "flag_doc", "flag_value"});
  for (const OutputSpec& spec : OutputSpecs(m, table, functions)) {
    flag(spec.flag);
    flag_to(&flags_all, spec.flag);
    for (const OutputFlag& f : spec.member_flags) flag(f), flag_to(&flags_all, f);
    if (!spec.present()) continue;
    mus::data o{mus::data::type::object}, members{mus::data::type::list};
    o.set("struct_name", spec.name);
    o.set("struct_doc", Lines(spec.doc));
    for (const OutputMember& mem : spec.members) {
      if (!mem.present) continue;
      const std::vector<std::string> doc = RenderedDoc(mem);
      std::string doc_lines;  // "  /// ..." lines (none where the member before documents it)
      for (const std::string& l : doc) doc_lines += "  ///" + (l.empty() ? std::string() : " " + l) + "\n";
      mus::data mo{mus::data::type::object};
      mo.set("member_doc", doc_lines);
      mo.set("member_type", mem.type);
      mo.set("member_names", mem.names);
      members.push_back(mo);
    }
    o.set("struct_members", members);
    outputs.push_back(o);
    mus::data a{mus::data::type::object};
    a.set("alias", spec.alias);
    a.set("struct_name", spec.name);
    aliases.push_back(a);
  }
  data.SetData("outputs", outputs,
               {"struct_name", "struct_doc", "struct_members", "member_doc", "member_type", "member_names", "line"});
  data.SetData("output_flags", flags, {"flag_name", "flag_doc", "flag_value"});
  data.SetData("output_aliases", aliases, {"alias", "struct_name"});
  std::string constants =
      "  /// Reaction components of EvalStatics (Statics::R), each the force (or moment) of the joint's first\n"
      "  /// link on its second, in the fixed frame:\n";
  for (const auto& c : statics.reactions) constants += "  ///   " + c.name + ": " + c.what + "\n";
  constants += "  static constexpr std::array<const char*, kNumReactions> kReactionNames{ " +
               Join(statics.reactions, [](const StaticsLayout::Component& c) { return Quote(c.name); }) + " };\n";
  constants += "  /// The joint of each reaction component (index into kJointNames).\n";
  constants += "  static constexpr std::array<int, kNumReactions> kReactionJoint{ " +
               Join(statics.reactions, [](const StaticsLayout::Component& c) { return std::to_string(c.joint); }) +
               " };\n";
  constants += "  static constexpr std::array<const char*, " + std::to_string(m.joints.size()) + "> kJointNames{ " +
               Join(m.joints, [](const Joint& j) { return Quote(j.name); }) + " };\n";
  constants += "  /// Joints with Coulomb friction, and whether each is prismatic (else revolute).\n";
  constants += "  static constexpr std::array<const char*, kNumFriction> kFrictionJoints{ " +
               Join(statics.friction, [&m](int j) { return Quote(m.joints[j].name); }) + " };\n";
  constants += "  static constexpr std::array<bool, kNumFriction> kFrictionPrismatic{ " +
               Join(statics.friction,
                    [&m](int j) { return std::string(m.joints[j].type() == JointType::kPrismatic ? "true" : "false"); }) +
               " };\n";
  constants += "  /// The loads, in the model's order.\n";
  constants += "  static constexpr std::array<const char*, " + std::to_string(m.loads.size()) + "> kLoadNames{ " +
               Join(m.loads, [](const Load& l) { return Quote(l.name); }) + " };\n";
  if (!statics.any) constants.clear();
  data.Set("statics_constants", constants);

  // ---- The model view (core/model_view.h): its structs, parameters and functions ----
  mus::data view_structs{mus::data::type::list}, view_functions{mus::data::type::list};
  std::map<std::string, std::vector<std::string>> struct_members;  // each struct's members, in its buffer's order
  for (const OutputSpec& spec : ViewStructSpecs(m, table, functions)) {
    if (!spec.present()) continue;
    mus::data o{mus::data::type::object}, members{mus::data::type::list};
    int index = 0;
    for (const OutputMember& mem : spec.members) {
      if (!mem.present) continue;
      for (const std::string& n : MemberNames(mem.names)) {
        mus::data mo{mus::data::type::object};
        mo.set("member_name", n);
        mo.set("index", std::to_string(index++));
        members.push_back(mo);
        struct_members[spec.name].push_back(n);
      }
    }
    o.set("struct_name", spec.name);
    o.set("num_members", std::to_string(index));
    o.set("struct_members", members);
    view_structs.push_back(o);
  }
  data.SetData("view_structs", view_structs, {"struct_name", "num_members", "struct_members", "member_name", "index"});
  for (size_t i = 0; i < functions.size(); ++i)
    if (!functions[i].model_member.empty() && functions[i].in_view)
      view_functions.push_back(ViewFunction(functions[i], bodies[i], struct_members));
  data.SetData("view_functions", view_functions,
               {"member", "returns", "indent", "args", "arg_type", "arg_name", "first", "lines", "line",
                "has_copied", "copied_args", "copied_indent", "copied_lines"});
  // ModelView::StaticsChecks (and ForcesChecked: Forces, then those checks): the statics' reads
  // of what Forces wrote, on the generated struct. Finite: the members statics::internal::
  // AllFinite reads (runtime/include/mechgen/statics/solve.h), each where the model's Statics
  // has it, in its order; the runtime's rule stated again here, and
  // tests/kinematics/model_view_test.cc checks on every shipped model that the two agree (a NaN
  // and an infinity in each entry in turn).
  bool has_forces = false;
  for (size_t i = 0; i < functions.size(); ++i)
    has_forces = has_forces || (functions[i].model_member == "Forces" && functions[i].in_view);
  const auto statics_struct = struct_members.find("Statics");
  auto statics_index = [&](const std::string& name) {
    if (statics_struct == struct_members.end()) return -1;
    const std::vector<std::string>& members = statics_struct->second;
    const auto it = std::find(members.begin(), members.end(), name);
    return it != members.end() ? static_cast<int>(it - members.begin()) : -1;
  };
  const bool potential = statics_index("V") >= 0 && statics_index("dV_dq") >= 0;
  std::vector<std::string> checked_names;
  for (const char* name : {"Q", "drive", "V", "dV_dq", "R", "normal"}) {
    const bool potential_member = std::string(name) == "V" || std::string(name) == "dV_dq";
    if (statics_index(name) >= 0 && (potential || !potential_member)) checked_names.push_back(name);
  }
  mus::data forces_checked{mus::data::type::list};
  for (size_t i = 0; i < checked_names.size(); ++i) {
    mus::data o{mus::data::type::object};
    o.set("member_name", checked_names[i]);
    o.set("index", std::to_string(statics_index(checked_names[i])));
    o.set("first", Bool(i == 0));
    o.set("last", Bool(i + 1 == checked_names.size()));
    forces_checked.push_back(o);
  }
  data.SetData("forces_checked", forces_checked, {"member_name", "index", "first", "last"});
  has_forces = has_forces && !checked_names.empty();
  data.Set("has_forces_checked", has_forces);
  data.Set("forces_checked_names", Join(checked_names, [](const std::string& n) { return n; }));
  data.Set("has_reaction_norm", has_forces && statics_index("R") >= 0 && !statics.reactions.empty());
  data.Set("reaction_index", statics_index("R"));
  std::vector<std::map<std::string, std::string>> view_params, view_derived;
  CxxPrinter flat;  // the parameters as the view's flat array p[i]
  for (size_t i = 0; i < m.params.size(); ++i) {
    view_params.push_back({{"name", m.params[i].name}, {"index", std::to_string(i)}});
    flat.Name(m.params[i].symbol, "p[" + std::to_string(i) + "]");
  }
  FunctionSpec fill;
  fill.args = {Arg("double*", "p", Argument::Direction::kInOut, "")};
  fill.count_ops = false;
  fill.body.emplace_back();
  for (size_t i = 0; i < m.derived.size(); ++i) {
    const DerivedParameter& d = m.derived[i];
    view_derived.push_back(
        {{"name", d.name},
         {"value", Number(ValueAtDefaults(m, d.value, d.mark, "derived parameter '" + d.name + "'"))}});
    fill.body[0].push_back(Store("p[" + std::to_string(m.params.size() + i) + "]", d.value));
  }
  data.SetList("view_params", view_params, {"name", "index"});
  data.SetList("view_derived", view_derived, {"name", "value"});
  data.Set("num_view_params", static_cast<int>(m.params.size() + m.derived.size()));
  data.Set("num_free_params", static_cast<int>(m.params.size()));
  const std::string fill_body = RenderBody(fill, &flat, nullptr);
  data.Set("fill_derived_body", (Mentions(StripComments(fill_body), "Scalar")
                                     ? "  using Scalar = double;  // the printer's literals: Scalar(2)\n"
                                     : "") +
                                    fill_body);
  data.Set("num_joints", static_cast<int>(m.joints.size()));
  data.Set("view_joint_names", Join(m.joints, [](const Joint& j) { return Quote(j.name); }));
  data.Set("num_loads", static_cast<int>(m.loads.size()));
  data.Set("view_load_names", Join(m.loads, [](const Load& l) { return Quote(l.name); }));
  // Model::kStaticsAtSpeed: the statics' Forces takes `velocities` (codegen/statics_functions.cc).
  bool statics_at_speed = false;
  for (const FunctionSpec& f : functions)
    if (f.model_member == "Forces")
      for (const Argument& a : f.args) statics_at_speed = statics_at_speed || a.name == "velocities";
  data.Set("has_statics_at_speed", statics_at_speed);
  data.Set("has_statics", statics.any);
  data.Set("has_switches", num_switches > 0);
  data.Set("has_design", m.design.any());
  data.Set("has_drawing", !DrawingConstants(m, k).empty());
  data.Set("has_applied_loads", model_flags.applied_loads.value);
  data.SetData("view_flags", flags_all, {"flag_name"});

  out.header = data.Render(templates_dir + "/mechanism.h.mustache");
  out.source = data.Render(templates_dir + "/mechanism.cc.mustache");
  out.view = data.Render(templates_dir + "/mechanism_view.cc.mustache");
  return out;
}

bool WriteFiles(const std::string& dir, const std::string& name, const EmittedModel& e,
                std::string* error) {
  namespace fs = std::filesystem;
  std::error_code ec;
  fs::create_directories(dir, ec);
  if (ec) {
    *error = "cannot create directory " + dir + ": " + ec.message();
    return false;
  }
  const std::pair<std::string, const std::string*> files[] = {
      {name + ".h", &e.header}, {name + ".cc", &e.source}, {name + "_view.cc", &e.view}};
  // Files that already hold these bytes are left alone (their time stamps too): the build's
  // restat then skips recompiling every model when only mechgen itself changed.
  bool unchanged = true;
  for (const auto& [file, text] : files) {
    std::ifstream in(fs::path(dir) / file, std::ios::binary);
    std::ostringstream old;
    old << in.rdbuf();
    unchanged = unchanged && in && old.str() == *text;
  }
  if (unchanged) return true;
  std::vector<fs::path> temps;
  for (const auto& [file, text] : files) {
    const fs::path tmp = fs::path(dir) / (file + ".tmp");
    std::ofstream os(tmp, std::ios::binary);
    os << *text;
    os.close();
    if (!os) {
      *error = "cannot write " + tmp.string();
      for (const auto& t : temps) fs::remove(t, ec);
      fs::remove(tmp, ec);
      return false;
    }
    temps.push_back(tmp);
  }
  for (size_t i = 0; i < temps.size(); ++i) {
    fs::rename(temps[i], fs::path(dir) / files[i].first, ec);
    if (ec) {
      *error = "cannot rename " + temps[i].string() + ": " + ec.message();
      return false;
    }
  }
  return true;
}

}  // namespace mechgen
