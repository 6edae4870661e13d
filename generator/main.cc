// mechgen: planar-mechanism code generator (model file -> symbolic derivation -> C++).
//
//   mechgen generate models/fourbar.yaml --out-dir generated
//   mechgen generate models/fourbar.yaml --print-quantities   (K L scene: what the model has)
//   mechgen report models/fourbar.yaml [--latex [--standalone]]
//   mechgen sweep models/fourbar.yaml --steps 360 --csv out.csv   (generator/driver/)
//   mechgen statics|simulate|engine MODEL [options]                (the same, each tool)
//
// A bad model prints `file:line:column: error: message`, exits 1 and writes nothing.
#include <CLI/CLI.hpp>

#include <algorithm>
#include <cctype>
#include <chrono>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <sstream>
#include <memory>

#include <yaml-cpp/yaml.h>

#include "analysis/grashof.h"
#include "analysis/kinematics.h"
#include "analysis/topology.h"
#include "analysis/validate.h"
#include "codegen/emit.h"
#include "symbolic/dynamics.h"
#include "symbolic/statics.h"
#include "codegen/functions.h"
#include "driver/tool_command.h"
#include "model/model.h"
#include "model/reader.h"
#include "report/report.h"
#include "symbolic/table.h"
#include "symbolic/transmission.h"

#ifndef MECHGEN_SOURCE_TEMPLATES
#define MECHGEN_SOURCE_TEMPLATES ""
#endif

namespace {

// Installed layout: <prefix>/bin/mechgen and <prefix>/share/mechgen/templates.
std::string DefaultTemplates() {
  namespace fs = std::filesystem;
  std::error_code ec;
  const fs::path exe = fs::canonical("/proc/self/exe", ec);
  if (!ec) {
    const fs::path installed = exe.parent_path().parent_path() / "share" / "mechgen" / "templates";
    if (fs::exists(installed / "mechanism.h.mustache")) return installed.string();
  }
  return MECHGEN_SOURCE_TEMPLATES;
}

// A message as one line of text: control characters and bytes that are not UTF-8 are
// shown as \xNN (a name from the model is echoed as written, never re-encoded).
std::string OneLine(const std::string& text) {
  std::string out;
  for (size_t i = 0; i < text.size(); ++i) {
    const unsigned char c = static_cast<unsigned char>(text[i]);
    int n = c < 0x80 ? 0 : c >= 0xc2 && c <= 0xdf ? 1 : c >= 0xe0 && c <= 0xef ? 2 : c >= 0xf0 && c <= 0xf4 ? 3 : -1;
    for (int k = 1; k <= n; ++k)
      if (i + k >= text.size() || (static_cast<unsigned char>(text[i + k]) & 0xc0) != 0x80) n = -1;
    if (n > 0) {
      out.append(text, i, n + 1);
      i += n;
    } else if (n < 0 || c < 0x20 || c == 0x7f) {
      char buf[8];
      std::snprintf(buf, sizeof buf, "\\x%02x", c);
      out += buf;
    } else {
      out += static_cast<char>(c);
    }
  }
  return out;
}

// Model -> topology -> kinematics -> the symbolic table -> function descriptions -> text.
struct Pipeline {
  mechgen::Model model;
  mechgen::Topology topology;
  std::vector<mechgen::FourBarLoop> four_bars;
  mechgen::Kinematics kinematics;
  std::unique_ptr<mechgen::SymbolicTable> table;
  std::unique_ptr<mechgen::StaticsTable> statics;
  std::unique_ptr<mechgen::DynamicsTable> dynamics;
  std::unique_ptr<mechgen::DesignTable> design;
  std::vector<mechgen::TransmissionAngle> transmission;
  mechgen::CxxPrinter printer;
  std::vector<mechgen::FunctionSpec> functions;
  mechgen::EmittedModel emitted;
};

void Run(Pipeline* p, const std::string& path, const std::string& name, const std::string& templates,
         mechgen::Strategy strategy) {
  p->model = mechgen::LoadModel(path, name);
  mechgen::Analysis analysis = mechgen::Validate(p->model);
  p->topology = analysis.topology;
  p->four_bars = analysis.four_bars;
  p->kinematics = mechgen::DeriveKinematics(p->model, p->topology, &analysis.coordinates, &analysis.cams);
  p->table = std::make_unique<mechgen::SymbolicTable>(p->model, p->kinematics, strategy);
  p->transmission = mechgen::FindTransmissionAngles(p->model, p->topology, p->kinematics, p->table->blocks);
  p->statics = std::make_unique<mechgen::StaticsTable>(p->model, p->kinematics, *p->table);
  p->dynamics = std::make_unique<mechgen::DynamicsTable>(p->model, p->kinematics, *p->table);
  p->design = std::make_unique<mechgen::DesignTable>(p->model, *p->table, &p->topology, &p->four_bars,
                                                     &p->transmission);
  p->functions = mechgen::BuildFunctions(p->model, p->kinematics, *p->table, p->transmission, &p->printer,
                                         p->statics.get(), p->dynamics.get(), p->design.get());
  p->emitted = mechgen::Emit(p->model, p->topology, p->kinematics, *p->table, p->transmission, p->functions,
                             &p->printer, templates);
}

// The build's manifest of a model (--manifest): its resolved quantities as C macros, from
// which mechgen_add_model() compiles each tool of the model as the tool itself or as a stub
// that says what the model lacks (cmake/MechgenAddModel.cmake). Written only when its bytes
// change, so that the tools are not rebuilt for nothing.
bool WriteManifest(const std::string& path, const mechgen::Model& m, std::string* error) {
  using mechgen::Quantity;
  std::string text = "// " + m.name + ": what mechgen generated for it (mechgen generate --manifest), for the tools\n"
                     "// that mechgen_add_model() compiles as the tool or as a stub (cmake/MechgenAddModel.cmake).\n"
                     "#pragma once\n"
                     "#define MECHGEN_MODEL_NAME \"" + m.name + "\"\n"
                     "#define MECHGEN_MODEL_QUANTITIES \"" + mechgen::QuantityList(m.outputs.quantities) + "\"\n";
  for (Quantity q : {Quantity::kK, Quantity::kL, Quantity::kScene, Quantity::kForces, Quantity::kPotential,
                     Quantity::kDynamics, Quantity::kShaking}) {
    std::string macro = mechgen::QuantityName(q);
    for (char& c : macro) c = static_cast<char>(std::toupper(static_cast<unsigned char>(c)));
    text += "#define MECHGEN_MODEL_HAS_" + macro + " " + (m.outputs.Has(q) ? "1" : "0") + "\n";
  }
  std::ifstream in(path, std::ios::binary);
  std::ostringstream old;
  old << in.rdbuf();
  if (in && old.str() == text) return true;
  const std::string tmp = path + ".tmp";
  {
    std::ofstream out(tmp, std::ios::binary | std::ios::trunc);
    out << text;
    out.close();
    if (!out) return *error = "cannot write " + tmp, false;
  }
  std::error_code ec;
  std::filesystem::rename(tmp, path, ec);
  if (ec) return *error = "cannot write " + path + ": " + ec.message(), false;
  return true;
}

// `mechgen study STUDY.yaml` and `mechgen synthesize TASK.yaml`: a study or task file (a YAML
// mapping with its key) names its model (`model:`, relative to the file); the analysis then
// runs on that model with `--study FILE` or `--task FILE` before its other options.
struct FileThatNamesItsModel {
  const char* tool;  ///< the subcommand
  const char* key;   ///< the key that tells the file from a model
  const char* flag;  ///< the driver's option that takes the file
  const char* what;  ///< the file's kind, in messages
  int bad_file;      ///< the exit status of the tool for an error in such a file (docs/studies.md, synthesis.md)
};
constexpr FileThatNamesItsModel kFilesThatNameTheirModel[] = {{"study", "method", "--study", "study", 2},
                                                              {"synthesize", "synthesis", "--task", "task", 1}};

// Turns `<tool> FILE [options]` into `<tool> MODEL <flag> FILE [options]` where FILE is such a
// file. Returns 0 (done, or nothing to do: a model, or a file the generator reads and judges
// as one) or an exit status after one line on stderr: the tool's status for a bad file when
// it names no model (its line and column), 2 for the flag given as well.
int ResolveFileThatNamesItsModel(mechgen::ToolCommand* c) {
  for (const FileThatNamesItsModel& form : kFilesThatNameTheirModel) {
    if (c->tool != form.tool) continue;
    YAML::Node root;
    try {
      root = YAML::LoadFile(c->model_path);
    } catch (const YAML::Exception&) {
      return 0;  // not YAML: the generator says why, as for any model
    }
    if (!root.IsMap() || !root[form.key]) return 0;
    const std::string file = c->model_path;
    const std::string usage = std::string("mechgen ") + form.tool + " MODEL " + form.flag + " " + file;
    if (std::find(c->driver_args.begin(), c->driver_args.end(), form.flag) != c->driver_args.end()) {
      std::cerr << "mechgen " << form.tool << ": error: " << file << " is a " << form.what
                << " file that names its model; give either `mechgen " << form.tool << " " << file << "` or `"
                << usage << "`\n";
      return 2;
    }
    const YAML::Node model = root["model"];
    if (!model || !model.IsScalar() || model.Scalar().empty()) {
      const YAML::Mark mark = model ? model.Mark() : root.Mark();
      std::cerr << file << ":" << mark.line + 1 << ":" << mark.column + 1 << ": error: a " << form.what
                << " run as `mechgen " << form.tool << " " << file
                << "` names its model (model: fourbar.yaml, relative to the " << form.what << " file); add it or run `"
                << usage << "`\n";
      return form.bad_file;
    }
    std::filesystem::path path(model.Scalar());
    if (path.is_relative()) path = std::filesystem::path(file).parent_path() / path;
    c->model_path = path.lexically_normal().string();
    c->driver_args.insert(c->driver_args.begin(), {form.flag, file});
  }
  return 0;
}

}  // namespace

int main(int argc, char** argv) {
  // `mechgen <tool> [options] <model> [driver options...]`: what follows the model is the
  // driver's, passed on unchanged; CLI11 sees only mechgen's part.
  const std::vector<std::string> tool_options_with_value = {"--templates", "--cache-dir"};
  const std::vector<std::string>& tool_names = mechgen::ToolNames();
  std::vector<std::string> driver_args;
  if (argc > 1 && std::find(tool_names.begin(), tool_names.end(), std::string(argv[1])) != tool_names.end()) {
    int model_end = argc;
    mechgen::SplitToolArguments(argc, argv, 2, tool_options_with_value, &model_end, &driver_args);
    argc = model_end;
  }
  CLI::App app{"mechgen: derives the equations of a planar mechanism described in a model file "
               "(models/README.md) symbolically, after Paul's Kinematics and Dynamics of Planar "
               "Machinery, and writes standalone C++ for it: positions, velocity and centripetal "
               "coefficients (Phi, Phi_phi, K, L), points, statics (driving forces, reactions, "
               "friction), dynamics (generalized inertia, equations of motion, bearing loads) and "
               "shaking, and their derivatives with respect to design parameters, as the model's outputs "
               "and design section ask. `generate` writes the code; `sweep`, `statics`, `simulate`, "
               "`engine` and `flywheel` compile (once, cached) and run the analysis of a model "
               "directly, `synthesize` fits its dimensions to a task and `study` runs a design study "
               "(parameter sweeps, tolerances) on it."};
  app.require_subcommand(1);
  std::string model_path, out_dir = ".", name, templates = DefaultTemplates();
  bool latex = false, standalone = false, quiet = false, print_quantities = false;
  std::string manifest;
  std::string strategy = "blocks";

  CLI::App* gen =
      app.add_subcommand("generate", "write <name>.h, <name>.cc and <name>_view.cc (its model view) for a model");
  gen->add_option("model", model_path, "model file (.yaml)")->required();
  gen->add_option("-o,--out-dir", out_dir, "output directory")->capture_default_str();
  gen->add_option("--name", name, "override the model's name (the C++ namespace mech::<name>)");
  gen->add_option("--templates", templates, "directory of the .mustache templates")->capture_default_str();
  gen->add_flag("-q,--quiet", quiet, "print nothing on success");
  gen->add_option("--strategy", strategy,
                  "blocks: block-triangular solve order with closed-form dyads; monolithic: one "
                  "Newton solve and one dense LU over all loops (for comparison)")
      ->check(CLI::IsMember({"blocks", "monolithic"}))
      ->capture_default_str();
  CLI::Option* print_flag = gen->add_flag(
      "--print-quantities", print_quantities,
      "print the model's quantities as the generator resolves them (with what they imply: dynamics brings K, "
      "L, forces and potential, shaking brings dynamics), on one line separated by blanks, e.g. `K L scene "
      "forces`, and write nothing; the build's tools follow from it (cmake/MechgenAddModel.cmake)");
  gen->add_option("--manifest", manifest,
                  "also write this file: the quantities as a C header (MECHGEN_MODEL_HAS_FORCES 0|1, ...) "
                  "from which mechgen_add_model() builds each tool of the model or a stub")
      ->excludes(print_flag);

  CLI::App* rep = app.add_subcommand(
      "report", "print loops, mobility, Phi, Phi_phi, Phi_q, K and L block by block, the points' K_P and L_P");
  rep->add_option("model", model_path, "model file (.yaml)")->required();
  CLI::Option* latex_flag = rep->add_flag("--latex", latex, "LaTeX instead of plain text (a fragment: needs amsmath)");
  rep->add_flag("--standalone", standalone,
                "with --latex: a complete document (article, amsmath, geometry) for pdflatex")
      ->needs(latex_flag);
  rep->add_option("--templates", templates, "directory of the .mustache templates")->capture_default_str();

  // One subcommand per analysis (generator/driver/tool_command.h); each takes its driver's
  // options after the model (those of the <model>_<tool> that mechgen_add_model() builds, for
  // the tools it builds).
  mechgen::ToolCommand tool_command;
  std::vector<CLI::App*> tool_apps;
  for (const std::string& tool : tool_names) {
    CLI::App* sub = app.add_subcommand(
        tool, "generate, compile (once: cached) and run the " + tool + " command of a model: " +
                  mechgen::ToolSummary(tool) + ". The options after MODEL are the analysis's own (`mechgen " +
                  tool + " MODEL --help` lists them" +
                  (tool == "synthesize" || tool == "study"
                       ? std::string("")
                       : "; the same as the <model>_" + tool + " that mechgen_add_model() builds") +
                  "); mechgen's own options come before MODEL.");
    std::string model_help = "model file (.yaml)";
    for (const FileThatNamesItsModel& form : kFilesThatNameTheirModel)
      if (tool == form.tool)
        model_help += std::string(", or a ") + form.what + " file that names its model (`model:`, relative to it)";
    sub->add_option("model", tool_command.model_path, model_help)->required();
    sub->add_option("--templates", templates, "directory of the .mustache templates")->capture_default_str();
    sub->add_option("--cache-dir", tool_command.cache_dir,
                    "the cache (default: $MECHGEN_CACHE_DIR, else $XDG_CACHE_HOME/mechgen, else "
                    "~/.cache/mechgen)");
    sub->add_flag("--no-cache", tool_command.no_cache,
                  "build in a temporary directory and delete it afterwards; the cache is not used");
    sub->add_flag("--rebuild", tool_command.rebuild, "compile again and replace the cached program");
    sub->add_flag("-v,--verbose", tool_command.verbose,
                  "print the cache's place, the compiler commands and the times on stderr");
    tool_apps.push_back(sub);
  }

  CLI11_PARSE(app, argc, argv);

  for (CLI::App* sub : tool_apps) {
    if (!sub->parsed()) continue;
    tool_command.tool = sub->get_name();
    tool_command.templates = templates;
    tool_command.driver_args = driver_args;
    if (const int status = ResolveFileThatNamesItsModel(&tool_command); status != 0) return status;
    const std::string tool_templates = templates;
    return mechgen::RunTool(tool_command, [&tool_templates](const std::string& path, const std::string& dir,
                                                            mechgen::GeneratedModel* model) {
      Pipeline p;
      try {
        Run(&p, path, "", tool_templates, mechgen::Strategy::kBlocks);
      } catch (const mechgen::ModelError& e) {
        std::cerr << OneLine(e.what()) << "\n";
        return 1;
      } catch (const std::exception& e) {
        std::cerr << OneLine(path + ": error: " + e.what()) << "\n";
        return 2;
      }
      std::string error;
      if (!mechgen::WriteFiles(dir, p.model.name, p.emitted, &error)) {
        std::cerr << OneLine(path + ": error: " + error) << "\n";
        return 2;
      }
      model->name = p.model.name;
      std::istringstream words(mechgen::QuantityList(p.model.outputs.quantities));
      for (std::string q; words >> q;) model->quantities.push_back(q);
      return 0;
    });
  }

  // --name becomes a namespace, a file name in --out-dir and a macro: a C++ identifier only.
  if (!name.empty()) {
    const std::string why = mechgen::NameProblem(name, mechgen::NameRole::kModel);
    if (!why.empty()) {
      std::cerr << OneLine("mechgen: error: --name '" + name + "' " + why +
                           "; give a C++ identifier (see Names in models/README.md)")
                << "\n";
      return 1;
    }
  }

  // --print-quantities: the model reader alone (it applies what each quantity implies).
  if (gen->parsed() && print_quantities) {
    try {
      const mechgen::Model m = mechgen::LoadModel(model_path, name);
      std::cout << mechgen::QuantityList(m.outputs.quantities) << "\n";
    } catch (const mechgen::ModelError& e) {
      std::cerr << OneLine(e.what()) << "\n";
      return 1;
    } catch (const std::exception& e) {
      std::cerr << OneLine(model_path + ": error: " + e.what()) << "\n";
      return 2;
    }
    std::cout.flush();
    return std::cout ? 0 : 2;
  }

  Pipeline p;
  const auto start = std::chrono::steady_clock::now();
  try {
    Run(&p, model_path, name, templates,
        strategy == "monolithic" ? mechgen::Strategy::kMonolithic : mechgen::Strategy::kBlocks);
  } catch (const mechgen::ModelError& e) {
    std::cerr << OneLine(e.what()) << "\n";
    return 1;
  } catch (const std::exception& e) {  // not located: a derivation step the checks did not foresee
    std::cerr << OneLine(model_path + ": error: " + e.what()) << "\n";
    return 2;
  }
  const double ms =
      std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count();

  if (gen->parsed()) {
    std::string error;
    if (!mechgen::WriteFiles(out_dir, p.model.name, p.emitted, &error) ||
        (!manifest.empty() && !WriteManifest(manifest, p.model, &error))) {
      std::cerr << model_path << ": error: " << error << "\n";
      return 2;
    }
    if (!quiet)
      std::cout << "mechgen: " << model_path << " -> " << out_dir << "/" << p.model.name << ".{h,cc}, " << p.model.name
                << "_view.cc (" << p.topology.loops.size() << " loop(s), mobility " << p.topology.loop_mobility
                << ", EvalCoefficients " << p.emitted.Ops("EvalCoefficients").Total() << " ops) in "
                << static_cast<int>(ms + 0.5) << " ms\n";
    if (!quiet)
      for (const std::string& note : mechgen::ChangePointNotes(p.kinematics, p.table->blocks))
        std::cout << "mechgen: " << model_path << ": note: " << note << "\n";
    if (!quiet && p.model.outputs.Has(mechgen::Quantity::kForces))
      for (const auto& [load, reads] : p.model.at_rest_loads)
        std::cout << "mechgen: " << model_path << ": note: the statics (EvalStatics) evaluates the " << load << " at rest (" << reads
                  << (reads.find(',') == std::string::npos ? " = 0" : " all 0")
                  << "): its value in a slow motion; the dynamics reads it as written\n";
    return 0;
  }
  mechgen::WriteReport(p.model, p.topology, p.four_bars, p.kinematics, *p.table, p.transmission, p.emitted,
                       !latex        ? mechgen::ReportFormat::kText
                       : standalone  ? mechgen::ReportFormat::kLatexDocument
                                     : mechgen::ReportFormat::kLatex,
                       std::cout);
  // The time on stderr: the report itself is the same bytes on every run.
  std::cerr << "mechgen: derivation and emission took " << static_cast<int>(ms + 0.5) << " ms\n";
  return 0;
}
